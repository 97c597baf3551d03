// The realtime path as a user runs it: `Model = realtime` scenes through the suturesim
// command (outputs, statistics, the guard's failure path, a mesh it cannot use).
#include "run_scene.h"
#include "stitch_checks.h"

#include <suturesim/core/level_crossing.h>
#include <suturesim/scene/wound_closure.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <map>
#include <sstream>

using namespace suturesim::test_support;

namespace
{
  const Args scene = {source_path("benchmarks/realtime_seed004_scale/realtime_seed004_scale.prm")};
  // a coarse block (h = 5 mm) keeps these runs short
  const Args coarse = {"--set", "Mesh/Geo parameters=h: 0.005, hexahedra: 0"};

  /// The default stitch on 1 mm tetrahedra with its pierce loads spread over 2 mm, and
  /// the settings @p more ("Path/Key=value").
  Args
  spread_stitch_on_1mm(const std::vector<std::string> &more)
  {
    Args args{source_path("parameters/stitch_interrupted.prm"), "--set", "Pierce points/Load radius=0.002", "--set",
              "Mesh/Geo parameters=h: 0.001, hexahedra: 0, Wg: 0.0004"};
    for (const auto &setting : more)
      args.insert(args.end(), {"--set", setting});
    return args;
  }
} // namespace

TEST(RealtimeScene, RunsTheSeed004ScaleSceneAndRecordsItsHapticStatistics)
{
  const auto r = run_suturesim("realtime_scale", join(join(scene, coarse), {"--set", "Time/End time=0.2"}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(r.has_summary);
  EXPECT_EQ(r.summary["status"], "completed");
  EXPECT_EQ(r.summary["model"], "realtime");
  const auto &m = r.summary["metrics"];
  EXPECT_EQ(m["steps"], 200);
  EXPECT_GT(m["step_time_median_us"].get<double>(), 0);
  EXPECT_GE(m["step_time_p99_us"].get<double>(), m["step_time_median_us"].get<double>());
  // the whole tick holds the tools' poses computed before the step, the step and what the
  // haptic thread does after it (the row, the states written): tick by tick no shorter,
  // so neither are its order statistics
  for (const char *q : {"median", "p99", "max"})
    EXPECT_GE(m[std::string("tick_time_") + q + "_us"].get<double>(),
              m[std::string("step_time_") + q + "_us"].get<double>())
      << q;
  EXPECT_GE(m["tick_deadline_misses"].get<unsigned>(), m["deadline_misses"].get<unsigned>());
  // the tick's phases: each a part of every tick, so no order statistic above the tick's;
  // contact is on and the row is recorded, so none of the four is empty
  for (const char *phase : {"collision", "solve", "coupling", "recording"})
    for (const char *q : {"median", "p99"})
      {
        const double t = m["tick_phases_us"][phase][q].get<double>();
        EXPECT_GT(t, 0) << phase << " " << q;
        EXPECT_LE(t, m[std::string("tick_time_") + q + "_us"].get<double>()) << phase << " " << q;
      }
  // the writer thread took every row and state
  EXPECT_EQ(m["recording"]["rows_dropped"], 0);
  EXPECT_EQ(m["recording"]["states_dropped"], 0);
  EXPECT_EQ(r.summary["realtime"]["suture_model"], "xpbd-rod");
  EXPECT_EQ(r.summary["suture"]["nodes"], 100);
  std::string header;
  const auto  rows = read_forces(r, &header);
  EXPECT_EQ(rows.size(), 201u); // t = 0 and every haptic step
  for (const char *column : {"suture_end_force_x [N]", "bottom_reaction_z [N]",
                             "top_centre_displacement_z [m]", "kinetic_energy [J]"})
    EXPECT_NE(header.find(column), std::string::npos) << column << " missing in " << header;
  for (const char *file : {"tissue.pvd", "suture.pvd", "parameters.prm"})
    EXPECT_TRUE(std::filesystem::exists(r.directory + "/" + file)) << file;
}

TEST(RealtimeScene, Seed004ScaleSceneCrossesTheSutureOverItselfAndSelfCollisionActs)
{
  // The benchmark as shipped (10 s, seed 002's transient constraints): the grasper lays
  // the strand across itself, so non-adjacent segments come within 2r and the response
  // acts on them (measured 2026-11-29 with the warm-started tissue on two threads:
  // 36 019 pair-steps, at most 8 pairs at once, 0.141 mm as detected, 2r = 0.2245 mm after
  // the correction's rounds; on one thread 32 912, 14, 0.00035 mm; before the rounds
  // 0.2130 mm, 5.1 % short, was left). Asked: that it acts in many steps, and that the
  // pairs it acts on end each step at least 0.95 of 2r apart.
  const auto r = run_suturesim("realtime_scale_full", scene);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(r.has_summary);
  const auto &self = r.summary["metrics"]["self_collision"];
  ASSERT_TRUE(self.is_object()) << r.summary["metrics"];
  const double reach = self["reach"].get<double>();
  EXPECT_NEAR(reach, 2 * 1.1225e-4, 1e-12);
  EXPECT_GT(self["pair_steps"].get<long>(), 1000);
  EXPECT_GE(self["max_pairs"].get<long>(), 1);
  ASSERT_FALSE(self["min_distance_detected"].is_null());
  EXPECT_LT(self["min_distance_detected"].get<double>(), reach) << "no pair came within 2r";
  EXPECT_GT(self["min_distance"].get<double>(), 0.95 * reach);
}

TEST(RealtimeScene, FixedBottomCarriesTheBlocksWeight)
{
  // The tissue block alone settles under gravity: the bottom's reaction is its weight
  // ρ V g = 1060 kg/m³ · 16 cm³ · 9.81 m/s² = 0.166378 N (XPBD multipliers, exact at rest).
  const auto r = run_suturesim("realtime_weight",
                               join(join(scene, coarse), {"--set", "Bodies=tissue", "--set", "Time/End time=1", "--set",
                                                          "Realtime/xpbd/Iterations=10", "--set",
                                                          "Realtime/xpbd/Damping rate=30"}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::string header;
  const auto  rows = read_forces(r, &header);
  // bottom_reaction_{x,y,z} follow time (no tool in a tissue-only scene)
  ASSERT_NE(header.find("time [s],bottom_reaction_x [N],bottom_reaction_y [N],bottom_reaction_z [N]"),
            std::string::npos)
    << header;
  ASSERT_FALSE(rows.empty());
  const double weight = 1060 * 0.04 * 0.04 * 0.01 * 9.81;
  std::printf("[ realtime weight ] bottom reaction %.6f N, weight %.6f N\n", rows.back()[3], weight);
  EXPECT_NEAR(rows.back()[3], weight, 1e-3 * weight);
}

TEST(RealtimeScene, DivergenceStopsWithOneLineAndKeepsTheLastGoodState)
{
  // A real 3-0 suture under explicit Euler at 1 kHz: dt is 2000 times its limit.
  const auto r = run_suturesim("realtime_diverge",
                               join(scene, {"--set", "Bodies=suture", "--set", "Time/End time=0.05", "--set",
                                            "Realtime/Integrator=symplectic-euler", "--set",
                                            "Realtime/Suture model=mass-spring"}));
  EXPECT_EQ(r.exit_code, 3) << r.output;
  ASSERT_TRUE(r.has_summary);
  EXPECT_EQ(r.summary["status"], "failed");
  EXPECT_NE(r.output.find("warning: "), std::string::npos) << "no stability warning:\n" << r.output;
  EXPECT_NE(r.output.find("error: diverged at step "), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("above the stability limit"), std::string::npos) << r.output;
  EXPECT_TRUE(std::filesystem::exists(r.directory + "/suture.pvd"));
}

TEST(RealtimeScene, RefusesAboveTheStabilityLimitWhenAsked)
{
  const auto r = run_suturesim("realtime_refuse",
                               join(scene, {"--set", "Bodies=suture", "--set", "Realtime/Integrator=symplectic-euler",
                                            "--set", "Realtime/Suture model=mass-spring", "--set",
                                            "Realtime/Above stability limit=refuse"}));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_FALSE(r.has_summary);
  EXPECT_NE(r.output.find("Realtime/Substeps"), std::string::npos) << r.output;
}

TEST(RealtimeScene, SameBlockUnderTheSameLoadInBothPathsFeedsTheProbeComparison)
{
  // benchmarks/block_patch_load run by both paths from the one file (coarse meshes), then
  // its compare.py --against: both must report every probe, press the top centre down,
  // and agree there within the factor of reference.json "realtime_check" (the measured
  // error of the converged volume model at the shipped resolution: the folder's README).
  const std::string file   = benchmark_scene("block_patch_load");
  const double      factor = benchmark_reference("block_patch_load")["realtime_check"]["max_factor"];
  const auto fe = run_suturesim("patch_accurate", {file, "--set", "Mesh/Geo parameters=h: 0.005, hexahedra: 1"});
  ASSERT_EQ(fe.exit_code, 0) << fe.output;
  const auto rt = run_suturesim("patch_realtime",
                                {file, "--set", "Model=realtime", "--set", "Mesh/Geo parameters=h: 0.005, hexahedra: 0",
                                 "--set", "Realtime/Integrator=xpbd", "--set", "Realtime/xpbd/Iterations=30", "--set",
                                 "Realtime/xpbd/Damping rate=50", "--set", "Time/End time=1.5"});
  ASSERT_EQ(rt.exit_code, 0) << rt.output;
  for (const char *probe : {"top_centre", "top_edge_of_patch", "top_outside", "mid_depth_centre"})
    for (const auto *r : {&fe, &rt})
      EXPECT_TRUE(r->summary["metrics"].contains(std::string(probe) + "_displacement_z")) << probe;
  const double u_fe = fe.summary["metrics"]["top_centre_displacement_z"];
  const double u_rt = rt.summary["metrics"]["top_centre_displacement_z"];
  EXPECT_LT(u_fe, 0);
  EXPECT_LT(u_rt, 0);
  EXPECT_LT(std::abs(std::log(u_rt / u_fe)), std::log(factor)) << u_fe << " vs " << u_rt;

  std::string output;
  EXPECT_EQ(run_logged({"/usr/bin/python3", source_path("benchmarks/block_patch_load/compare.py"), "--against",
                        fe.directory, rt.directory},
                       rt.directory + "_compare.log", output),
            0)
    << output;
  EXPECT_NE(output.find("| top_centre |"), std::string::npos) << output;
  EXPECT_TRUE(std::filesystem::exists(rt.directory + "/probe_comparison.csv"));
}

TEST(RealtimeScene, NeedlePassPuncturesAtTheThresholdAndRecordsTheForceCurves)
{
  // parameters/needle_pass.prm through the suturesim command on a coarser pad (h = 2 mm):
  // entry and exit punctures at the threshold within 5 % (issue 5), both pierce points
  // drawn onto the suture, the needle columns and metrics, and the plot script's PNG/PDF
  const auto r = run_suturesim("needle_pass", {source_path("parameters/needle_pass.prm"), "--set",
                                               "Mesh/Geo parameters=h: 0.002, hexahedra: 0"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto  &m         = r.summary["metrics"];
  const double threshold = r.summary["needle"]["puncture_threshold"];
  for (const char *k : {"puncture_force_entry", "puncture_force_exit"})
    {
      ASSERT_TRUE(m.contains(k)) << k;
      EXPECT_GE(m[k].get<double>(), threshold) << k;
      EXPECT_LE(m[k].get<double>(), 1.05 * threshold) << k;
    }
  // the pull through two holes at mu = 0.2 against the suture's soft constraints
  // (seed 002): 0.40 N measured at h = 1.5 mm; the FTL thread that ignored the holes
  // dragged the tissue and climbed to 1.7 N
  EXPECT_GT(m["peak_pull_force"].get<double>(), 0);
  EXPECT_LT(m["peak_pull_force"].get<double>(), 1.0);
  std::vector<std::string> kinds;
  for (const auto &e : r.summary["events"])
    if (e["kind"] != "touch_entry" && e["kind"] != "touch_exit" && e["kind"] != "release")
      kinds.push_back(e["kind"]);
  EXPECT_EQ(kinds, (std::vector<std::string>{"puncture_entry", "puncture_exit", "onto_suture", "onto_suture"}));
  std::string header;
  read_forces(r, &header);
  for (const char *column : {"needle_force_x [N]", "needle_torque_z [N*m]", "suture_tension_swage [N]",
                             "pierce_0_state [0:none|1:stick|2:slip]", "pierce_1_slip_velocity [m/s]",
                             "pierce_1_normal_force [N]", "pierce_0_friction_force [N]"})
    EXPECT_NE(header.find(column), std::string::npos) << column;

  std::string plot_output;
  EXPECT_EQ(run_logged({"/usr/bin/python3", source_path("postprocess/plot_forces.py"), r.directory},
                       r.directory + "_plot.log", plot_output),
            0)
    << plot_output;
  for (const char *file : {"forces.png", "needle_forces.png", "needle_forces.pdf"})
    EXPECT_TRUE(std::filesystem::exists(r.directory + "/" + file)) << file;
}

namespace
{
  /// A run that ended without what its pass is for: exit 6, status "incomplete" with
  /// @p reason among summary.json's "incomplete", one "incomplete:" line and no error
  /// line, the run's record otherwise whole (issue 26: never a silent run with missing
  /// metrics).
  void
  expect_incomplete(const RunResult &r, const std::string &reason)
  {
    EXPECT_EQ(r.exit_code, 6) << r.output;
    ASSERT_TRUE(r.has_summary) << r.output;
    EXPECT_EQ(r.summary["status"], "incomplete");
    ASSERT_TRUE(r.summary.contains("incomplete")) << r.summary.dump(1);
    EXPECT_NE(r.summary["incomplete"][0].get<std::string>().find(reason), std::string::npos) << r.summary.dump(1);
    EXPECT_EQ(lines_starting(r.output, "error"), 0u) << r.output;
    EXPECT_EQ(lines_starting(r.output, "incomplete: "), 1u) << r.output;
    EXPECT_EQ(lines_starting(r.output, "incomplete: " + r.summary["incomplete"][0].get<std::string>()), 1u)
      << r.output;
    EXPECT_TRUE(std::filesystem::exists(r.directory + "/forces.csv"));
  }
} // namespace

TEST(RealtimeScene, ASutureTooShortForThePassEndsIncompleteWithTheReason)
{
  // a 10 mm suture on the 16 mm pass and its 31 mm pull: the far end is drawn out
  // through the entry hole (the pierce point "released"); the pass's metrics are there
  const auto r = run_suturesim("short_suture", {source_path("parameters/needle_pass.prm"), "--set",
                                                "Suture/Straight/Length=0.01", "--set",
                                                "Mesh/Geo parameters=h: 0.002, hexahedra: 0"});
  expect_incomplete(r, "the suture's far end was drawn out of the tissue at t = ");
  EXPECT_NE(r.summary["incomplete"][0].get<std::string>().find("too short for this pass"), std::string::npos);
  EXPECT_TRUE(r.summary["metrics"].contains("puncture_force_exit"));
  // the full-length suture of the same pass is complete (NeedlePassPuncturesAtTheThreshold...);
  // so is the needle alone, which leaves its holes at the swage as a pass does
  const auto alone = run_suturesim("needle_alone", {source_path("parameters/needle_pass.prm"), "--set", "Bodies=tissue",
                                                    "--set", "Mesh/Geo parameters=h: 0.002, hexahedra: 0"});
  EXPECT_EQ(alone.exit_code, 0) << alone.output;
  EXPECT_EQ(alone.summary["status"], "completed");
  EXPECT_NE(alone.summary["events"].dump().find("\"released\""), std::string::npos) << alone.summary["events"].dump();
}

TEST(RealtimeScene, ANeedleThatNeverPuncturesEndsIncomplete)
{
  // a threshold of 100 N the tissue never reaches before the tip has turned past the
  // planned exit (t = 1.2 s); the same pass cut before its planned exit is complete
  const Args pass{source_path("parameters/needle_pass.prm"), "--set", "Puncture/Threshold=100", "--set",
                  "Mesh/Geo parameters=h: 0.002, hexahedra: 0"};
  const auto r = run_suturesim("never_punctures", join(pass, {"--set", "Time/End time=1.2"}));
  expect_incomplete(r, "the needle never punctured the tissue, though its tip had turned past the planned exit");
  EXPECT_NE(r.summary["incomplete"][0].get<std::string>().find("below Puncture/Threshold = 100 N"), std::string::npos);
  EXPECT_FALSE(r.summary["metrics"].contains("puncture_force_entry"));
  const double exit_time = r.summary["needle"]["pass"]["t_tip_exit"];
  ASSERT_LT(exit_time, 1.2);
  const auto early = run_suturesim("never_punctures_early",
                                   join(pass, {"--set", "Time/End time=" + std::to_string(0.9 * exit_time)}));
  EXPECT_EQ(early.exit_code, 0) << early.output;
  EXPECT_EQ(early.summary["status"], "completed");
}

namespace
{
  /// Pierce points 0..n-1 of a run's forces.csv keep their anchors (material points of
  /// the needle and thread, ζ_a) ascending from the tip whenever
  /// two neighbours both exist (seed 001 sec. 4.2, seed 002 sec. 4: no point passes another).
  void
  expect_pierce_order(const RunResult &r, const int n)
  {
    std::string header;
    const auto  rows  = read_forces(r, &header);
    const auto  index = [&](const std::string &column) {
      std::stringstream s(header);
      int               k = 0;
      for (std::string c; std::getline(s, c, ','); ++k)
        if (c == column)
          return k;
      return -1;
    };
    for (int k = 0; k + 1 < n; ++k)
      {
        const int a = index("pierce_" + std::to_string(k) + "_state [0:none|1:stick|2:slip]");
        const int b = index("pierce_" + std::to_string(k + 1) + "_state [0:none|1:stick|2:slip]");
        ASSERT_GE(a, 0);
        ASSERT_GE(b, 0);
        unsigned both = 0;
        for (const auto &row : rows)
          if (row[a] > 0 && row[b] > 0)
            {
              EXPECT_LT(row[a + 1], row[b + 1]) << "t = " << row[0]; // anchors ascending from the tip
              ++both;
            }
        std::printf("[ pierce order ] points %d and %d together in %u of %zu rows\n", k, k + 1, both, rows.size());
        EXPECT_GT(both, 0u) << "points " << k << " and " << k + 1 << " never together: nothing checked";
      }
  }
} // namespace

TEST(RealtimeScene, StitchPassesBothWoundSidesInOrderAcrossTheGap)
{
  // parameters/stitch_interrupted.prm up to the end of the needle's turn (0.9 s): the
  // gaping wound measures its 0.4 mm on top, the stitch's depth gap is the ruled face's
  // Wg (1 - delta/Di), and one pass makes four punctures in turn — top of A, wound face
  // of A, wound face of B, top of B — whose pierce points stay in thread order
  const auto r = run_suturesim("stitch_interrupted",
                               {source_path("parameters/stitch_interrupted.prm"), "--set", "Time/End time=0.9"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto &m = r.summary["metrics"];
  EXPECT_NEAR(m["initial_gap"].get<double>(), 4e-4, 1e-9);
  EXPECT_NEAR(m["gaps"]["stitch_depth"]["initial"].get<double>(), 4e-4 * (1 - 0.001755 / 0.003), 2e-6);
  EXPECT_TRUE(m["closure_tension"].is_null()); // not drawn tight yet
  std::vector<std::string> kinds;
  std::vector<double>      x;
  for (const auto &e : r.summary["events"])
    if (e["kind"] == "puncture_entry" || e["kind"] == "puncture_exit")
      {
        kinds.push_back(e["kind"]);
        x.push_back(e["position"][0]);
      }
  ASSERT_EQ(kinds, (std::vector<std::string>{"puncture_entry", "puncture_exit", "puncture_entry", "puncture_exit"}));
  // the tip's position at each puncture (beyond the rest surface by the dimple or tent)
  EXPECT_LT(x[0], -0.004);                  // top of A, near the bite distance
  EXPECT_LT(std::abs(x[1]), 1e-3);          // out of A within the gap
  EXPECT_LT(std::abs(x[2]), 1e-3);          // into B within the gap
  EXPECT_LT(x[1], x[2]);
  EXPECT_GT(x[3], 0.004);                   // top of B
  expect_pierce_order(r, 4);

  // seed 003's evaluation of the stitch against the planned pass: 1 ms looks turn the
  // needle by 2 mrad; the faces' facets of 1.5 mm sit within 20 um of the edge
  expect_planned_stitch(r, {1e-4, 1e-4, 2e-5});
}

TEST(RealtimeScene, ARunningSeriesStitchesOnAlongTheWoundAndTheEvaluationSpacesItsStitches)
{
  // The stitch's pass twice (Needle/Pass/Stitches = 2), the second 4 mm along the wound
  // (+y), to the second pass's end (6.5 s; the tail's grasp moved after it, no tie-off):
  // eight punctures, four a pass, each pass the planned one at its own entry, and seed
  // 003's evaluation finds two stitches crossing the wound their spacing apart (the
  // chords' midpoints: 4 mm less what the first pass moved the skin, measured 2.4 um).
  // The default spacing limit is twice the bite depth, 3.51 mm: 4 mm apart the stitches
  // are clear of it, 3 mm apart both are too close to each other (seed 003's tear-into
  // case 1, two insertions too close).
  const std::string stitch = source_path("parameters/stitch_interrupted.prm");
  const auto series = [&](const std::string &name, const std::string &spacing) {
    return run_suturesim(name, {stitch, "--set", "Needle/Pass/Stitches=2", "--set", "Needle/Pass/Spacing=" + spacing,
                                "--set", "Closure/Tie off=false", "--set", "Suture/Last end/Grasp time=7", "--set",
                                "Suture/Last end/Keyframes=7.1: 0.0129, 0, 0.008; 8: 0.0309, 0, 0.008", "--set",
                                "Time/End time=6.5"});
  };
  const auto r4 = series("running_4mm", "0, 0.004, 0");
  ASSERT_EQ(r4.exit_code, 0) << r4.output;
  expect_series_of_two(r4, 0.004);
  // puncture by puncture: in and out in turn
  std::vector<std::string> kinds;
  for (const auto &e : r4.summary["events"])
    if (e["kind"] == "puncture_entry" || e["kind"] == "puncture_exit")
      kinds.push_back(e["kind"]);
  for (std::size_t k = 0; k < kinds.size(); ++k)
    EXPECT_EQ(kinds[k], k % 2 ? "puncture_exit" : "puncture_entry") << k;
  const auto &e4 = r4.summary["metrics"]["stitch_evaluation"];
  EXPECT_EQ(e4["too_close_to_neighbour"], 0);

  const auto r3 = series("running_3mm", "0, 0.003, 0");
  ASSERT_EQ(r3.exit_code, 0) << r3.output;
  const auto &e3 = r3.summary["metrics"]["stitch_evaluation"];
  ASSERT_EQ(e3["count"], 2) << e3;
  EXPECT_NEAR(e3["stitches"][0]["spacing"].get<double>(), 0.003, 5e-5);
  EXPECT_EQ(e3["too_close_to_neighbour"], 2);
  EXPECT_EQ(e3["too_close_to_edge"], 0);
}

TEST(RealtimeScene, ARunningSutureOnALongerWoundClosesStitchByStitch)
{
  // parameters/stitch_running.prm: three passes 5 mm apart along a 30 mm wound, then the
  // tail drawn across from 12 s while the needle draws its end the other way. A gap pair
  // at each stitch gives each its own closure (metrics.gaps.s<k>): they close one after
  // the other from the tail's end (measured 12.17, 12.94 and 14.55 s), each at the
  // interpolated crossing of 0.1 mm between the two forces.csv rows around it; the
  // first pair's closure is the run's. The ends are tied off at the first step where
  // every pair is below the closure gap at once (Tie off when = every pair).
  const auto r = run_suturesim("stitch_running", {source_path("parameters/stitch_running.prm")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto &m = r.summary["metrics"];
  const auto &e = m["stitch_evaluation"];
  ASSERT_EQ(e["count"], 3) << e;
  EXPECT_EQ(e["too_close_to_neighbour"], 0);
  EXPECT_EQ(e["too_close_to_edge"], 0);
  for (int k = 0; k < 3; ++k)
    {
      EXPECT_NEAR(e["stitches"][k]["entry"][1].get<double>(), -0.005 + 0.005 * k, 1e-5) << k;
      EXPECT_TRUE(e["stitches"][k]["crosses_wound"].get<bool>()) << k;
    }
  std::string header;
  const auto  rows = read_forces(r, &header);
  const auto  time = column(header, "time");
  double      last = 0;
  for (const std::string name : {"s1", "s2", "s3"})
    {
      SCOPED_TRACE(name);
      const auto &g = m["gaps"][name];
      ASSERT_TRUE(g["closure_time"].is_number()) << g;
      const double t_c = g["closure_time"].get<double>();
      EXPECT_GT(t_c, last); // one after the other, from the tail's end
      last               = t_c;
      const auto      gap = column(header, "gap_" + name);
      std::size_t     k   = 0;
      while (k + 1 < rows.size() && rows[k + 1][time] < t_c)
        ++k;
      ASSERT_LT(k + 1, rows.size());
      EXPECT_GE(rows[k][gap], 1e-4);
      EXPECT_LT(rows[k + 1][gap], 1e-4);
      EXPECT_LE(rows[k + 1][time] - rows[k][time], 1.5e-3); // one haptic step
    }
  EXPECT_EQ(m["gaps"]["s1"]["closure_time"], m["closure_time"]);
  EXPECT_EQ(m["gaps"]["s1"]["closure_tension"], m["closure_tension"]);
  ASSERT_TRUE(m["tie_off_time"].is_number());
  const double t_tie = m["tie_off_time"].get<double>();
  EXPECT_GE(t_tie, last);
  bool seen = false;
  for (const auto &row : rows)
    if (std::abs(row[time] - t_tie) < 1e-9)
      {
        seen = true;
        for (const std::string name : {"s1", "s2", "s3"})
          EXPECT_LT(row[column(header, "gap_" + name)], 1e-4) << name;
      }
  EXPECT_TRUE(seen);
}

TEST(RealtimeScene, AnInterruptedSeriesClosesAndTiesOffEachStitchWithItsOwnSuture)
{
  // parameters/stitch_series_interrupted.prm: three stitches 5 mm apart, each pulled
  // through to a 15 mm tail, its tail taken and laid across the wound, drawn closed by the
  // needle's tightening, tied off on its own gap pair and cut beside it
  // (Needle/Pass/Series = interrupted). Each stitch closes in its own turn (the second as
  // its pull draws the thread through, before its tail is taken: measured 13.61 s, the
  // tail at 15.21 s), is tied off once
  // its tail is held, at its tie-off gap (not at its tightening's end) and before the
  // next stitch's entry, and stays closed to under a third of its initial gap (held at
  // their holes instead of a stitch width beyond, the strands crossing over the wound
  // were lost and the stitches opened again to 0.23-0.28 of 0.35-0.40 mm); once cut,
  // the needle's thread ends there and it pulls on nothing; each cut lies nearer the
  // needle than the one before (the rest of the thread is the next stitch's suture).
  const auto r =
    run_suturesim("stitch_series_interrupted", {source_path("parameters/stitch_series_interrupted.prm")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto &m = r.summary["metrics"];
  const auto &e = m["stitch_evaluation"];
  ASSERT_EQ(e["count"], 3) << e;
  const auto &series = m["interrupted_series"];
  ASSERT_EQ(series.size(), 3u) << m;
  std::string header;
  const auto  rows = read_forces(r, &header);
  const auto  time = column(header, "time");
  const auto  fx = column(header, "needle_force_x"), fy = column(header, "needle_force_y"),
             fz = column(header, "needle_force_z");
  double      cut  = 1e9;
  for (int k = 0; k < 3; ++k)
    {
      SCOPED_TRACE(k + 1);
      const auto &g = m["gaps"]["s" + std::to_string(k + 1)];
      const auto &s = series[k];
      ASSERT_TRUE(g["closure_time"].is_number() && g["tie_off_time"].is_number()) << g;
      const double closed = g["closure_time"].get<double>(), tied = g["tie_off_time"].get<double>();
      ASSERT_TRUE(s["tail_force_at_tie_off"].is_number()) << s;
      std::printf("[ interrupted series ] stitch %d: tail taken at %.3f s, closed at %.3f s with %.3f N, tied off "
                  "at %.3f s with %.3f N (the hand's pull on the tail %.3f N), final gap %.3e m\n",
                  k + 1, s["tail_taken_at"].get<double>(), closed, g["closure_tension"].get<double>(), tied,
                  g["tie_off_tension"].get<double>(), s["tail_force_at_tie_off"].get<double>(),
                  g["final"].get<double>());
      EXPECT_TRUE(s["pull_stopped"].get<bool>()) << s;
      EXPECT_LE(s["tail_taken_at"].get<double>(), tied);
      EXPECT_LE(closed, tied);
      EXPECT_LE(g["tie_off_gap"].get<double>(), 5e-5); // tied as it closed
      EXPECT_LT(g["final"].get<double>(), g["initial"].get<double>() / 3); // and held
      const double before = k == 0 ? 0.0 : m["gaps"]["s" + std::to_string(k)]["tie_off_time"].get<double>();
      EXPECT_GT(e["stitches"][k]["entry_time"].get<double>(), before); // after the stitch before is tied
      EXPECT_LT(s["cut_node"].get<double>(), cut);
      cut = s["cut_node"].get<double>();
      // the first row after the tie-off: the needle's thread is cut, it pulls on nothing
      std::size_t i = 0;
      while (i < rows.size() && rows[i][time] <= tied + 1e-9)
        ++i;
      ASSERT_LT(i, rows.size());
      const auto needle_force = [&](const std::size_t j) {
        return std::sqrt(rows[j][fx] * rows[j][fx] + rows[j][fy] * rows[j][fy] + rows[j][fz] * rows[j][fz]);
      };
      EXPECT_GT(needle_force(i - 1), 1.0); // the tie-off's step: drawn tight
      EXPECT_EQ(needle_force(i), 0.0) << rows[i][time];
    }
}

TEST(RealtimeScene, StitchClosesTheWoundAndALargerBiteNeedsMoreTension)
{
  // The whole stitch scene (7.5 s): drawn tight, the wound's top edges meet (final gap
  // below 0.1 mm; drawn on past closure to the scene's tie-off gap, 0.05 mm, and held
  // there) with the pierce points in thread order throughout.
  // Bite distance: the needle turns about its own centre, so a bite d goes as deep as
  // delta = R - sqrt(R^2 - d^2). The thread across the wound then runs at depth delta,
  // closer to the incision's floor (Di = 3 mm), about which each side turns to close the
  // top: its moment arm Di - delta falls from 1.25 mm (d = 5 mm) to 0.29 mm (d = 6 mm),
  // so the larger bite needs a larger tension to close the top (measured, the ends
  // drawn the same way: 4.47 N at 5 mm, 5.78 N at 6 mm; the test asks for 15 % more).
  // At the end no suture node lies inside the tissue outside the bites' tracts (the
  // realtime path's suture–surface contact).
  const std::string stitch = source_path("parameters/stitch_interrupted.prm");
  const auto        r5     = run_suturesim("stitch_closes", {stitch});
  ASSERT_EQ(r5.exit_code, 0) << r5.output;
  const auto &m5 = r5.summary["metrics"];
  EXPECT_LT(std::abs(m5["final_gap"].get<double>()), 1e-4);
  ASSERT_FALSE(m5["closure_tension"].is_null());
  EXPECT_GT(m5["closure_time"].get<double>(), 2.5); // after the tail's grasp
  ASSERT_FALSE(m5["tie_off_time"].is_null());
  EXPECT_GT(m5["tie_off_time"].get<double>(), m5["closure_time"].get<double>());
  EXPECT_GT(m5["tie_off_tension"].get<double>(), m5["closure_tension"].get<double>());
  expect_pierce_order(r5, 4);
  // no suture node ends inside the tissue (deeper than the suture's radius) but those
  // the bites carry between their pierce points, and the check sees those
  EXPECT_EQ(m5["suture_nodes_inside_tissue"].get<int>(), 0) << m5["suture_penetration_depth"];
  EXPECT_GT(m5["suture_nodes_in_tracts"].get<int>(), 5);
  // Regression values of this deterministic run (the checks above are the physics):
  // stored 2026-11-25 from `suturesim --output DIR` (the default scene; the closure
  // re-stored 2026-11-27, read since at the gap's interpolated crossing). Spread measured
  // on this machine (AMD EPYC, GCC 12): bit-identical with the hot kernels' x86-64-v3
  // (FMA) clones and with their baseline build (this scene's quasi-static tissue and
  // FTL suture do not call them); an input moved by one ulp (shear modulus, angular
  // speed) moves them by at most 6e-16 (closure) and 2.2e-15 (tie-off) relative, so
  // the run does not amplify round-off. Tolerance 1e-12 relative: ~500 times that
  // spread, room for another compiler's or libm's rounding; the tension rises by 2e-3 N
  // (4.6e-4 relative) over the haptic step in which the wound closes.
  EXPECT_NEAR(m5["closure_tension"].get<double>(), 4.47299300872754, 1e-12 * 4.47299300872754);
  EXPECT_NEAR(m5["tie_off_tension"].get<double>(), 4.848175935808833, 1e-12 * 4.848175935808833);
  // the gap's crossing, interpolated within the haptic step (1 ms) that closes
  EXPECT_NEAR(m5["closure_time"].get<double>(), 6.643240844819425, 1e-9);
  // the holes' loads at closure (docs/calibration.md): one table row for the run, with
  // the thread's tension between its four holes from suture.pvd, and the figure
  std::string loads;
  EXPECT_EQ(run_logged({"/usr/bin/python3", source_path("postprocess/plot_pierce_loads.py"), r5.directory},
                       r5.directory + "_pierce_loads.log", loads),
            0)
    << loads;
  const auto row = loads.find("| realtime (stitch_closes) | 6.643 s |");
  ASSERT_NE(row, std::string::npos) << loads;
  const std::string line = loads.substr(row, loads.find('\n', row) - row);
  EXPECT_EQ(std::count(line.begin(), line.end(), '|'), 11) << line;
  EXPECT_EQ(std::count(line.begin(), line.end(), '/'), 3 + 3 + 4) << line; // 4 holes twice, 5 sections
  for (const char *file : {"pierce_loads.png", "pierce_loads.pdf"})
    EXPECT_TRUE(std::filesystem::exists(r5.directory + "/" + file)) << file;

  const auto r6 = run_suturesim("stitch_bite_6mm", {stitch, "--set", "Needle/Pass/Entry point=-0.006, 0, 0.006",
                                                    "--set", "Needle/Pass/Bite depth=0.0027085"});
  ASSERT_EQ(r6.exit_code, 0) << r6.output;
  const auto &m6 = r6.summary["metrics"];
  ASSERT_FALSE(m6["closure_tension"].is_null());
  const double T6 = m6["closure_tension"].get<double>(), T5 = m5["closure_tension"].get<double>();
  std::printf("[ stitch ] closure tension: d = 5 mm %.3f N, d = 6 mm %.3f N\n", T5, T6);
  EXPECT_GT(T6, 1.15 * T5);
}

TEST(RealtimeScene, SpreadStitchWithDampingPerUnitMassHasAMeshLimit)
{
  // Issue 28, item 4: the stitch's realtime closure tension has no mesh limit as shipped
  // (point pierce loads, one B per node: 3.30 N on 2 mm tetrahedra, 4.47 N on 1.5 mm,
  // the wound not closing on 1.2 mm with B per unit mass and point loads,
  // docs/interrupted_stitch.md). With the pierce loads spread over 2 mm and B = beta m
  // it has one: the two finest meshes of
  // parameters/studies/mesh_convergence_stitch_realtime.prm (0.8 and 0.65 mm at 3 kHz)
  // differ by 0.7 %. Here the next pair down, 1 and 0.8 mm at 2 kHz (measured: 3.541 and
  // 3.661 N, 3.4 %; both within 0.5 % of their 3 kHz values), held to the 5 %.
  const std::string stitch = source_path("parameters/stitch_interrupted.prm");
  const std::vector<std::string> consistent{
    stitch, "--set", "Pierce points/Load radius=0.002", "--set", "Realtime/quasi-static/Damping=per unit mass",
    "--set", "Realtime/quasi-static/Tissue damping rate=2e7", "--set", "Realtime/Rate=2000"};
  std::vector<double> tension;
  for (const std::string h : {"0.001", "0.0008"})
    {
      auto args = consistent;
      args.insert(args.end(), {"--set", "Mesh/Geo parameters=h: " + h + ", hexahedra: 0, Wg: 0.0004"});
      const auto r = run_suturesim("stitch_spread_" + h, args);
      ASSERT_EQ(r.exit_code, 0) << r.output;
      const auto &m = r.summary["metrics"];
      ASSERT_FALSE(m["closure_tension"].is_null()) << h;
      EXPECT_EQ(m["suture_nodes_inside_tissue"].get<int>(), 0) << h;
      tension.push_back(m["closure_tension"].get<double>());
    }
  std::printf("[ stitch ] spread loads, B per unit mass: closure tension %.4f N (1 mm), %.4f N (0.8 mm)\n",
              tension[0], tension[1]);
  EXPECT_LT(std::abs(tension[1] - tension[0]), 0.05 * tension[1]);
}

TEST(RealtimeScene, AThreadBentAtItsHolesSlidesThroughThemWithoutChattering)
{
  // The realtime stitch of parameters/studies/thread_convergence_stitch_turn_length.prm
  // (1 mm tetrahedra, 3 kHz, 100 links, the contact load, L_t = 1 mm), its thread laid
  // straight through its holes (seed 002) and bent at them (Realtime/ftl/Hole placement
  // = kink; docs/interrupted_stitch.md, "The realtime thread's links"). Laid straight, a
  // sliding point jumps whenever it passes a node: between 2 and 5 s the wound's two
  // face points jump by more than 0.5 N in 108 and 87 steps (measured). Bent, none does.
  // counted by postprocess/pierce_chatter.py, the docs' command: per hole, the steps
  // whose normal force changes by more than 0.5 N and those whose friction changes sign
  const std::string        stitch = source_path("parameters/stitch_interrupted.prm");
  std::vector<std::string> counting{"/usr/bin/python3", source_path("postprocess/pierce_chatter.py")};
  for (const std::string placement : {"segment", "kink"})
    {
      const auto r = run_suturesim(
        "stitch_holes_" + placement,
        {stitch, "--set", "Pierce points/Load radius=0.002", "--set", "Realtime/quasi-static/Damping=per unit mass",
         "--set", "Realtime/quasi-static/Tissue damping rate=2e7", "--set", "Realtime/Rate=3000", "--set",
         "Mesh/Geo parameters=h: 0.001, hexahedra: 0, Wg: 0.0004", "--set", "Realtime/Contact load=true", "--set",
         "Realtime/ftl/Quasi-spring constant=60000", "--set", "Realtime/ftl/Turn length=0.001", "--set",
         "Realtime/ftl/Hole placement=" + placement});
      ASSERT_EQ(r.exit_code, 0) << r.output;
      ASSERT_FALSE(r.summary["metrics"]["closure_tension"].is_null()) << placement;
      counting.push_back(r.directory);
    }
  std::string table;
  ASSERT_EQ(run_logged(counting, (scratch_path() / "stitch_holes_chatter.log").string(), table), 0) << table;
  std::map<std::string, std::pair<unsigned, unsigned>> chatter; // jumps, friction sign changes
  for (const std::string placement : {"segment", "kink"})
    {
      const auto row = table.find("| stitch_holes_" + placement + " |");
      ASSERT_NE(row, std::string::npos) << table;
      std::stringstream line(table.substr(row, table.find('\n', row) - row));
      unsigned          holes = 0, hole = 0, jumps = 0, flips = 0;
      for (std::string word; line >> word;)
        if (word == "hole" && line >> hole >> word && line >> jumps >> word >> flips)
          {
            chatter[placement].first += jumps;
            chatter[placement].second += flips;
            ++holes;
            line.ignore(1); // the comma
          }
      EXPECT_EQ(holes, 4u) << table;
      std::printf("[ stitch holes ] %s: %u normal-force jumps over 0.5 N, %u friction sign changes (2-5 s)\n",
                  placement.c_str(), chatter[placement].first, chatter[placement].second);
    }
  EXPECT_GT(chatter["segment"].first, 50u);
  EXPECT_EQ(chatter["kink"].first, 0u);
  EXPECT_LT(chatter["kink"].second, chatter["segment"].second / 10);
}

TEST(RealtimeScene, ASpreadPointOnAWoundFaceLoadsTheOtherLipUnlessTheLoadStopsAtTheWound)
{
  // Pierce points/Load across the wound in the realtime path: the stitch's pass with its
  // loads spread over 2 mm (1 mm tetrahedra) makes four pierce points, in at the skin
  // 5 mm from the wound, out through lip A's face, in through lip B's, out at the skin.
  // With the kernel across the wound (true, the default) each face point puts a share of
  // its load on the other lip (the accurate path's share on its L2 mesh: 44 %,
  // docs/needle_and_pierce_points.md) and the skin points none (2 mm of a 5 mm bite);
  // stopped at the wound (false) none does.
  for (const std::string across : {"true", "false"})
    {
      const auto r = run_suturesim(
        "stitch_across_" + across,
        spread_stitch_on_1mm({"Time/End time=2.5", "Pierce points/Load across the wound=" + across}));
      ASSERT_EQ(r.exit_code, 0) << r.output;
      const auto &points = r.summary["pierce_points"];
      ASSERT_EQ(points.size(), 4u) << across;
      for (std::size_t k = 0; k < 4; ++k)
        {
          const double share = points[k]["load_across_wound"].get<double>();
          const double x     = points[k]["reference"][0].get<double>();
          std::printf("[ across=%s ] pierce point %zu at x = %+.5f m: share across the wound %.4f\n",
                      across.c_str(), k, x, share);
          if (across == "false" || k == 0 || k == 3)
            EXPECT_EQ(share, 0.0) << across << " " << k;
          else // the face points, on the wound's faces at |x| < 0.2 mm
            {
              EXPECT_LT(std::abs(x), 2.5e-4) << k;
              EXPECT_GT(share, 0.2) << k;
              EXPECT_LT(share, 0.6) << k;
            }
        }
    }
}

TEST(RealtimeScene, TheWoundsFacesInContactNoLongerCrossAtTheStitchsDepth)
{
  // Realtime/Face contact stiffness (realtime/wound_face_contact.h): the stitch with its
  // loads spread over 2 mm across the wound, on 1 mm tetrahedra at 3 kHz (B per unit
  // mass, as parameters/studies/mesh_convergence_stitch_realtime.prm). Without the faces'
  // contact the lips cross at the stitch's depth (measured: the gap there least at
  // -69.0 um); with 1e4 N/m per pair they touch with the penalty's give (-10.7 um), as
  // the accurate faces do (-7.4 um on Q1-P0, docs/interrupted_stitch.md). The closure
  // tension hardly moves (3.543 -> 3.567 N): the crossing is not what keeps it low.
  std::vector<double> depth, tension;
  for (const std::string k : {"0", "1e4"})
    {
      const auto r = run_suturesim("stitch_face_contact_" + k,
                                   spread_stitch_on_1mm({"Realtime/quasi-static/Damping=per unit mass",
                                                         "Realtime/quasi-static/Tissue damping rate=2e7",
                                                         "Realtime/Rate=3000",
                                                         "Realtime/Face contact stiffness=" + k}));
      ASSERT_EQ(r.exit_code, 0) << r.output;
      const auto &m = r.summary["metrics"];
      ASSERT_FALSE(m["closure_tension"].is_null()) << k;
      depth.push_back(m["gaps"]["stitch_depth"]["least"].get<double>());
      tension.push_back(m["closure_tension"].get<double>());
      std::printf("[ face contact %s N/m ] least gap at the stitch's depth %.1f um, closure tension %.4f N\n",
                  k.c_str(), depth.back() * 1e6, tension.back());
    }
  EXPECT_LT(depth[0], -40e-6);
  EXPECT_GT(depth[1], -20e-6);
  EXPECT_LT(std::abs(tension[1] - tension[0]), 0.05 * tension[0]);
}

TEST(LevelCrossing, FractionOfTheStepInEitherDirectionAndTheStepsEndWithoutABracket)
{
  using suturesim::level_crossing;
  // a linear quantity 3 -> 1 reaches 2.5 a quarter into the step, 1 -> 3 reaches 2.5 at
  // three quarters; a level hit exactly at either end counts there
  EXPECT_DOUBLE_EQ(level_crossing(3, 1, 2.5), 0.25);
  EXPECT_DOUBLE_EQ(level_crossing(1, 3, 2.5), 0.75);
  EXPECT_EQ(level_crossing(2.5, 1, 2.5), 0.0); // falling: on the level before
  EXPECT_EQ(level_crossing(1, 2.5, 2.5), 1.0); // rising: on the level after
  // no bracket (both on one side, or no sample before): the step's end
  EXPECT_EQ(level_crossing(2, 1, 2.5), 1.0);
  EXPECT_EQ(level_crossing(3, 4, 2.5), 1.0);
  EXPECT_EQ(level_crossing(std::nan(""), 3, 2.5), 1.0);
}

TEST(WoundClosure, GapIsTheOpeningAlongThePairAndClosureFreezesTheMotion)
{
  suturesim::scene::ClosureParameters prm;
  prm.pairs       = {{"mid", {-5e-4, 0, 0.006}, {5e-4, 0, 0.006}}, {"deep", {-2e-4, 0, 0.004}, {2e-4, 0, 0.004}}};
  prm.closure_gap = 1e-4;
  prm.start_time  = 1;
  suturesim::scene::ClosureMonitor monitor(prm);
  // the opening along a -> b: a sideways shift of b does not count, overlap is negative
  EXPECT_NEAR(monitor.gap(0, {-5e-4, 0, 0.006}, {5e-4, 3e-4, 0.006}), 1e-3, 1e-15);
  EXPECT_NEAR(monitor.gap(0, {1e-4, 0, 0.006}, {-1e-4, 0, 0.006}), -2e-4, 1e-15);
  monitor.update(0, {1e-3, 4e-4}, 0);
  monitor.update(0.5, {5e-5, 4e-4}, 1); // before the start time: not a closure
  EXPECT_FALSE(monitor.closed());
  monitor.update(1, {5e-4, 2e-4}, 2);
  EXPECT_FALSE(monitor.closed());
  EXPECT_EQ(monitor.motion_time(1.5), 1.5);
  monitor.update(2, {9e-5, 1e-4}, 3.5); // the first pair decides
  monitor.update(3, {-2e-5, 5e-5}, 4);
  EXPECT_TRUE(monitor.closed());
  EXPECT_EQ(monitor.motion_time(2.5), 2.0); // tied off at closure
  nlohmann::json m;
  monitor.write(m);
  EXPECT_EQ(m["initial_gap"].get<double>(), 1e-3);
  EXPECT_EQ(m["final_gap"].get<double>(), -2e-5);
  // read where the gap crosses 1e-4 m between the steps at 1 s (5e-4 m, 2 N) and 2 s
  // (9e-5 m, 3.5 N): at the fraction 4e-4/4.1e-4 of that step
  const double s = 4e-4 / 4.1e-4;
  EXPECT_NEAR(m["closure_time"].get<double>(), 1 + s, 1e-15);
  EXPECT_NEAR(m["closure_tension"].get<double>(), 2 + 1.5 * s, 1e-15);
  EXPECT_EQ(m["gaps"]["deep"]["least"].get<double>(), 5e-5);
  EXPECT_EQ(m["tie_off_time"].get<double>(), 2.0); // the motions stop at a step
  // each pair's own closure: the first pair's is the run's; the deep pair reaches the
  // closure gap at 2 s (1e-4 m, 3.5 N) and is below it at 3 s: it closed at 2 s
  EXPECT_EQ(m["gaps"]["mid"]["closure_time"], m["closure_time"]);
  EXPECT_EQ(m["gaps"]["mid"]["closure_tension"], m["closure_tension"]);
  EXPECT_EQ(m["gaps"]["deep"]["closure_time"].get<double>(), 2.0);
  EXPECT_EQ(m["gaps"]["deep"]["closure_tension"].get<double>(), 3.5);
  // a pair that never closes has none, and a checkpoint's snapshot keeps what each has
  suturesim::scene::ClosureMonitor open(prm);
  open.update(1, {5e-4, 5e-4}, 1);
  open.update(2, {5e-5, 5e-4}, 2);
  open.restore(open.snapshot());
  open.update(3, {4e-5, 6e-5}, 3);
  nlohmann::json o;
  open.write(o);
  EXPECT_TRUE(o["gaps"]["mid"]["closure_time"].is_number());
  EXPECT_NEAR(o["gaps"]["deep"]["closure_time"].get<double>(), 2 + 4e-4 / 4.4e-4, 1e-15);
  suturesim::scene::ClosureMonitor never(prm);
  never.update(1, {5e-4, 5e-4}, 1);
  never.update(2, {5e-5, 5e-4}, 2);
  nlohmann::json n;
  never.write(n);
  EXPECT_TRUE(n["gaps"]["deep"]["closure_time"].is_null());
  EXPECT_TRUE(n["gaps"]["deep"]["closure_tension"].is_null());
}

TEST(WoundClosure, AGapAlreadyBelowAtTheFirstCountedStepClosesThere)
{
  // no bracket reaches back before the start time: the crossing before it is not the
  // suture's, so the first counted step is read as it is
  suturesim::scene::ClosureParameters prm;
  prm.pairs      = {{"mid", {-5e-4, 0, 0.006}, {5e-4, 0, 0.006}}};
  prm.start_time = 1;
  suturesim::scene::ClosureMonitor monitor(prm);
  monitor.update(0.5, {5e-4}, 1);
  monitor.update(1, {5e-5}, 2);
  nlohmann::json m;
  monitor.write(m);
  EXPECT_EQ(m["closure_time"].get<double>(), 1.0);
  EXPECT_EQ(m["closure_tension"].get<double>(), 2.0);
}

TEST(WoundClosure, ATieOffGapBelowTheClosureGapDrawsTheStitchOnPastClosure)
{
  // closure is still measured at the closure gap; the ends are held only once the gap
  // is below the tie-off gap, and the tension there is reported apart
  suturesim::scene::ClosureParameters prm;
  prm.pairs       = {{"mid", {-5e-4, 0, 0.006}, {5e-4, 0, 0.006}}};
  prm.closure_gap = 1e-4;
  prm.tie_off_gap = 5e-5;
  suturesim::scene::ClosureMonitor monitor(prm);
  monitor.update(0, {1e-3}, 0);
  monitor.update(1, {9e-5}, 3.5);
  EXPECT_TRUE(monitor.closed());
  EXPECT_FALSE(monitor.tied());
  EXPECT_EQ(monitor.motion_time(1.5), 1.5); // still drawn
  monitor.update(2, {6e-5}, 4.5);
  monitor.update(3, {4e-5}, 5);
  monitor.update(4, {3e-5}, 5.2);
  EXPECT_TRUE(monitor.tied());
  EXPECT_EQ(monitor.motion_time(3.5), 3.0);
  nlohmann::json m;
  monitor.write(m);
  const double s = 9e-4 / 9.1e-4; // the crossing of 1e-4 m between 0 s and 1 s
  EXPECT_NEAR(m["closure_tension"].get<double>(), 3.5 * s, 1e-15);
  EXPECT_NEAR(m["closure_time"].get<double>(), s, 1e-15);
  EXPECT_EQ(m["tie_off_tension"].get<double>(), 5.0); // at the step that stops the motions
  EXPECT_EQ(m["tie_off_time"].get<double>(), 3.0);

  // without a tie-off nothing is held
  prm.tie_off = false;
  suturesim::scene::ClosureMonitor free(prm);
  free.update(0, {1e-3}, 0);
  free.update(1, {1e-5}, 3);
  EXPECT_TRUE(free.closed());
  EXPECT_FALSE(free.tied());
  EXPECT_EQ(free.motion_time(9.0), 9.0);
}

TEST(WoundClosure, AnInterruptedSeriesTiesEachStitchOffOnItsOwnPairWithinItsTightening)
{
  // two stitches drawn from 1 s and 4 s, tightened over [1.2, 3] s and [5, 7] s: each
  // pair counts its closure from its own pull on (not as the other stitch moves its
  // edges, nor after its tie-off) and ties its stitch off within its tightening, or from
  // when its tail is taken (start_stitch); a stitch still open at its tightening's end is
  // tied there; the series' motions stop at the last tie-off
  suturesim::scene::ClosureParameters prm;
  prm.pairs               = {{"s1", {-2e-4, 0, 0.006}, {2e-4, 0, 0.006}},
                             {"s2", {-2e-4, 0.005, 0.006}, {2e-4, 0.005, 0.006}}};
  prm.closure_gap         = 1e-4;
  prm.tie_off_gap         = 5e-5;
  prm.tie_off_each_stitch = true;
  suturesim::scene::ClosureMonitor monitor(prm);
  monitor.set_stitches({{1, 1.2, 3}, {4, 5, 7}});
  const double never = std::numeric_limits<double>::infinity();
  monitor.update(0, {4e-4, 4e-4}, 0);
  monitor.update(0.5, {4e-4, 3e-5}, 1); // s2's gap dips as stitch 1 is made: not its closure
  monitor.update(1.5, {9e-5, 3e-4}, 2); // s1 closed, above the tie-off gap
  EXPECT_EQ(monitor.stitch_ties()[0], never);
  monitor.update(2, {4e-5, 3e-4}, 2.5);
  EXPECT_EQ(monitor.stitch_ties()[0], 2.0);
  EXPECT_FALSE(monitor.tied());
  EXPECT_EQ(monitor.motion_time(4), 4.0); // the series goes on
  EXPECT_TRUE(monitor.ties_off(5.5, {2e-4, 4e-5}));
  EXPECT_FALSE(monitor.ties_off(4.5, {2e-4, 4e-5})); // drawn, its tail not taken yet
  monitor.start_stitch(1, 4.5);                       // ... now taken: from then on
  EXPECT_TRUE(monitor.ties_off(4.5, {2e-4, 4e-5}));
  monitor.update(2.5, {2e-4, 3e-4}, 1); // s1 opens again after its tie-off
  monitor.update(6, {1.2e-4, 2e-4}, 3);
  monitor.update(7, {9e-5, 1.5e-4}, 4); // s2 still open at its tightening's end: tied there
  EXPECT_EQ(monitor.stitch_ties()[1], 7.0);
  EXPECT_TRUE(monitor.tied());
  EXPECT_EQ(monitor.motion_time(8), 7.0);
  nlohmann::json m;
  monitor.write(m);
  // s1 crossed 1e-4 m between 0.5 s (4e-4 m, 1 N) and 1.5 s (9e-5 m, 2 N)
  const double f = 3e-4 / 3.1e-4;
  EXPECT_NEAR(m["gaps"]["s1"]["closure_time"].get<double>(), 0.5 + f, 1e-15);
  EXPECT_NEAR(m["gaps"]["s1"]["closure_tension"].get<double>(), 1 + f, 1e-15);
  EXPECT_EQ(m["gaps"]["s1"]["tie_off_time"].get<double>(), 2.0);
  EXPECT_EQ(m["gaps"]["s1"]["tie_off_tension"].get<double>(), 2.5);
  EXPECT_EQ(m["gaps"]["s1"]["tie_off_gap"].get<double>(), 4e-5);
  EXPECT_TRUE(m["gaps"]["s2"]["closure_time"].is_null());
  EXPECT_EQ(m["gaps"]["s2"]["tie_off_time"].get<double>(), 7.0);
  EXPECT_EQ(m["gaps"]["s2"]["tie_off_gap"].get<double>(), 1.5e-4);
  EXPECT_EQ(m["tie_off_time"].get<double>(), 7.0); // the series' last
  EXPECT_EQ(m["tie_off_tension"].get<double>(), 4.0);
  // a checkpoint's snapshot keeps each stitch's tie-off
  suturesim::scene::ClosureMonitor again(prm);
  again.set_stitches({{1, 1.2, 3}, {4, 5, 7}});
  again.restore(monitor.snapshot());
  nlohmann::json a;
  again.write(a);
  EXPECT_EQ(a, m);
}

TEST(RealtimeScene, RegionModuliNameAPhysicalVolumeOfTheMesh)
{
  // a layer the mesh does not have is an input error naming the entry and the region,
  // and the accurate path refuses layers it does not apply yet
  const std::string stitch = source_path("parameters/stitch_interrupted.prm");
  const auto        r = run_suturesim("region_unknown", {stitch, "--set", "Tissue/Region moduli=fat: 840, 36000"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_NE(r.output.find("Region moduli"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("'fat'"), std::string::npos) << r.output;
  EXPECT_FALSE(r.has_summary && r.summary["status"] == "completed");
  const auto bad = run_suturesim("region_poisson", {stitch, "--set", "Tissue/Region moduli=dermis: 3e6, 1e6"});
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("0 < mu < 1.5 K"), std::string::npos) << bad.output;
  const auto accurate = run_suturesim("region_accurate", {source_path("parameters/needle_pass.prm"), "--set",
                                                          "Model=accurate", "--set", "Bodies=tissue", "--set",
                                                          "Tissue/Region moduli=dermis: 840, 36000"});
  EXPECT_NE(accurate.exit_code, 0);
  EXPECT_NE(accurate.output.find("realtime only"), std::string::npos) << accurate.output;
}

TEST(RealtimeScene, AccessPointsPassTheGraspersPullThroughUnchanged)
{
  // parameters/tasks/node_access_pull.prm as shipped: a suture through two fixed access
  // points (seed 004's node access), its start pinned, its end lifted 10 mm. At rest the
  // pegs are frictionless: the tension through both equals what the start's pin and the
  // end's grasper feel, and the thread has slid on through both towards the grasper.
  const auto r = run_suturesim("realtime_access", {source_path("parameters/tasks/node_access_pull.prm")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(r.has_summary);
  const auto &access = r.summary["metrics"]["access"];
  ASSERT_EQ(access.size(), 2u);
  EXPECT_EQ(access[0]["name"], "entry");
  EXPECT_EQ(access[1]["name"], "exit");
  std::string header;
  const auto  rows = read_forces(r, &header);
  ASSERT_NE(header.find("time [s],suture_start_force_x [N],suture_start_force_y [N],suture_start_force_z [N],"
                        "suture_end_force_x [N],suture_end_force_y [N],suture_end_force_z [N]"),
            std::string::npos)
    << header;
  const auto  &last  = rows.back();
  const double start = std::hypot(last[1], last[2], last[3]), end = std::hypot(last[4], last[5], last[6]);
  const double entry = access[0]["tension"], exit = access[1]["tension"];
  std::printf("[ access ] tension through entry %.9f N, exit %.9f N; pin %.9f N, grasper %.9f N; links %d, %d\n",
              entry, exit, start, end, access[0]["link"].get<int>(), access[1]["link"].get<int>());
  EXPECT_GT(entry, 0.01); // N: the lift stretches the thread (0.08 N as shipped)
  EXPECT_NEAR(exit, entry, 1e-6 * entry);
  EXPECT_NEAR(start, entry, 1e-6 * entry);
  EXPECT_NEAR(end, entry, 1e-6 * entry);
  // from links 15 and 25 (b at 15.5 and 25.5 mm on the straight thread)
  EXPECT_LT(access[0]["link"].get<int>(), 15);
  EXPECT_LT(access[1]["link"].get<int>(), 25);
}

TEST(RealtimeScene, TwoStageSceneKeepsTheProbeOutAndThePassPuncturesAtTheThreshold)
{
  // parameters/tasks/two_stage.prm as shipped (seed 004's two stages on its cubic
  // tissue). External: a probe pressing the top 0.3 mm stays out of the tissue up to
  // its penalty's give, and the needle's tip presses the surface until the threshold;
  // internal: the punctures' pierce points carry the needle, then the suture, through.
  const auto r = run_suturesim("realtime_two_stage", {source_path("parameters/tasks/two_stage.prm")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(r.has_summary);
  EXPECT_EQ(r.summary["status"], "completed");
  const auto kinds = event_kinds_punctures_at(r, 0.7); // N, Puncture/Threshold
  ASSERT_GE(kinds.size(), 4u);
  EXPECT_EQ(std::vector<std::string>(kinds.begin(), kinds.begin() + 4),
            (std::vector<std::string>{"touch_entry", "puncture_entry", "touch_exit", "puncture_exit"}));
  EXPECT_NE(std::find(kinds.begin(), kinds.end(), "onto_suture"), kinds.end()); // the suture followed
  const auto  &probe = r.summary["metrics"]["probe"];
  const double push = probe["force"][2], gap = probe["least_gap"];
  std::printf("[ two stages ] probe push %.4f N, least gap %.3e m (of a 3e-4 m press)\n", push, gap);
  EXPECT_GT(push, 1.0); // N: the dermis pushes back (4.95 N as shipped)
  EXPECT_LT(gap, 0.0);  // it pressed
  EXPECT_GT(gap, -0.5 * 3e-4); // m: the penalty gives less than half the press, the surface took the rest
  std::string header;
  read_forces(r, &header);
  EXPECT_NE(header.find("probe_force_x [N],probe_force_y [N],probe_force_z [N]"), std::string::npos) << header;
}
