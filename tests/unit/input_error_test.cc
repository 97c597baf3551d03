// Malformed scenes (conventions.md §8, "expected failure"): every file in tests/data/bad
// names the fragment its one-line error must contain on its first line; the run must
// exit non-zero and leave no summary.json.
#include "run_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace suturesim::test_support;
namespace fs = std::filesystem;

namespace
{
  std::vector<std::string>
  bad_scenes()
  {
    std::vector<std::string> files;
    for (const auto &e : fs::directory_iterator(source_path("tests/data/bad")))
      files.push_back(e.path().filename().string());
    std::sort(files.begin(), files.end());
    return files;
  }

  std::string
  error_lines(const std::string &output)
  {
    std::string       lines;
    std::stringstream in(output);
    for (std::string line; std::getline(in, line);)
      if (!line.empty())
        lines += line + "\n";
    return lines;
  }
} // namespace

class BadScene : public ::testing::TestWithParam<std::string>
{};

TEST_P(BadScene, FailsWithOneLineNamingTheProblem)
{
  const std::string file = "tests/data/bad/" + GetParam();
  std::ifstream     in(source_path(file));
  std::string       first;
  std::getline(in, first);
  ASSERT_EQ(first.rfind("# expect: ", 0), 0u) << file << " lacks its '# expect:' line";
  const std::string expected = first.substr(10);

  // Run from the data folder so that messages carry the relative path "bad/x.prm".
  const auto r = run_suturesim(GetParam(), {"bad/" + GetParam()}, {"/usr/bin/env", "-C", source_path("tests/data")});
  EXPECT_EQ(r.exit_code, 2) << r.output; // main(): an InputError exits with 2
  EXPECT_FALSE(r.has_summary) << "a failed input left summary.json behind";
  const std::string lines = error_lines(r.output);
  EXPECT_EQ(std::count(lines.begin(), lines.end(), '\n'), 1) << "not one line:\n" << lines;
  EXPECT_EQ(lines.rfind("error: ", 0), 0u) << lines;
  EXPECT_NE(lines.find(expected), std::string::npos)
    << "expected '" << expected << "' in:\n" << lines;
}

INSTANTIATE_TEST_SUITE_P(InputErrors, BadScene, ::testing::ValuesIn(bad_scenes()),
                         [](const auto &info) {
                           return info.param.substr(0, info.param.find('.'));
                         });

TEST(InputErrors, EveryFileInTheBadFolderIsACase)
{
  // Every file in tests/data/bad is a scene (.prm) and a case of BadScene above (one
  // line naming the problem, exit 2, no summary.json). The count is the folder's as
  // of this commit: a case lost or added shows here and is counted on purpose.
  const auto  files = bad_scenes();
  std::size_t scenes = 0;
  for (const auto &f : files)
    scenes += fs::path(f).extension() == ".prm";
  EXPECT_EQ(scenes, files.size()) << "a file in tests/data/bad that is not a scene";
  const ::testing::TestSuite *suite = nullptr;
  const auto                 &unit  = *::testing::UnitTest::GetInstance();
  for (int k = 0; k < unit.total_test_suite_count(); ++k)
    if (std::string(unit.GetTestSuite(k)->name()) == "InputErrors/BadScene")
      suite = unit.GetTestSuite(k);
  ASSERT_NE(suite, nullptr);
  std::printf("[ input errors ] %zu malformed scenes in tests/data/bad, %d BadScene cases\n", files.size(),
              suite->total_test_count());
  EXPECT_EQ(static_cast<std::size_t>(suite->total_test_count()), files.size());
  EXPECT_EQ(files.size(), 184u);
}

namespace
{
  /// Runs suturesim with @p arguments into @p folder, whose file @p blocked is first made
  /// a link to /dev/full (refusing every write with ENOSPC, as a full disk does); expects
  /// exit 5 and exactly one error line, naming @p failing as not written. Returns the output.
  std::string
  expect_one_write_error(const fs::path &folder, const std::string &blocked, const std::string &failing,
                         std::vector<std::string> arguments)
  {
    fs::remove_all(folder);
    fs::create_directories(folder);
    fs::create_symlink("/dev/full", folder / blocked);
    arguments.insert(arguments.begin(), suturesim_binary());
    arguments.insert(arguments.end(), {"--output", folder.string()});
    std::string output;
    const int   code = run_logged(arguments, folder.string() + ".log", output);
    EXPECT_EQ(code, 5) << output;
    EXPECT_NE(output.find("error: " + (folder / failing).string() + ": cannot be written (No space left on device)"),
              std::string::npos)
      << output;
    std::size_t       errors = 0; // one error line, after the run's progress lines
    std::stringstream in(output);
    for (std::string line; std::getline(in, line);)
      errors += line.rfind("error", 0) == 0 || line.find("terminate") != std::string::npos;
    EXPECT_EQ(errors, 1u) << output;
    return output;
  }
} // namespace

// A write that fails ends the run with one line naming the file, exit 5, and no
// summary.json (io/checked_output.h). The failure is injected: summary.json's temporary
// file is a link to /dev/full, which refuses every write with ENOSPC as a full disk does.
// Before the writes were checked, such a run exited 0 with an empty summary.json.
TEST(InputErrors, AFailedWriteIsOneLineExitFiveAndNoSummary)
{
  const auto folder = scratch_path() / "failed_write";
  const auto output = expect_one_write_error(folder, "summary.json.tmp", "summary.json",
                                             {source_path("tests/data/cook_coarse.prm")});
  EXPECT_FALSE(fs::exists(folder / "summary.json")) << output;
  EXPECT_FALSE(fs::exists(folder / "summary.json.tmp")) << "the temporary file is left behind";
  // the rest of the run was written: the failure is the summary's alone
  EXPECT_TRUE(fs::exists(folder / "forces.csv"));
}

// The realtime path writes its .vtu and .pvd files on a writer thread
// (core/background_writer.h): a write that fails there (tissue.pvd's temporary file a
// link to /dev/full) still ends the run with the one line naming the file and exit 5:
// the haptic loop stops at the next tick.
TEST(InputErrors, AFailedWriteOnTheRealtimeWriterThreadIsOneLineExitFive)
{
  const auto folder = scratch_path() / "failed_realtime_write";
  expect_one_write_error(folder, "tissue.pvd.tmp", "tissue.pvd",
                         {benchmark_scene("realtime_seed004_scale"), "--set", "Time/End time=0.6"});
  // the first state's .vtu was written before its series failed, and the run stopped
  // there: no later state
  EXPECT_TRUE(fs::exists(folder / "tissue_00000.vtu"));
  EXPECT_FALSE(fs::exists(folder / "tissue.pvd"));
  EXPECT_FALSE(fs::exists(folder / "tissue_00001.vtu"));
}

TEST(InputErrors, UnwritableOutputFolder)
{
  // Under a regular file no folder can be made, even as root.
  const std::string blocked = source_path("tests/data/cook_coarse.prm") + "/out";
  std::string       out;
  const int         code = run_logged({suturesim_binary(), source_path("tests/data/cook_coarse.prm"), "--output", blocked},
                                      (scratch_path() / "unwritable_output.log").string(), out);
  EXPECT_GT(code, 0); // exited, and not with 0
  EXPECT_NE(out.find("error: --output " + blocked + ": cannot write"), std::string::npos) << out;
}

TEST(InputErrors, CholeskyRefusesTheFrictionalCoupledTangent)
{
  // The pierce points' friction on the thread makes the coupled tangent non-symmetric
  // (TissueNeedle::symmetric_tangent()), and MUMPS's Cholesky would factorise the mirror
  // of one triangle instead (tissue/linear_solver.h): forced, it is refused at setup.
  const Args pass = {source_path("parameters/needle_pass.prm"), "--set", "Model=accurate", "--set",
                     "Tissue/Linear solver/Factorization=cholesky"};
  const auto        r    = run_suturesim("cholesky_friction", pass);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_FALSE(r.has_summary);
  const std::string lines = error_lines(r.output);
  EXPECT_EQ(std::count(lines.begin(), lines.end(), '\n'), 1) << "not one line:\n" << lines;
  EXPECT_NE(lines.find("Tissue/Linear solver/Factorization"), std::string::npos) << lines;
  EXPECT_NE(lines.find("cholesky needs a symmetric tangent"), std::string::npos) << lines;
  // without friction the tangent is symmetric and Cholesky is taken
  const auto ok = run_suturesim("cholesky_frictionless", join(pass, {"--set", "Pierce points/Friction coefficient=0",
                                                                     "--set", "Time/End time=0.04"}));
  EXPECT_EQ(ok.exit_code, 0) << ok.output;
}

TEST(InputErrors, UnknownOverride)
{
  const auto r =
    run_suturesim("bad_override", {source_path("tests/data/cook_coarse.prm"), "--set", "Tissue/Elemnt degree=2"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_FALSE(r.has_summary);
  EXPECT_NE(r.output.find("--set \"Tissue/Elemnt degree=2\""), std::string::npos) << r.output;
}

TEST(InputErrors, EmptyOverridePath)
{
  const auto r = run_suturesim("empty_override", {source_path("tests/data/cook_coarse.prm"), "--set", "=1"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_NE(r.output.find("expected \"Subsection/Key=value\""), std::string::npos) << r.output;
}

// A folder given as the scene ran the all-defaults scene (issue 26): refused by name.
TEST(InputErrors, AFolderIsNoScene)
{
  const auto r = run_suturesim("folder_scene", {source_path("tests/data/bad_inputs")});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_FALSE(r.has_summary);
  EXPECT_NE(r.output.find("bad_inputs: is not a file"), std::string::npos) << r.output;
}

TEST(Validate, AcceptsEveryShippedScene)
{
  unsigned n = 0;
  for (const auto &e : fs::recursive_directory_iterator(source_path("parameters")))
    if (e.path().extension() == ".prm" && e.path().parent_path().filename() != "studies" &&
        e.path().parent_path().filename() != "calibration") // studies: StudyRun; calibrations: Calibration
      {
        const auto r = run_suturesim("validate", {"--validate", e.path().string()});
        EXPECT_EQ(r.exit_code, 0) << e.path() << "\n" << r.output;
        EXPECT_NE(r.output.find(": valid"), std::string::npos) << r.output;
        EXPECT_FALSE(fs::exists(r.directory)) << "--validate wrote output";
        ++n;
      }
  EXPECT_GE(n, 2u);
}

TEST(Validate, TheEmbeddedDefaultSceneIsTheInterruptedStitch)
{
  // issue 6: `suturesim` with no scene file runs parameters/stitch_interrupted.prm
  const auto r = run_suturesim("validate_default", {"--validate"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("<default scene stitch_interrupted.prm>: valid"), std::string::npos) << r.output;
}

TEST(Validate, RefusesTheAccuratePathsSpreadTouchInTheRealtimePathAndASpreadStoppedAtNoWound)
{
  // --validate refuses them as the run does (InputErrors/BadScene): a study's --validate
  // once passed a reference with Puncture/Touch radius that its realtime run refused; a
  // spread stopped at the wound was refused without its faces only where the accurate
  // stitch was built
  for (const std::string bad :
       {"realtime_touch_radius", "load_across_wound_without_faces", "load_across_wound_realtime_without_faces"})
    {
      const auto r = run_suturesim("validate_" + bad, {"--validate", source_path("tests/data/bad/" + bad + ".prm")});
      EXPECT_EQ(r.exit_code, 2) << bad << "\n" << r.output;
      EXPECT_NE(r.output.find(bad == "realtime_touch_radius" ? "Puncture/Touch radius: the realtime path"
                                                             : "Load across the wound: false needs the wound's faces"),
                std::string::npos)
        << r.output;
    }
}

TEST(Validate, RejectsUnknownKey)
{
  const auto r = run_suturesim("validate_bad", {"--validate", source_path("tests/data/bad/unknown_key.prm")});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.output.find("No entry with name <Element dgree>"), std::string::npos) << r.output;
}
