// The tissue's linear solvers (tissue/linear_solver.h; `Tissue/Linear solver`): the
// iterative ones the README recommends above 5e4 DoFs — CG and GMRES with smoothed
// aggregation (PETSc GAMG, the rigid-body modes as near null space) or hypre's
// BoomerAMG — give the Newton solution of the direct factorisation. The block is the
// accurate scenes' dermis (neo-Hookean, mu = 2.22 MPa, K = 29.6 MPa, nu = 0.46) in their
// Q1-P0 mixed formulation, fixed at the bottom and pressed and sheared on top.
#include "block_model.h"

#include <deal.II/lac/vector.h>

#include <gtest/gtest.h>

#include <cstdio>

using namespace suturesim;

namespace
{
  struct Solved
  {
    dealii::Vector<double> u;
    tissue::NewtonReport   report;
  };

  Solved
  solve_block(const std::string &method, const std::string &preconditioner)
  {
    test_support::BlockModel block(" set Element degree = 1\n set Formulation = mixed\n"
                                   " subsection Linear solver\n  set Method = " + method +
                                     "\n  set Preconditioner = " + preconditioner +
                                     "\n end\n"
                                     " subsection Material\n  set Model = neo-Hookean\n  set Bulk modulus = 29.6e6\n"
                                     "  subsection neo-Hookean\n   set Shear modulus = 2.22e6\n  end\n end\n"
                                     " subsection Boundary conditions\n  set Fixed = bottom\n  set Traction = top\n"
                                     "  subsection Traction function\n"
                                     "   set Function expression = 1e5 * t; 0; -2e5 * t\n  end\n end\n",
                                   dealii::Point<3>(0.02, 0.02, 0.01), {12, 12, 6});
    Solved s;
    s.report = block.model->solve_static(1.0);
    s.u      = dealii::Vector<double>(block.model->displacement());
    return s;
  }
} // namespace

TEST(LinearSolver, KrylovMethodsWithAlgebraicMultigridGiveTheDirectSolution)
{
  const Solved direct = solve_block("direct", "gamg");
  ASSERT_TRUE(direct.report.converged) << direct.report.failure;
  const double size = direct.u.linfty_norm();
  std::printf("[ linear solver ] %u DoFs, |u|_max = %.4e m; direct: %u Newton iterations\n", direct.u.size(), size,
              direct.report.iterations);
  EXPECT_GT(size, 1e-4); // a few per cent strain: the solve has something to do
  unsigned compared = 0;
  for (const auto &[method, preconditioner] : std::vector<std::pair<std::string, std::string>>{
         {"cg", "gamg"}, {"gmres", "gamg"}, {"cg", "boomeramg"}, {"gmres", "boomeramg"}})
    {
      const Solved s = solve_block(method, preconditioner);
      ASSERT_TRUE(s.report.converged) << method << "+" << preconditioner << ": " << s.report.failure;
      dealii::Vector<double> difference = s.u;
      difference -= direct.u;
      const double error = difference.linfty_norm() / size;
      std::printf("[ linear solver ] %s + %s: %u Newton iterations, %u Krylov iterations in all, "
                  "|u - u_direct|_max / |u|_max = %.2e\n",
                  method.c_str(), preconditioner.c_str(), s.report.iterations, s.report.linear_iterations, error);
      // Newton stops at 1e-9 of the first residual (Tissue/Newton defaults) whichever the
      // solver, the Krylov solves at 1e-2 of that: the solutions agree to the Newton
      // tolerance (measured 2.6e-12 to 1.0e-11, 2026-11-25: the last update is quadratic)
      EXPECT_LT(error, 1e-9) << method << " + " << preconditioner;
      EXPECT_GT(s.report.linear_iterations, 0u);
      ++compared;
    }
  EXPECT_EQ(compared, 4u);
}
