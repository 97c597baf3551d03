// A solve that fails after its step halvings (the accurate tissue, the suture alone, the
// coupled needle pass) stops with exit code 3 and one error line that names the step and
// the last converged state; summary.json says "failed" with the message, and every output
// ends at that state: the last .pvd entry and the last forces.csv row are at the time the
// message names, never at the failed step's. Each run is made to fail by allowing Newton
// too few iterations for the step (the nonlinear problem cannot converge in them).
#include "run_scene.h"
#include "vtu_reader.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

using namespace suturesim::test_support;

namespace
{
  /// The (timestep, file) of the last DataSet of a .pvd collection.
  std::pair<double, std::string>
  last_pvd_entry(const std::string &pvd)
  {
    std::ifstream     in(pvd);
    std::stringstream s;
    s << in.rdbuf();
    const std::string text = s.str();
    const std::regex  entry(R"re(<DataSet timestep="([^"]*)"[^>]*file="([^"]*)")re");
    std::pair<double, std::string> last{-1.0, ""};
    for (auto it = std::sregex_iterator(text.begin(), text.end(), entry); it != std::sregex_iterator(); ++it)
      last = {std::stod((*it)[1].str()), (*it)[2].str()};
    return last;
  }

  /// What every failed run shows: exit 3, one error line, summary.json "failed".
  void
  expect_failed(const RunResult &r)
  {
    EXPECT_EQ(r.exit_code, 3) << r.output;
    EXPECT_EQ(lines_starting(r.output, "error: "), 1u) << r.output;
    ASSERT_TRUE(r.has_summary) << r.output;
    EXPECT_EQ(r.summary["status"], "failed");
    ASSERT_TRUE(r.summary.contains("error"));
    EXPECT_NE(r.summary["error"].get<std::string>().find("failed"), std::string::npos);
  }

  /// The .pvd @p series, its last file and forces.csv end at @p converged_time.
  void
  expect_outputs_end_at(const RunResult &r, const double converged_time, const std::string &series)
  {
    const auto [time, file] = last_pvd_entry(r.directory + "/" + series);
    EXPECT_NEAR(time, converged_time, 1e-12) << series;
    const Vtu last = read_vtu(r.directory + "/" + file);
    EXPECT_NEAR(last.get("FieldData", "TIME").values.at(0), converged_time, 1e-7) << file;

    const auto rows = read_forces(r);
    ASSERT_FALSE(rows.empty());
    EXPECT_NEAR(rows.back().at(0), converged_time, 1e-12) << "forces.csv goes past the converged state";
  }
} // namespace

TEST(SolverFailure, TissueNewtonThatCannotConvergeKeepsTheInitialState)
{
  // Cook's membrane (2 × 2 Q1) in two load steps; one Newton iteration cannot solve the
  // first, nor its half after the one halving allowed.
  const auto r = run_suturesim("fail_tissue", {source_path("tests/data/cook_coarse.prm"), "--set",
                                               "Tissue/Newton/Max iterations=1", "--set", "Time/Max cutbacks=1"});
  EXPECT_NE(r.output.find("error: Newton failed at step 1 (t = 0.25 s) after 1 step halvings"), std::string::npos)
    << r.output;
  expect_failed(r);
  expect_outputs_end_at(r, 0.0, "tissue.pvd");
}

TEST(SolverFailure, SutureNewtonThatCannotConvergeKeepsTheInitialState)
{
  const auto r = run_suturesim("fail_suture", {benchmark_scene("rod_cantilever"), "--set",
                                               "Suture/Newton/Max iterations=1", "--set", "Time/Max cutbacks=1"});
  EXPECT_NE(r.output.find("error: suture load step from t = 0.000000 s to 0.100000 s failed after 1 step halvings"),
            std::string::npos)
    << r.output;
  expect_failed(r);
  expect_outputs_end_at(r, 0.0, "suture.pvd");
}

namespace
{
  /// The accurate needle pass: two tissue Newton iterations solve the approach, not the
  /// first step with a pierce point on the needle (its first halving also fails).
  std::vector<std::string>
  failing_needle_pass()
  {
    return {source_path("parameters/needle_pass.prm"), "--set", "Model=accurate", "--set", "Time/Step size=0.04",
            "--set", "Time/End time=1.5", "--set", "Tissue/Newton/Max iterations=2", "--set",
            "Time/Max cutbacks=1"};
  }
} // namespace

TEST(SolverFailure, CoupledNeedlePassThatCannotConvergeKeepsItsLastAcceptedStep)
{
  const auto r = run_suturesim("fail_needle", failing_needle_pass());
  std::smatch       m;
  const std::regex  last(R"(last converged state t = ([0-9.eE+-]+) s)");
  ASSERT_TRUE(std::regex_search(r.output, m, last)) << r.output;
  const double converged = std::stod(m[1].str());
  EXPECT_GT(converged, 0.0) << "the pass failed before any step was accepted";
  EXPECT_NE(r.output.find("coupled Newton: no convergence in 2 iterations"), std::string::npos) << r.output;
  expect_failed(r);
  expect_outputs_end_at(r, converged, "tissue.pvd");
  expect_outputs_end_at(r, converged, "suture.pvd");
  EXPECT_NEAR(r.summary["metrics"]["simulated_time"].get<double>(), converged, 1e-12);
}

// With Suture/Newton/Trace failures the same run writes each failed coupled solve's
// trial states to coupled_newton_trace.csv (scene/coupled_newton_trace.h), and fails as
// it does without: the trace only watches. Every solve the log reports failed is there,
// from its start (iteration 0) through the two iterations allowed, each iteration going
// on from exactly one trial state. The points file is begun; its rows are the pierce
// points on the thread, none yet in these first steps (the needle's tip holds them).
TEST(SolverFailure, AFailedCoupledSolvesTrialStatesAreTraced)
{
  std::vector<std::string> args = failing_needle_pass();
  args.insert(args.end(), {"--set", "Suture/Newton/Trace failures=true"});
  const auto r = run_suturesim("fail_needle_traced", args);
  expect_failed(r);
  EXPECT_NE(r.output.find("coupled Newton: no convergence in 2 iterations"), std::string::npos) << r.output;

  std::string header;
  const auto  rows = read_numeric_csv(r.directory + "/coupled_newton_trace.csv", &header);
  ASSERT_FALSE(rows.empty()) << "no coupled_newton_trace.csv";
  const std::size_t solve = column(header, "solve"), iteration = column(header, "iteration"),
                    taken = column(header, "taken"), residual = column(header, "residual"),
                    step = column(header, "step");
  int failed = 0;
  for (std::size_t at = 0; (at = r.output.find("failed: coupled Newton", at)) != std::string::npos; ++at)
    ++failed;
  EXPECT_GE(failed, 2) << r.output; // the step and its halving
  std::map<std::pair<int, int>, int> taken_per_iterate;
  for (const auto &row : rows)
    {
      const int s = static_cast<int>(row.at(solve)), it = static_cast<int>(row.at(iteration));
      EXPECT_GE(s, 1);
      EXPECT_LE(s, failed);
      EXPECT_LE(it, 2);
      EXPECT_EQ(row.at(step) > 0, it > 0) << "solve " << s << " iteration " << it;
      if (row.at(taken) == 1)
        {
          ++taken_per_iterate[{s, it}];
          EXPECT_TRUE(std::isfinite(row.at(residual))) << "solve " << s << " iteration " << it;
        }
    }
  for (int s = 1; s <= failed; ++s)
    for (int it = 0; it <= 2; ++it)
      EXPECT_EQ((taken_per_iterate[{s, it}]), 1) << "solve " << s << " iteration " << it;
  std::string points_header;
  read_numeric_csv(r.directory + "/coupled_newton_trace_points.csv", &points_header);
  EXPECT_EQ(points_header.rfind("time [s],dt [s],solve,iteration,halvings,point,element,", 0), 0u) << points_header;
}

// Rod dynamics that run away (no numerical dissipation, rho_inf = 1, no damping, a 50 N
// step load on a 3-0 suture's free end: the tip whips at ~1 km/s) never fail a step
// outright: the steps shrink to the floor 1 ms / 2^20 and, unguarded, crept on for
// hundreds of thousands of steps. The pace guard (core/cutback_stepper.h) stops it at the
// first full window of 200 steps with status failed, a diagnosis and the state kept.
TEST(SolverFailure, RunawayRodDynamicsStopWithinABoundedNumberOfSteps)
{
  const auto r = run_suturesim("fail_runaway_rod",
                               {source_path("parameters/suture_swing.prm"), "--set",
                                "Time/Generalized-alpha/Spectral radius=1", "--set", "Suture/Damping=0", "--set",
                                "Suture/Loads/End force=0,0,-50", "--set", "Time/Max cutbacks=20"});
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_EQ(lines_starting(r.output, "error: "), 1u) << r.output;
  ASSERT_TRUE(r.has_summary) << r.output;
  EXPECT_EQ(r.summary["status"], "failed");
  const std::string error = r.summary.value("error", "");
  EXPECT_NE(error.find("steps collapsed"), std::string::npos) << error;
  EXPECT_NE(error.find("Time/Maximum steps"), std::string::npos) << error;
  const auto rows = read_forces(r);
  ASSERT_FALSE(rows.empty());
  EXPECT_LE(rows.size(), 1u + 200u) << "the initial state and at most one window of steps";
  EXPECT_LT(rows.back().at(0), 0.5); // it stopped long before the end time
  expect_outputs_end_at(r, rows.back().at(0), "suture.pvd");
}
