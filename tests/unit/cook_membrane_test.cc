// Cook's membrane (benchmarks/cook_membrane; deal.II code gallery, Pelteret & McBride
// 2016): the published tip displacements (values and tolerance from the folder's
// reference.json), quadratic Newton convergence, the same answer from two MPI processes,
// reactions. The nearly incompressible variant (locking) is cook_locking_test.cc.
#include "run_scene.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace suturesim::test_support;

namespace
{
  RunResult
  cook(const std::string &name, const unsigned n, const unsigned degree, const Args &extra = {},
       const Args &launcher = {})
  {
    return run_suturesim(name,
                         join({benchmark_scene("cook_membrane"), "--set",
                               "Mesh/Elements per edge=" + std::to_string(n), "--set",
                               "Tissue/Element degree=" + std::to_string(degree)},
                              extra),
                         launcher);
  }

  double
  tip_mm(const RunResult &r)
  {
    return 1e3 * r.summary["metrics"]["tip_displacement_y"].get<double>();
  }

  /// The run's tip displacement against the code gallery's published value for its
  /// element degree and mesh, within the tolerance of benchmarks/cook_membrane/reference.json.
  void
  expect_published(const RunResult &r)
  {
    const auto        ref       = benchmark_reference("cook_membrane");
    const auto       &published = ref["published"];
    const auto        meshes    = published["elements_per_edge"].get<std::vector<unsigned>>();
    const unsigned    n         = std::stoul(run_parameter(r, "Mesh/Elements per edge"));
    const std::string element   = "Q" + run_parameter(r, "Tissue/Element degree");
    const auto        at        = std::find(meshes.begin(), meshes.end(), n);
    ASSERT_NE(at, meshes.end()) << "no published value for n = " << n;
    const double u = 1e3 * published[element][at - meshes.begin()].get<double>();
    std::printf("Cook's membrane %s, n = %u: %.4f mm, published %.2f mm\n", element.c_str(), n, tip_mm(r), u);
    EXPECT_NEAR(tip_mm(r), u, ref["tolerance"]["relative"].get<double>() * u) << element << ", n = " << n;
  }
} // namespace

// Published tip displacements of the code gallery (benchmarks/cook_membrane/reference.json)
TEST(CookMembrane, PublishedTipDisplacementQ2)
{
  const auto r = cook("cook_q2_8", 8, 2);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_published(r);
}

TEST(CookMembrane, PublishedTipDisplacementQ2Default)
{
  // the scene as shipped (Q2, 16 elements per edge)
  const auto r = run_suturesim("cook_default", {benchmark_scene("cook_membrane")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_published(r);
}

TEST(CookMembrane, PublishedTipDisplacementQ1)
{
  const auto r = cook("cook_q1_8", 8, 1);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  expect_published(r);
}

TEST(CookMembrane, NewtonConvergesQuadratically)
{
  const auto r = cook("cook_newton", 8, 2, {"--set", "Tissue/Newton/Line search=false"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  unsigned checked = 0;
  for (const auto &step : r.summary["steps"])
    {
      const auto res = step["residual_norms"].get<std::vector<double>>();
      if (res.size() < 4)
        continue;
      // Quadratic: log(r_{k+1}/r_0) ≈ 2 log(r_k/r_0) once in the asymptotic range. Check
      // the last pair whose successor is above round-off (1e-12 r_0).
      const double r0 = res[0];
      for (std::size_t k = 1; k + 1 < res.size(); ++k)
        if (res[k] < 1e-2 * r0 && res[k + 1] > 1e-12 * r0)
          {
            const double order = std::log(res[k + 1] / r0) / std::log(res[k] / r0);
            EXPECT_GE(order, 1.8) << "residuals " << step["residual_norms"].dump();
            ++checked;
          }
    }
  EXPECT_GE(checked, 5u) << "too few asymptotic iterations to judge";
}

TEST(CookMembrane, TwoMpiProcessesGiveTheSerialResult)
{
  const auto serial = cook("cook_serial", 8, 2);
  const auto parallel =
    cook("cook_mpi", 8, 2, {}, mpi_launcher(2));
  ASSERT_EQ(serial.exit_code, 0) << serial.output;
  ASSERT_EQ(parallel.exit_code, 0) << parallel.output;
  EXPECT_EQ(parallel.summary["mpi_processes"], 2);
  EXPECT_NEAR(tip_mm(parallel), tip_mm(serial), 1e-8 * tip_mm(serial));
  const auto fs = serial.summary["metrics"]["reaction_force"]["left"];
  const auto fp = parallel.summary["metrics"]["reaction_force"]["left"];
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(fp[d].get<double>(), fs[d].get<double>(), 1e-8);
}

TEST(CookMembrane, ReactionBalancesTheTraction)
{
  const auto r = cook("cook_reaction", 4, 1);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // The clamped face carries the whole 1 N load: R_y = -1 N, R_x = 0 (equilibrium).
  const auto f = r.summary["metrics"]["reaction_force"]["left"];
  EXPECT_NEAR(f[1].get<double>(), -1.0, 1e-9);
  EXPECT_NEAR(f[0].get<double>(), 0.0, 1e-9);
}

TEST(Reactions, OnlyConstrainedComponentsAndEachDofOnce)
{
  // Left clamped and u_z = 0 on both z faces: the z faces carry no in-plane force, the
  // clamped face carries the whole 1 N, each DoF counted for the first boundary only.
  const auto r = run_suturesim("reactions_masked",
                               {source_path("tests/data/cook_coarse.prm"), "--set",
                                "Tissue/Boundary conditions/Fixed=left, back:z, front:z"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto &f = r.summary["metrics"]["reaction_force"];
  for (const char *face : {"back", "front"})
    {
      EXPECT_EQ(f[face][0].get<double>(), 0.0) << face;
      EXPECT_EQ(f[face][1].get<double>(), 0.0) << face;
    }
  EXPECT_NEAR(f["left"][1].get<double>(), -1.0, 1e-9);
  EXPECT_NEAR(f["back"][2].get<double>() + f["front"][2].get<double>() + f["left"][2].get<double>(),
              0.0, 1e-9);
}

TEST(Reactions, IndependentOfThePartition)
{
  // Skin pad with a slit, 1 and 5 MPI processes. Before the reaction DoFs were taken
  // from the constraints, this case gave -158.7 N on 5 ranks against -221.65 N serial.
  const Args args = {source_path("parameters/skin_pad_pull.prm"),
                     "--set",
                     "Mesh/Geo parameters=h: 0.003",
                     "--set",
                     "Tissue/Element degree=1",
                     "--set",
                     "Time/Step size=1"};
  const auto serial   = run_suturesim("reactions_np1", args);
  const auto parallel = run_suturesim("reactions_np3", args, mpi_launcher(5));
  ASSERT_EQ(serial.exit_code, 0) << serial.output;
  ASSERT_EQ(parallel.exit_code, 0) << parallel.output;
  for (const char *b : {"bottom", "wound_left"})
    for (int d = 0; d < 3; ++d)
      {
        const double s = serial.summary["metrics"]["reaction_force"][b][d].get<double>();
        const double p = parallel.summary["metrics"]["reaction_force"][b][d].get<double>();
        EXPECT_NEAR(p, s, 1e-8 * std::abs(serial.summary["metrics"]["reaction_force"][b][0].get<double>()))
          << b << " " << d;
      }
}
