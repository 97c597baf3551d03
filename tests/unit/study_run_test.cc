// `suturesim study` end to end (issue 24): the shipped studies at small size, the
// stability boundary against dt_crit, reruns that run nothing, the Snakemake export, and
// the errors a study reports only after its runs.
#include <suturesim/study/convergence.h>
#include <suturesim/study/pareto.h>

#include "run_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <tuple>

using namespace suturesim;
using namespace suturesim::test_support;
namespace fs = std::filesystem;

namespace
{
  struct StudyRun
  {
    int            exit_code = -1;
    std::string    output;
    std::string    folder;
    nlohmann::json study; ///< study.json, when written
  };

  /// `suturesim study <file> --output <scratch>/<name> <args>`; @p fresh clears the folder;
  /// @p environment as start_process() takes it.
  StudyRun
  run_study(const std::string &name, const std::string &file, const Args &args, const bool fresh = true,
            const Args &environment = {})
  {
    StudyRun r;
    r.folder = (scratch_path() / name).string();
    if (fresh)
      fs::remove_all(r.folder);
    r.exit_code = run_logged(join({suturesim_binary(), "study", file, "--output", r.folder}, args), r.folder + ".log",
                             r.output, environment);
    std::ifstream json(r.folder + "/study.json");
    if (json)
      json >> r.study;
    return r;
  }

  /// cases.csv as rows of cells, the header first (no quoted commas in these studies'
  /// numeric columns; the quoted axis values are compared whole).
  std::vector<std::vector<std::string>>
  read_csv(const std::string &file)
  {
    std::ifstream                         in(file);
    std::vector<std::vector<std::string>> rows;
    for (std::string line; std::getline(in, line);)
      {
        std::vector<std::string> cells;
        std::string              cell;
        bool                     quoted = false;
        for (const char c : line + ",")
          if (c == '"')
            quoted = !quoted;
          else if (c == ',' && !quoted)
            cells.push_back(cell), cell.clear();
          else
            cell += c;
        rows.push_back(cells);
      }
    return rows;
  }

  /// The columns of @p rows whose header is not a cost (costs are measured times).
  std::vector<std::vector<std::string>>
  without_costs(const std::vector<std::vector<std::string>> &rows)
  {
    std::vector<bool> keep;
    for (const auto &h : rows.at(0))
      keep.push_back(h.find("time [s]") == std::string::npos && h.find("core_seconds") == std::string::npos &&
                     h.find("peak_memory") == std::string::npos && h.find("step_time") == std::string::npos);
    std::vector<std::vector<std::string>> out;
    for (const auto &row : rows)
      {
        out.emplace_back();
        for (std::size_t k = 0; k < row.size(); ++k)
          if (keep.at(k))
            out.back().push_back(row[k]);
      }
    return out;
  }

  std::map<std::string, fs::file_time_type>
  run_records(const std::string &folder)
  {
    std::map<std::string, fs::file_time_type> times;
    for (const auto &c : fs::directory_iterator(fs::path(folder) / "cases"))
      times[c.path().filename().string()] = fs::last_write_time(c.path() / "run.json");
    return times;
  }

  /// The study file @p file's text with its base scene's relative path @p relative (its
  /// first occurrence) given from the source tree's @p from instead, so that a changed
  /// copy in the scratch folder finds it; "" when the file does not hold @p relative.
  std::string
  study_text_from_anywhere(const std::string &file, const std::string &relative, const std::string &from)
  {
    std::string study = read_text(file);
    const auto  base  = study.find(relative);
    if (base == std::string::npos)
      return "";
    return study.replace(base, relative.size(), source_path(from));
  }

  /// study.json's rows by name.
  std::map<std::string, nlohmann::json>
  rows_by_name(const nlohmann::json &study)
  {
    std::map<std::string, nlohmann::json> rows;
    for (const auto &c : study.at("cases"))
      rows[c["name"].get<std::string>()] = c;
    return rows;
  }

  const std::string small_study = source_path("tests/data/studies/realtime_small.prm");
} // namespace

TEST(StudyRun, PatchLoadParetoAtSmallSizeWritesTablesFrontAndCharts)
{
  // the shipped study, 0.5 s instead of 3 s (the reference: one quasi-static step)
  const auto r = run_study("study_patch_load", source_path("parameters/studies/patch_load_pareto.prm"),
                           {"--jobs", "2", "--set", "Time/End time=0.5"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char *file : {"cases.csv", "study.json", "pareto.png", "pareto.pdf"})
    EXPECT_TRUE(fs::exists(fs::path(r.folder) / file)) << file;
  const auto rows = read_csv(r.folder + "/cases.csv");
  ASSERT_EQ(rows.size(), 19u); // header, the reference, 17 cases
  EXPECT_EQ(rows[0][0], "case");
  EXPECT_NE(std::find(rows[0].begin(), rows[0].end(), "probes.max error [1]"), rows[0].end());
  EXPECT_NE(std::find(rows[0].begin(), rows[0].end(), "step_time_median [s]"), rows[0].end());

  // the front study.json names is the non-dominated set of its own (cost, error) pairs
  const auto     &cases = r.study.at("cases");
  std::vector<std::string> expected;
  for (std::size_t i = 1; i < cases.size(); ++i)
    {
      if (cases[i]["status"] != "completed")
        continue;
      bool dominated = false;
      for (std::size_t j = 1; j < cases.size(); ++j)
        {
          const double ci = cases[i]["cost"], ei = cases[i]["error"], cj = cases[j]["cost"], ej = cases[j]["error"];
          dominated |= cases[j]["status"] == "completed" && cj <= ci && ej <= ei && (cj < ci || ej < ei);
        }
      if (!dominated)
        expected.push_back(cases[i]["name"]);
    }
  std::vector<std::string> front = r.study.at("front");
  std::sort(front.begin(), front.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(front, expected);
  EXPECT_GE(front.size(), 2u);
}

TEST(StudyRun, ExplicitStabilityBoundaryLiesWithinFivePercentOfDtCrit)
{
  const auto r = run_study("study_stability_explicit", source_path("parameters/studies/stability_explicit.prm"),
                           {"--jobs", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(fs::path(r.folder) / "stability.csv"));
  EXPECT_TRUE(fs::exists(fs::path(r.folder) / "stability.png"));
  const auto &boundary = r.study.at("stability").at("boundary");
  ASSERT_EQ(boundary.size(), 3u); // every shear modulus of the axis
  for (const auto &b : boundary)
    {
      ASSERT_FALSE(b["largest_stable_dt"].is_null()) << b.dump();
      ASSERT_FALSE(b["smallest_diverged_dt"].is_null()) << b.dump();
      const double crit = b["dt_crit"], stable = b["largest_stable_dt"], diverged = b["smallest_diverged_dt"];
      std::printf("[ stability ] shear modulus %s Pa: stable up to %.4g dt_crit, diverged from %.4g dt_crit\n",
                  b["y"].get<std::string>().c_str(), stable / crit, diverged / crit);
      EXPECT_LT(stable, diverged);
      EXPECT_GE(stable, 0.95 * crit);
      EXPECT_LE(diverged, 1.05 * crit);
    }
  // a diverged case is a row with its status and the guard's reason, not a gap
  std::size_t diverged = 0;
  for (const auto &c : r.study.at("cases"))
    if (c["status"] == "failed")
      {
        ++diverged;
        EXPECT_NE(c["reason"].get<std::string>().find("diverged"), std::string::npos) << c.dump();
      }
  EXPECT_GT(diverged, 0u);
}

TEST(StudyRun, RerunWithNothingChangedRunsNoCase)
{
  const auto first = run_study("study_rerun", small_study, {"--jobs", "2"});
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_EQ(first.study["timing"]["cases_run"], 5);
  const auto before = run_records(first.folder);

  // best.prm is a scene that reproduces the cheapest adequate case by itself
  ASSERT_TRUE(first.study["best"].is_string()) << first.study.dump();
  const std::string best = first.study["best"];
  const auto        again = run_suturesim("study_rerun_best", {first.folder + "/best.prm"});
  ASSERT_EQ(again.exit_code, 0) << again.output;
  std::ifstream  in(first.folder + "/cases/" + best + "/summary.json");
  nlohmann::json chosen;
  in >> chosen;
  for (const char *metric : {"top_centre_displacement_z", "mid_depth_centre_displacement_z"})
    EXPECT_EQ(again.summary["metrics"][metric], chosen["metrics"][metric]) << metric;
  const auto second = run_study("study_rerun", small_study, {"--jobs", "2"}, false);
  ASSERT_EQ(second.exit_code, 0) << second.output;
  EXPECT_EQ(second.study["timing"]["cases_run"], 0);
  EXPECT_EQ(second.study["timing"]["cases_reused"], 5);
  EXPECT_EQ(run_records(second.folder), before);
  EXPECT_EQ(without_costs(read_csv(second.folder + "/cases.csv")), without_costs(read_csv(first.folder + "/cases.csv")));
  // a setting that changes every case runs them all again
  const auto third = run_study("study_rerun", small_study, {"--jobs", "2", "--set", "Realtime/Rate=500"}, false);
  ASSERT_EQ(third.exit_code, 0) << third.output;
  EXPECT_EQ(third.study["timing"]["cases_run"], 5);
}

// Reference/Processes: the reference runs under mpirun -np 2 (its summary.json says so),
// a listed case with the same settings serially, and the two agree to the solver's
// tolerance; the exported Snakefile gives the reference two cores.
TEST(StudyRun, AReferenceOnTwoProcessesGivesTheSerialResult)
{
  const std::string file = (scratch_path() / "studies" / "cook_processes.prm").string();
  fs::create_directories(scratch_path() / "studies");
  const std::string same = "Tissue/Element degree=2, Mesh/Elements per edge=4";
  std::ofstream(file) << "set Name = cook_processes\nset Base scene = " << source_path("tests/data/cook_coarse.prm")
                      << "\nsubsection Reference\n  set Settings = " << same
                      << "\n  set Processes = 2\nend\nsubsection Cases\n  set List = serial: " << same
                      << "\nend\nsubsection Metrics\n  set Probes = tip\nend\n"
                         "subsection Objective\n  set Error = probes.max\nend\n";
  const auto r = run_study("study_processes", file, {"--jobs", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::map<std::string, nlohmann::json> summaries;
  for (const std::string name : {"reference", "serial"})
    {
      std::ifstream in(r.folder + "/cases/" + name + "/summary.json");
      in >> summaries[name];
    }
  EXPECT_EQ(summaries["reference"]["mpi_processes"], 2);
  EXPECT_EQ(summaries["serial"]["mpi_processes"], 1);
  const double tip = summaries["serial"]["metrics"]["tip_displacement_y"].get<double>();
  EXPECT_GT(std::abs(tip), 1e-3); // the membrane bends by millimetres
  // Newton stops at 1e-9 of the first residual (Tissue/Newton defaults) on either count
  EXPECT_NEAR(summaries["reference"]["metrics"]["tip_displacement_y"].get<double>(), tip, 1e-8 * std::abs(tip));
  const auto exported = run_study("study_processes_snakemake", file, {"--export", "snakemake"});
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  std::ifstream      snakefile(exported.folder + "/Snakefile");
  std::ostringstream text;
  text << snakefile.rdbuf();
  EXPECT_NE(text.str().find("PROCESSES = {\n    \"reference\": 2,\n    \"serial\": 1,\n}"), std::string::npos)
    << text.str();
}

TEST(StudyRun, SnakemakeExportGivesTheSameTableAsJobs)
{
  const auto jobs = run_study("study_jobs", small_study, {"--jobs", "2"});
  ASSERT_EQ(jobs.exit_code, 0) << jobs.output;
  const auto exported = run_study("study_snakemake", small_study, {"--export", "snakemake"});
  ASSERT_EQ(exported.exit_code, 0) << exported.output;
  ASSERT_TRUE(fs::exists(fs::path(exported.folder) / "Snakefile"));
  // snakemake from Debian (scripts/install-deps.sh); its own working folder is the study's
  std::string snakemake_output;
  ASSERT_EQ(run_logged({"snakemake", "--directory", exported.folder, "--snakefile", exported.folder + "/Snakefile",
                        "--cores", "2"},
                       exported.folder + "/snakemake.log", snakemake_output),
            0)
    << "see " << exported.folder << "/snakemake.log";
  const auto snake = read_csv(exported.folder + "/cases.csv");
  ASSERT_EQ(snake.size(), 6u);
  EXPECT_EQ(without_costs(snake), without_costs(read_csv(jobs.folder + "/cases.csv")));
  // the map (Figures/Map): a row per case, each with its own run's value, both ways alike
  const auto map = read_csv(jobs.folder + "/map.csv");
  ASSERT_EQ(map.size(), 5u);
  EXPECT_EQ(map, read_csv(exported.folder + "/map.csv"));
  EXPECT_TRUE(fs::exists(fs::path(jobs.folder) / "map.png"));
  for (const auto &cell : jobs.study.at("map").at("cells"))
    {
      const auto &c = *std::find_if(jobs.study.at("cases").begin(), jobs.study.at("cases").end(),
                                    [&](const auto &k) { return k["name"] == cell["case"]; });
      nlohmann::json summary;
      std::ifstream(jobs.folder + "/cases/" + c["name"].get<std::string>() + "/summary.json") >> summary;
      EXPECT_EQ(cell["values"]["top_centre_displacement_z"], summary["metrics"]["top_centre_displacement_z"]);
      EXPECT_EQ(cell["reference_values"]["top_centre_displacement_z"].is_number(), true);
    }
}

TEST(StudyRun, ACaseThatEndsWithoutWhatItsSceneAskedIsIncompleteWithTheReason)
{
  // the run's own "incomplete" (exit 6, scene/run_summary.h) becomes the row's status,
  // its one line the reason
  const auto r = run_study("study_needle_incomplete", source_path("tests/data/studies/needle_incomplete.prm"), {});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::map<std::string, nlohmann::json> rows;
  for (const auto &c : r.study.at("cases"))
    if (!c["is_reference"].get<bool>())
      rows[c["name"].get<std::string>()] = c;
  ASSERT_EQ(rows.size(), 2u) << r.study.dump(1);
  for (const auto &[name, c] : rows)
    if (name.find("100") != std::string::npos)
      {
        EXPECT_EQ(c["status"], "incomplete") << c.dump();
        EXPECT_NE(c.value("reason", "").find("the needle never punctured the tissue"), std::string::npos) << c.dump();
      }
    else
      EXPECT_EQ(c["status"], "completed") << c.dump();
}

// A reference that fails (exit 3) stops the study at its report, naming it; with
// Reference/On failure = report (per axis only) the study goes on: the failed
// reference's cases are not compared with it and their map cells carry its status.
// A case that a library stopped, with no line of suturesim's own: the study names the exit
// code and what the log said last. Here Open MPI's MPI_Init, told to make its session
// directory under a file (OMPI_MCA_orte_tmpdir_base, the user's to set, which each case
// keeps: core/mpi_session.h), fails and exits 1 (as it did in CI, 2026-12-05, when two
// singletons shared a session directory; the reason said only "exit code 1").
TEST(StudyRun, ACaseThatALibraryStoppedIsCrashedWithWhatItsLogSaidLast)
{
  const auto not_a_folder = scratch_path() / "not_a_folder";
  std::ofstream(not_a_folder) << "a file\n";
  const auto r = run_study("study_library_stopped", small_study, {},
                           true, {"OMPI_MCA_orte_tmpdir_base=" + (not_a_folder / "tmp").string()});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("crashed"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("exit code 1 after '"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("MPI_INIT"), std::string::npos) << r.output;
}

TEST(StudyRun, AnIncompleteRunIsMeasuredAndAnIncompleteReferenceIsReportedInItsCell)
{
  // tests/data/studies/incomplete_reference.prm: per Needle/Pass/Tighten duration, 1 s
  // takes the needle back into the pad at 1.7 s (the run ends there, incomplete), 100 s
  // does not. With Reference/On failure = report the incomplete reference keeps its cell
  // and its case is not compared; the other cell is.
  const std::string file = source_path("tests/data/studies/incomplete_reference.prm");
  const auto        r    = run_study("study_incomplete_reference", file, {});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto rows = rows_by_name(r.study);
  ASSERT_EQ(rows.size(), 4u) << r.study.dump(1);
  EXPECT_EQ(rows.at("reference_1")["status"], "incomplete");
  EXPECT_NE(rows.at("reference_1").value("reason", "").find("the needle's swage went back into the tissue"),
            std::string::npos)
    << rows.at("reference_1").dump();
  EXPECT_EQ(rows.at("reference_100")["status"], "completed");
  EXPECT_EQ(rows.at("1")["status"], "no reference") << rows.at("1").dump();
  EXPECT_EQ(rows.at("1").value("reason", "").rfind("its reference run 'reference_1' incomplete: ", 0), 0u)
    << rows.at("1").dump();
  EXPECT_EQ(rows.at("100")["status"], "completed");
  EXPECT_TRUE(rows.at("100")["errors"]["puncture_force_entry"].is_number()) << rows.at("100").dump();

  // the references ended before the needle comes down (a copy with their End time at
  // 1.65 s): both complete, and the case that ends incomplete at 1.7 s has its error
  // measured as a completed one's, its status and reason its own
  std::string study = study_text_from_anywhere(file, "../needle_clearance", "tests/data/needle_clearance");
  ASSERT_FALSE(study.empty());
  const auto rate = study.find("Realtime/Rate=1000");
  ASSERT_NE(rate, std::string::npos);
  study.insert(rate + std::string("Realtime/Rate=1000").size(), ", Time/End time=1.65");
  const auto short_file = scratch_path() / "incomplete_reference_short.prm";
  std::ofstream(short_file) << study;
  const auto s = run_study("study_incomplete_reference_short", short_file.string(), {});
  ASSERT_EQ(s.exit_code, 0) << s.output;
  rows = rows_by_name(s.study);
  ASSERT_EQ(rows.size(), 4u) << s.study.dump(1);
  EXPECT_EQ(rows.at("reference_1")["status"], "completed");
  EXPECT_EQ(rows.at("1")["status"], "incomplete");
  EXPECT_NE(rows.at("1").value("reason", "").find("Needle/Pass/Tighten drives it there"), std::string::npos)
    << rows.at("1").dump();
  EXPECT_TRUE(rows.at("1")["errors"]["puncture_force_entry"].is_number()) << rows.at("1").dump();
}

TEST(StudyRun, AFailedReferenceStopsTheStudyOrIsReportedInItsCells)
{
  const std::string file = source_path("tests/data/studies/failed_reference.prm");
  const auto        stopped = run_study("study_failed_reference_stop", file, {});
  EXPECT_EQ(stopped.exit_code, 2) << stopped.output;
  EXPECT_NE(stopped.output.find("failed_reference.prm:11: Reference/Settings: the reference run 'reference_300' "
                                "failed: diverged at step 5: runaway kinetic energy"),
            std::string::npos)
    << stopped.output;
  EXPECT_FALSE(fs::exists(fs::path(stopped.folder) / "study.json"));

  // the same file with the reference's failure reported (a copy in the scratch folder)
  std::string study = study_text_from_anywhere(file, "../../../benchmarks", "benchmarks");
  ASSERT_FALSE(study.empty());
  study.replace(study.find("  set Per axis"), 0, "  set On failure = report\n");
  const auto reported_file = scratch_path() / "failed_reference_report.prm";
  std::ofstream(reported_file) << study;
  const auto r = run_study("study_failed_reference_report", reported_file.string(), {});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  auto rows = rows_by_name(r.study);
  ASSERT_EQ(rows.size(), 6u) << r.study.dump(1);
  EXPECT_EQ(rows.at("reference_300")["status"], "failed");
  EXPECT_EQ(rows.at("reference_4000")["status"], "completed");
  for (const auto &[name, c] : rows)
    {
      if (c["is_reference"].get<bool>())
        continue;
      const bool at_300 = name.rfind("300_", 0) == 0;
      EXPECT_EQ(c["status"], at_300 ? "no reference" : "completed") << c.dump();
      if (at_300)
        {
          EXPECT_EQ(c.value("reason", ""), "its reference run 'reference_300' failed: " +
                                             rows.at("reference_300").value("reason", ""))
            << c.dump();
        }
    }
  // map.csv: every case's own value; the reference's status beside it
  const auto map = read_csv(r.folder + "/map.csv");
  ASSERT_EQ(map.size(), 5u);
  const auto column = [&](const std::string &name) {
    return std::find(map[0].begin(), map[0].end(), name) - map[0].begin();
  };
  const auto status = column("status"), reference_status = column("reference status"),
             value = column("top_centre_displacement_z");
  ASSERT_LT(reference_status, static_cast<long>(map[0].size()));
  for (std::size_t k = 1; k < map.size(); ++k)
    {
      const bool at_300 = map[k][0].rfind("300_", 0) == 0;
      EXPECT_EQ(map[k][status], at_300 ? "no reference" : "completed");
      EXPECT_EQ(map[k][reference_status], at_300 ? "failed" : "completed");
      EXPECT_FALSE(map[k][value].empty());
    }
  EXPECT_TRUE(fs::exists(fs::path(r.folder) / "map.png"));
}

TEST(StudyRun, ErrorsFoundAfterTheRunsNameTheStudyLine)
{
  const auto dir = scratch_path() / "bad_studies";
  fs::create_directories(dir);
  const std::string base = source_path("benchmarks/block_patch_load/block_patch_load.prm");
  const std::string head = "set Name = bad\nset Base scene = " + base +
                           "\nsubsection Reference\n  set Settings = Model=realtime, \"Mesh/Geo parameters=h: 0.005, "
                           "hexahedra: 0\", Time/End time=0.01";
  const std::string cases = "\nsubsection Cases\n  set Settings = Model=realtime, \"Mesh/Geo parameters=h: 0.005, "
                            "hexahedra: 0\", Time/End time=0.01\n  set Axes = Realtime/xpbd/Iterations = 2\nend\n";
  struct Bad
  {
    std::string name, text, expected;
  };
  const std::vector<Bad> bad{
    {"no_such_metric", head + "\nend" + cases + "subsection Metrics\n  set Scalars = nonsense\nend\n",
     "no_such_metric.prm:11: Metrics/Scalars: the reference has no metric 'nonsense'"},
    {"refused_reference", head + ", Realtime/Integrator=symplectic-euler, Realtime/Rate=10, Realtime/Above stability limit=refuse\nend" + cases,
     "refused_reference.prm:4: Reference/Settings: the reference run 'reference' refused: "},
  };
  for (const auto &b : bad)
    {
      const std::string file = (dir / (b.name + ".prm")).string();
      std::ofstream(file) << b.text;
      const auto r = run_study("bad_" + b.name, file, {});
      std::printf("[ study error ] %s", r.output.substr(r.output.rfind("error: ")).c_str());
      EXPECT_EQ(r.exit_code, 2) << r.output;
      EXPECT_NE(r.output.find(b.expected), std::string::npos) << r.output;
    }
  // the command line
  EXPECT_EQ(run_study("bad_jobs", small_study, {"--jobs", "0"}).exit_code, 2);
  EXPECT_NE(run_study("bad_option", small_study, {"--nonsense"}).output.find("unknown"), std::string::npos);
  const auto only = run_study("bad_only", small_study, {"--only", "nonsense"});
  EXPECT_EQ(only.exit_code, 2);
  EXPECT_NE(only.output.find("--only nonsense: the study has no such case"), std::string::npos) << only.output;
}

TEST(StudyRun, XpbdStretchFallsWithIterationsAndRate)
{
  // the shipped study at 0.1 s: XPBD never diverges, and its suture stretches less with
  // more iterations at one rate and with a higher rate at one iteration count (its
  // constraints' effective stiffness grows with both: Macklin et al. 2016, sec. 3.3)
  const auto r = run_study("study_stability_xpbd", source_path("parameters/studies/stability_xpbd.prm"),
                           {"--jobs", "2", "--set", "Time/End time=0.1"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(fs::path(r.folder) / "stability.png"));
  const std::string modulus = "Suture/Cross section/Young's modulus";
  using Cell = std::tuple<std::string, int, int>; // (modulus, iterations, rate)
  std::map<Cell, double> stretch;
  for (const auto &c : r.study.at("cases"))
    {
      ASSERT_EQ(c["status"], "completed") << c.dump();
      if (c["is_reference"])
        continue;
      // each case against the rod of its own modulus
      const std::string E = c["axes"][modulus];
      EXPECT_EQ(c["reference"], "reference_" + E) << c.dump();
      const int iterations = std::stoi(c["axes"]["Realtime/xpbd/Iterations"].get<std::string>());
      const int rate       = std::stoi(c["axes"]["Realtime/Rate"].get<std::string>());
      stretch[{E, iterations, rate}] = c["limits"]["suture_stretch_max"];
    }
  ASSERT_EQ(stretch.size(), 90u);
  ASSERT_EQ(r.study.at("best").size(), 3u); // a cheapest adequate case per modulus
  for (const auto &[key, value] : stretch)
    {
      const auto &[E, iterations, rate] = key;
      const auto more_iterations        = stretch.upper_bound({E, iterations, 1 << 30});
      if (more_iterations != stretch.end() && std::get<0>(more_iterations->first) == E)
        {
          EXPECT_LT(stretch.at({E, std::get<1>(more_iterations->first), rate}), value)
            << E << " Pa, " << iterations << " iterations, " << rate << " Hz";
        }
      const auto faster = stretch.find({E, iterations, 2 * rate});
      if (faster != stretch.end())
        {
          EXPECT_LT(faster->second, value) << E << " Pa, " << iterations << " iterations, " << rate << " Hz";
        }
      // XPBD's compliance over the step, 1/(k dt^2) with k = EA/l (1.6 1/kg here at 1 GPa
      // and 250 Hz), is 1e-7 of a node's inverse mass (2.2e7 1/kg): each constraint is
      // rigid, and what is left of the stretch is the iterations' residual, the same at
      // every modulus of a suture
      EXPECT_NEAR(stretch.at({"3e9", iterations, rate}), value, 0.05 * value)
        << E << " Pa, " << iterations << " iterations, " << rate << " Hz";
    }
  // the map: the over-stretched cells (beyond Objective/Limits' 1 %) inaccurate, the others stable
  for (const auto &cell : r.study.at("stability").at("cells"))
    {
      const auto &c = *std::find_if(r.study.at("cases").begin(), r.study.at("cases").end(),
                                    [&](const auto &k) { return k["name"] == cell["case"]; });
      EXPECT_EQ(cell["state"], c["limits"]["suture_stretch_max"].get<double>() > 0.01 ? "inaccurate" : "stable")
        << cell.dump();
    }
}

TEST(StudyRun, ConvergenceTableHasAnOrderPerSeries)
{
  const auto r = run_study("study_convergence", source_path("tests/data/studies/convergence_small.prm"), {"--jobs", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto &series = r.study.at("convergence").at("series");
  ASSERT_EQ(series.size(), 1u); // every case is Model=realtime
  EXPECT_EQ(series[0]["series"], "realtime");
  // the parameter that names the series, for the chart's legend
  EXPECT_EQ(r.study.at("convergence").at("series_parameter"), "Model");
  EXPECT_EQ(series[0]["table"].size(), 4u);
  EXPECT_TRUE(series[0]["observed_order"].is_number()) << series.dump();
  const std::string text = read_text(r.folder + "/convergence.csv");
  EXPECT_NE(text.find("# realtime: observed order p = "), std::string::npos) << text;
  EXPECT_TRUE(fs::exists(fs::path(r.folder) / "convergence.png"));
}

TEST(StudyRun, RealtimeTearOnsetMapOverBiteAndSpacing)
{
  // the shipped realtime map in full (25 two-stitch runs, about 3 min on two cores): each
  // cell holds its own run's metrics and flags; at the widest spacing, where no neighbour
  // is nearer than the wound, the onset rises with the bite (seed 003's ligament rule:
  // the threshold T_c l grows with the ligament to the wound)
  const auto r = run_study("study_tearing_bite_spacing_realtime",
                           source_path("parameters/studies/tearing_bite_spacing_realtime.prm"), {"--jobs", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(fs::path(r.folder) / "map.png"));
  EXPECT_EQ(read_csv(r.folder + "/map.csv").size(), 26u);
  const auto &map = r.study.at("map");
  ASSERT_EQ(map.at("cells").size(), 25u);
  EXPECT_FALSE(map.at("references_per_cell").get<bool>());
  std::map<std::pair<double, double>, double> onset; // (spacing, bite) -> onset force
  int                                         flagged = 0;
  for (const auto &cell : map.at("cells"))
    {
      nlohmann::json summary;
      std::ifstream(r.folder + "/cases/" + cell["case"].get<std::string>() + "/summary.json") >> summary;
      const auto &m = summary.at("metrics");
      for (const auto &[name, value] : cell["values"].items())
        {
          const std::string part = name.substr(name.find('.') + 1);
          EXPECT_EQ(value, m.at("realtime_tearing").value(part, nlohmann::json())) << cell.dump();
        }
      for (const auto &[name, value] : cell["flags"].items())
        EXPECT_EQ(value, m.at("stitch_evaluation").at(name.substr(name.find('.') + 1))) << cell.dump();
      flagged += cell["flags"]["stitch_evaluation.too_close_to_neighbour"].get<int>() > 0;
      ASSERT_TRUE(cell["values"]["realtime_tearing.onset_force"].is_number()) << cell.dump();
      const double spacing = std::stod(cell["y"].get<std::string>().substr(3));
      onset[{spacing, std::stod(cell["x"].get<std::string>())}] = cell["values"]["realtime_tearing.onset_force"];
    }
  // the closest spacings are flagged, the widest not (seed 003: spacing < 2 x bite depth)
  EXPECT_GT(flagged, 0);
  EXPECT_LT(flagged, 25);
  double last = 0;
  for (const auto &[key, force] : onset)
    if (key.first == 0.008)
      {
        std::printf("[ map ] bite %g m: onset %.3f N\n", key.second, force);
        EXPECT_GT(force, last) << key.second;
        last = force;
      }
}

TEST(StudyRun, AResolutionSeriesReferenceIsItsExtrapolation)
{
  const auto r = run_study("study_series", source_path("tests/data/studies/series_small.prm"), {"--jobs", "2"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto &account = r.study.at("reference_series");
  ASSERT_EQ(account.at("runs").size(), 3u);
  const auto &f = account.at("metrics").at("top_centre_displacement_z");
  // these three meshes' sags change more from the medium to the fine mesh than from the
  // coarse to the medium: no asymptotic range, so the finest run's value is the reference
  const std::vector<double> values = f.at("values");
  const std::vector<double> h      = f.at("h");
  EXPECT_TRUE(study::estimate_convergence(h, values).diverging);
  ASSERT_EQ(f["used"], "finest") << f.dump();
  EXPECT_NE(f["why"].get<std::string>().find("grow under refinement"), std::string::npos) << f.dump();
  const double reference = values.back();
  std::printf("[ series ] h = %s, sag = %s, used: %s%s\n", f["h"].dump().c_str(), f["values"].dump().c_str(),
              f["used"].get<std::string>().c_str(), f.contains("why") ? (" (" + f["why"].get<std::string>() + ")").c_str() : "");
  unsigned checked = 0;
  for (const auto &c : r.study.at("cases"))
    {
      EXPECT_EQ(c["reference"], "series") << c.dump();
      std::ifstream  in(r.folder + "/cases/" + c["name"].get<std::string>() + "/summary.json");
      nlohmann::json summary;
      in >> summary;
      const double v = summary["metrics"]["top_centre_displacement_z"];
      EXPECT_NEAR(c["errors"]["top_centre_displacement_z"].get<double>(), (v - reference) / std::abs(reference), 1e-9)
        << c.dump();
      ++checked;
    }
  EXPECT_EQ(checked, 5u); // the three runs of the series against their own extrapolation, and the two cases
  // both cases are within the 50 % tolerance: one of them is the cheapest (by step time)
  EXPECT_TRUE(r.study.at("best").is_string()) << r.study.at("best").dump();

  // --only keeps the whole series (it is one reference) and the same measurement
  const auto one = run_study("study_series_only", source_path("tests/data/studies/series_small.prm"),
                             {"--jobs", "2", "--only", "xpbd"});
  ASSERT_EQ(one.exit_code, 0) << one.output;
  ASSERT_EQ(one.study.at("cases").size(), 4u);
  EXPECT_EQ(one.study.at("reference_series").at("runs").size(), 3u);
  EXPECT_EQ(one.study.at("cases").back().at("errors"), r.study.at("cases").back().at("errors"));
}

TEST(StudyRun, StitchParetoAtSmallSize)
{
  // the shipped study with the accurate reference on 3 mm hexahedra and the realtime
  // default on 2 mm tetrahedra (each through its path's model section, so the variants'
  // own meshes stay): about 90 s on 2 cores instead of 4 minutes
  const auto r = run_study("study_stitch_pareto", source_path("parameters/studies/stitch_pareto.prm"),
                           {"--jobs", "2", "--set",
                            "Model accurate/Mesh/Geo parameters=h: 0.003, hexahedra: 1, Wg: 0.0004", "--set",
                            "Model realtime/Mesh/Geo parameters=h: 0.002, hexahedra: 0, Wg: 0.0004"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  for (const char *file : {"cases.csv", "pareto.png", "pareto.pdf"})
    EXPECT_TRUE(fs::exists(fs::path(r.folder) / file)) << file;
  const auto &cases = r.study.at("cases");
  ASSERT_EQ(cases.size(), 12u); // the reference and every variant, none dropped
  unsigned punctured = 0;
  for (const auto &c : cases)
    {
      const std::string name = c["name"];
      if (name == "mass-spring-suture" || name == "surface-tissue")
        {
          // explicit variants past their own stability limit: failed rows that say so
          EXPECT_EQ(c["status"], "failed") << c.dump();
          EXPECT_NE(c["reason"].get<std::string>().find("dt_crit"), std::string::npos) << c.dump();
          continue;
        }
      ASSERT_TRUE(c["status"] == "completed" || c["status"] == "incomplete") << c.dump();
      // both paths puncture when the needle's force reaches the same threshold (0.7 N,
      // coupling/needle_puncture.h); what differs is the overshoot within one step
      for (const char *key : {"puncture_force_entry", "puncture_force_exit"})
        if (!c["errors"][key].is_null())
          {
            EXPECT_LT(std::abs(c["errors"][key].get<double>()), 0.05) << name << " " << key;
            ++punctured;
          }
    }
  EXPECT_GE(punctured, 16u); // entry and exit of the reference and seven variants at least
  // the default closes the wound, so its closure error is measured
  const auto def = std::find_if(cases.begin(), cases.end(), [](const auto &c) { return c["name"] == "default"; });
  ASSERT_NE(def, cases.end());
  EXPECT_EQ((*def)["status"], "completed") << def->dump();
  EXPECT_TRUE((*def)["errors"]["closure_tension"].is_number()) << def->dump();
  EXPECT_TRUE((*def)["errors"]["events.time"].is_number()) << def->dump();
}

TEST(StudyRun, MeshConvergenceStitchAtSmallSize)
{
  // three realtime meshes and the reference on 3 mm hexahedra (about 30 s)
  const auto r = run_study("study_mesh_convergence_stitch",
                           source_path("parameters/studies/mesh_convergence_stitch.prm"),
                           {"--jobs", "2", "--only", "rt-2mm,rt-1.8mm,rt-1.5mm", "--set",
                            "Model accurate/Mesh/Geo parameters=h: 0.003, hexahedra: 1, Wg: 0.0004"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_EQ(r.study.at("cases").size(), 4u); // --only: these three and their reference
  EXPECT_TRUE(fs::exists(fs::path(r.folder) / "convergence.csv"));
  EXPECT_TRUE(fs::exists(fs::path(r.folder) / "convergence.png"));
  std::map<std::string, nlohmann::json> series;
  for (const auto &s : r.study.at("convergence").at("series"))
    series[s["series"]] = s;
  ASSERT_EQ(series.size(), 2u);
  // the realtime series: coarse to fine, an order and an extrapolation from three sizes
  const auto &rt = series.at("realtime");
  ASSERT_EQ(rt["table"].size(), 3u);
  const std::vector<double> gmsh_h{0.002, 0.0018, 0.0015};
  for (std::size_t k = 0; k < 3; ++k)
    {
      const double h = rt["table"][k]["h"];
      // h = (V/N)^(1/3) of tetrahedra of edge a is a/(6 sqrt 2)^(1/3) = 0.49 a for regular ones
      EXPECT_GT(h / gmsh_h[k], 0.4) << rt.dump();
      EXPECT_LT(h / gmsh_h[k], 0.6) << rt.dump();
      EXPECT_TRUE(rt["table"][k]["value"].is_number()) << rt.dump();
    }
  EXPECT_TRUE(rt["observed_order"].is_number()) << rt.dump();
  EXPECT_TRUE(rt["extrapolated"].is_number()) << rt.dump();
  // the solver's effort per case: the accurate reference's from its summary.json, none
  // for the realtime cases
  for (const auto &c : r.study.at("cases"))
    {
      const auto &costs = c["costs"];
      if (c["name"] != "reference")
        {
          EXPECT_TRUE(costs["newton_per_step_max"].is_null()) << c.dump();
          EXPECT_TRUE(costs["failed_attempts"].is_null()) << c.dump();
          continue;
        }
      std::ifstream  in(r.folder + "/cases/reference/summary.json");
      nlohmann::json summary;
      in >> summary;
      unsigned most = 0;
      for (const auto &step : summary["steps"])
        most = std::max(most, step["newton_iterations"].get<unsigned>());
      EXPECT_GE(most, 2u); // the tightening needs iterations
      EXPECT_EQ(costs["newton_per_step_max"].get<double>(), most) << c.dump();
      EXPECT_EQ(costs["failed_attempts"].get<double>(), summary["solver"]["failed_attempts"].get<double>());
    }
  // the accurate series: the reference alone, no estimate from one size
  const auto &acc = series.at("accurate");
  ASSERT_EQ(acc["table"].size(), 1u);
  EXPECT_FALSE(acc.contains("observed_order"));
  // both paths mesh the same pad: their meshes' volumes agree
  std::ifstream ref(r.folder + "/cases/reference/summary.json"), fine(r.folder + "/cases/rt-1.5mm/summary.json");
  nlohmann::json a, b;
  ref >> a;
  fine >> b;
  EXPECT_NEAR(a["mesh"]["volume"].get<double>(), b["mesh"]["volume"].get<double>(), 1e-3 * b["mesh"]["volume"].get<double>());
}

TEST(StudyRun, ShippedStudiesValidate)
{
  // each is also run: the stitch studies at small size above, the others in their tests,
  // but for those docs/studies.md's table of shipped studies marks "validation only",
  // whose runs take from minutes to hours (the finest cases of the convergence series,
  // the accurate references of tearing_bite_spacing.prm); the small-size series
  // machinery is AResolutionSeriesReference... above
  for (const auto &entry : fs::directory_iterator(source_path("parameters/studies")))
    {
      std::string output;
      const int   code = run_logged({suturesim_binary(), "study", entry.path().string(), "--validate"},
                                  (scratch_path() / ("validate_" + entry.path().stem().string() + ".log")).string(),
                                  output);
      EXPECT_EQ(code, 0) << entry.path() << ": " << output;
    }
}
