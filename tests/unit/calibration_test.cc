// `suturesim calibrate` end to end (issue 28): the fit recovers known constants from a
// synthetic reference, and a bad calibration file is a one-line error at its line.
#include "run_scene.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

using namespace suturesim::test_support;
namespace fs = std::filesystem;

namespace
{
  struct Calibration
  {
    int            exit_code = -1;
    std::string    output;
    std::string    folder;
    nlohmann::json result; ///< calibration.json, when written
  };

  Calibration
  calibrate(const std::string &name, const std::string &file, const Args &args = {})
  {
    Calibration c;
    c.folder = (scratch_path() / name).string();
    fs::remove_all(c.folder);
    c.exit_code =
      run_logged(join({suturesim_binary(), "calibrate", file, "--output", c.folder}, args), c.folder + ".log", c.output);
    std::ifstream json(c.folder + "/calibration.json");
    if (json)
      json >> c.result;
    return c;
  }
} // namespace

TEST(Calibration, RecoversKnownVolumeScalesFromASyntheticReferenceToOnePercent)
{
  // the reference is the realtime volume model with spring scale 1.6 and volume scale
  // 0.55 (tests/data/calibration/synthetic_volume_scales.prm); the fit starts from 1, 3
  const auto c = calibrate("calibration_synthetic", source_path("tests/data/calibration/synthetic_volume_scales.prm"),
                           {"--jobs", "2"});
  ASSERT_EQ(c.exit_code, 0) << c.output;
  ASSERT_TRUE(c.result.is_object()) << c.output;
  const auto  &p        = c.result["parameters"];
  const double truth[2] = {1.6, 0.55}, start[2] = {1, 3};
  ASSERT_EQ(p.size(), 2u);
  for (int k = 0; k < 2; ++k)
    {
      const double fitted = p[k]["fitted"].get<double>();
      std::printf("[ calibration ] %s = %.9g (true %.9g), standard error %s\n",
                  p[k]["path"].get<std::string>().c_str(), fitted, truth[k], p[k]["standard_error"].dump().c_str());
      EXPECT_NEAR(fitted, truth[k], 0.01 * truth[k]);
      EXPECT_DOUBLE_EQ(p[k]["initial"].get<double>(), start[k]);
    }
  // the start was far off (the outside probe by more than 100 %), the fit is not
  const double before = c.result["objective"]["initial"].get<double>();
  const double after  = c.result["objective"]["fitted"].get<double>();
  EXPECT_GT(before, 0.1);
  EXPECT_LT(after, 1e-8 * before);
  EXPECT_GT(c.result["train"]["initial"]["probe.top_outside"].get<double>(), 0.5);
  EXPECT_LT(c.result["train"]["fitted"]["probes.max"].get<double>(), 1e-4);
  // the history has every run of the objective, the held-out case ran at both points
  EXPECT_EQ(c.result["history"].size(), c.result["optimiser"]["objective_runs"].get<std::size_t>());
  EXPECT_EQ(c.result["validation"]["fitted"]["finer"]["status"], "completed");
  EXPECT_EQ(c.result["validation"]["initial"]["finer"]["status"], "completed");
  for (const char *f : {"calibrated.prm", "calibration_history.png", "calibration_history.pdf", "calibration_errors.png",
                        "calibration_errors.pdf"})
    EXPECT_TRUE(fs::exists(fs::path(c.folder) / f)) << f;

  // the fragment, included by a scene, gives the run the fitted values
  const auto scene = scratch_path() / "calibration_synthetic_included.prm";
  {
    std::ofstream out(scene);
    out << "include " << source_path("benchmarks/block_patch_load/block_patch_load.prm") << "\n"
        << "include " << c.folder << "/calibrated.prm\n";
  }
  const auto run = run_suturesim("calibration_synthetic_included", {scene.string(), "--validate"});
  ASSERT_EQ(run.exit_code, 0) << run.output;
}

TEST(Calibration, ShippedCalibrationsAreValid)
{
  unsigned n = 0;
  for (const auto &e : fs::directory_iterator(source_path("parameters/calibration")))
    if (e.path().extension() == ".prm")
      {
        const auto c = calibrate("calibration_validate", e.path().string(), {"--validate"});
        EXPECT_EQ(c.exit_code, 0) << e.path() << "\n" << c.output;
        EXPECT_NE(c.output.find(": valid, "), std::string::npos) << c.output;
        ++n;
      }
  EXPECT_GE(n, 1u);
}

TEST(Calibration, BadCalibrationFilesAreOneLineErrorsAtTheirLine)
{
  const std::string base = source_path("benchmarks/block_patch_load/block_patch_load.prm");
  const auto        check = [&](const std::string &name, const std::string &calibration, const std::string &expected) {
    const auto file = scratch_path() / (name + ".prm");
    {
      std::ofstream out(file);
      out << "set Name = " << name << "\n"
          << "set Base scene = " << base << "\n"
          << "subsection Cases\n  set Settings = Model=realtime\n  set List = short: Time/End time=1\nend\n"
          << "subsection Metrics\n  set Probes = top_centre\nend\n"
          << "subsection Calibration\n"
          << calibration << "end\n";
    }
    const auto c = calibrate(name, file.string(), {"--validate"});
    EXPECT_EQ(c.exit_code, 2) << name << ": " << c.output;
    EXPECT_NE(c.output.find(file.string() + ":" + expected), std::string::npos) << name << ": " << c.output;
    EXPECT_EQ(std::count(c.output.begin(), c.output.end(), '\n'), 1) << c.output;
  };
  // line 11 is the first line inside subsection Calibration
  check("calibration_reversed_bounds", "  set Parameters = Realtime/volume/Spring stiffness scale: 1, 5, 0.1\n",
        "11: Calibration/Parameters: 'Realtime/volume/Spring stiffness scale': needs lower < upper");
  check("calibration_outside_bounds", "  set Parameters = Realtime/volume/Spring stiffness scale: 20, 0.1, 5\n",
        "11: Calibration/Parameters: 'Realtime/volume/Spring stiffness scale': needs lower < upper and the initial");
  check("calibration_unknown_path", "  set Parameters = Realtime/volume/Spring stiffnes scale: 1, 0.1, 5\n",
        "11: Calibration/Parameters: case 'bound'");
  check("calibration_out_of_range", "  set Parameters = Realtime/volume/Spring stiffness scale: 1, 1e-5, 5\n",
        "11: Calibration/Parameters: case 'bound'");
  check("calibration_unknown_weight",
        "  set Parameters = Realtime/volume/Spring stiffness scale: 1, 0.1, 5\n  set Weights = probe.top: 1\n",
        "12: Calibration/Weights: 'probe.top' is not one of the Metrics' error columns");
  // the study's --case-list (the driver's runs): a file that cannot be read is one line
  std::string output;
  const auto  missing = (scratch_path() / "calibration_no_such_list.txt").string();
  EXPECT_EQ(run_logged({suturesim_binary(), "study", source_path("parameters/calibration/volume_patch_load.prm"),
                        "--case-list", missing, "--validate"},
                       (scratch_path() / "calibration_case_list.log").string(), output),
            2);
  EXPECT_EQ(output, "error: study: --case-list " + missing + ": cannot be read\n");
  check("calibration_nothing_to_fit", "  set Validation = fine: Time/End time=1\n",
        "11: Calibration/Validation: needs Calibration/Parameters to fit");
}
