// deal.II step-44's problem (benchmarks/indentation_block): the top point's displacement
// after every load step against step-44's own values (reference.json, 1e-10 relative), and
// Newton iterations per step no more than step-44's + 1 with the mixed fields as Newton
// unknowns. The exact variant (p̃, J̃ recomputed from u) reaches the same solution, and
// so does the assembly over two threads.
#include "run_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <thread>

using namespace suturesim::test_support;

namespace
{
  /// top_centre_displacement_y after each load step (rows of forces.csv after t = 0)
  std::vector<double>
  top_displacement(const RunResult &r)
  {
    std::string       header;
    const auto        rows   = read_forces(r, &header);
    const std::size_t column = suturesim::test_support::column(header, "top_centre_displacement_y");
    std::vector<double> u;
    for (std::size_t i = 1; i < rows.size(); ++i)
      u.push_back(rows[i].at(column));
    return u;
  }
} // namespace

TEST(IndentationBlock, MatchesStep44AtEveryLoadStep)
{
  const auto r = run_suturesim("indentation_block", {benchmark_scene("indentation_block")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const auto  ref       = benchmark_reference("indentation_block");
  const auto &step44    = ref["step44"]["direct_static_condensation"];
  const auto  expected  = step44["top_displacement_y"].get<std::vector<double>>();
  const auto  newton44  = step44["newton_iterations"].get<std::vector<unsigned>>();
  const auto  tolerance = ref["tolerance"]["relative"].get<double>();
  const auto  extra     = ref["tolerance"]["newton_extra_iterations"].get<unsigned>();

  const auto u = top_displacement(r);
  ASSERT_EQ(u.size(), expected.size()) << "one row per load step, no cut-backs";
  for (std::size_t k = 0; k < u.size(); ++k)
    {
      std::printf("step %2zu: u_y = %.16e m, step-44 %.16e m, relative difference %.1e\n", k + 1, u[k], expected[k],
                  std::abs(u[k] / expected[k] - 1));
      EXPECT_NEAR(u[k], expected[k], tolerance * std::abs(expected[k])) << "load step " << k + 1;
    }
  const auto &steps = r.summary["steps"];
  ASSERT_EQ(steps.size(), newton44.size() + 1) << "the initial state and ten load steps";
  for (std::size_t k = 0; k < newton44.size(); ++k)
    {
      const auto &s = steps[k + 1];
      EXPECT_LE(s["newton_iterations"].get<unsigned>(), newton44[k] + extra) << "load step " << k + 1;
      EXPECT_EQ(s["line_search_backtracks"].get<unsigned>(), 0u) << "load step " << k + 1;
      EXPECT_EQ(s["cutbacks"].get<unsigned>(), 0u) << "load step " << k + 1;
    }
}

TEST(IndentationBlock, BothMixedUpdatesReachTheSameSolution)
{
  // one global refinement (8 cells) keeps this quick; the exact variant needs line search
  // and backtracking here, the Newton-unknown variant does not
  const Args coarse = {benchmark_scene("indentation_block"), "--set", "Mesh/Global refinements=1"};
  const auto newton = run_suturesim("indentation_block_newton", coarse);
  const auto exact  = run_suturesim("indentation_block_exact", join(coarse, {"--set", "Tissue/Mixed update=exact"}));
  ASSERT_EQ(newton.exit_code, 0) << newton.output;
  ASSERT_EQ(exact.exit_code, 0) << exact.output;
  const auto a = top_displacement(newton), b = top_displacement(exact);
  ASSERT_EQ(a.size(), 10u);
  ASSERT_EQ(b.size(), a.size());
  for (std::size_t k = 0; k < a.size(); ++k)
    EXPECT_NEAR(a[k], b[k], 1e-10 * std::abs(a[k])) << "load step " << k + 1;
  const double last = benchmark_reference("indentation_block")["step44"]["other_refinements"]["1"].get<double>();
  EXPECT_NEAR(a.back(), last, 1e-9 * std::abs(last)) << "step-44 at one global refinement";
  EXPECT_LT(newton.summary["solver"]["newton_iterations_total"].get<unsigned>(),
            exact.summary["solver"]["newton_iterations_total"].get<unsigned>());
  // the factorisation's memory as MUMPS estimated it before (the resource guard's) and made it
  const double estimate = newton.summary["solver"]["factorization_memory_estimate"];
  EXPECT_GT(estimate, 0);
  EXPECT_LE(estimate, newton.summary["solver"]["factorization_memory"].get<double>());
}

TEST(IndentationBlock, TwoThreadsGiveTheOneThreadResult)
{
  // The assembly over two threads (--threads 2, tissue_assembly.cc) adds the cells'
  // contributions in the same order; what differs is deal.II's cell-similarity shortcut,
  // which it switches off with threads: round-off, and the same Newton path.
  if (std::thread::hardware_concurrency() < 2)
    GTEST_SKIP() << "one core";
  // step-44's resolution: 64 cells, so that both threads get cells (WorkStream hands out
  // chunks of 8)
  const std::string scene = benchmark_scene("indentation_block");
  const auto one = run_suturesim("indentation_block_1_thread", {scene});
  const auto two = run_suturesim("indentation_block_2_threads", {scene, "--threads", "2"});
  ASSERT_EQ(one.exit_code, 0) << one.output;
  ASSERT_EQ(two.exit_code, 0) << two.output;
  EXPECT_EQ(one.summary["threads"].get<unsigned>(), 1u);
  EXPECT_EQ(two.summary["threads"].get<unsigned>(), 2u);
  const auto a = top_displacement(one), b = top_displacement(two);
  ASSERT_EQ(a.size(), 10u);
  ASSERT_EQ(b.size(), a.size());
  for (std::size_t k = 0; k < a.size(); ++k)
    {
      EXPECT_NEAR(a[k], b[k], 1e-13 * std::abs(a[k])) << "load step " << k + 1;
      EXPECT_EQ(one.summary["steps"][k + 1]["newton_iterations"], two.summary["steps"][k + 1]["newton_iterations"]);
    }
}
