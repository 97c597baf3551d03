// The default scene's mesh path (gmsh .geo at run time, physical names, slit) on a
// coarse resolution: the outputs of the contract exist, and the reactions balance
// (no body force: the fixed bottom and the retracted wound face carry equal and
// opposite forces).
#include "run_scene.h"

#include <gtest/gtest.h>

#include <filesystem>

using namespace suturesim::test_support;
namespace fs = std::filesystem;

TEST(SkinPad, CoarsePullWritesTheOutputContractAndBalances)
{
  const auto r = run_suturesim("skin_pad", {source_path("parameters/skin_pad_pull.prm"), "--set",
                                            "Mesh/Geo parameters=h: 0.005", "--set", "Tissue/Element degree=1",
                                            "--set", "Time/Step size=0.5"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.summary["status"], "completed");
  EXPECT_EQ(r.summary["model"], "accurate");
  EXPECT_TRUE(r.summary.contains("commit"));
  EXPECT_TRUE(r.summary["timings"].contains("linear solve"));
  for (const auto *f : {"parameters.prm", "forces.csv", "tissue.pvd", "tissue_00000.vtu",
                        "tissue_00002.vtu", "mesh.msh"})
    EXPECT_TRUE(fs::exists(fs::path(r.directory) / f)) << f;

  const auto bottom = r.summary["metrics"]["reaction_force"]["bottom"];
  const auto wound  = r.summary["metrics"]["reaction_force"]["wound_left"];
  // Retracting the left lip in -x: the support pulls the tissue in -x.
  EXPECT_LT(wound[0].get<double>(), 0.0);
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(bottom[d].get<double>() + wound[d].get<double>(), 0.0,
                1e-6 * std::abs(wound[0].get<double>()));
  // The right lip stays behind: the wound opens.
  const auto left  = r.summary["metrics"]["probes"]["wound_left_top"];
  const auto right = r.summary["metrics"]["probes"]["wound_right_top"];
  // (the probe sits 1 um inside the face, where u_x differs by |du/dx| * 1 um < 1e-7 m)
  EXPECT_NEAR(left[0].get<double>(), -0.001, 1e-7);
  EXPECT_GT(right[0].get<double>() - left[0].get<double>(), 5e-4);
}
