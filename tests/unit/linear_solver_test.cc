// The tissue's linear solvers (tissue/linear_solver.h; `Tissue/Linear solver`): the
// iterative ones the README recommends above 5e4 DoFs — CG and GMRES with smoothed
// aggregation (PETSc GAMG, the rigid-body modes as near null space) or hypre's
// BoomerAMG — give the Newton solution of the direct factorisation. The block is the
// accurate scenes' dermis (neo-Hookean, mu = 2.22 MPa, K = 29.6 MPa, nu = 0.46) in their
// Q1-P0 mixed formulation, fixed at the bottom and pressed and sheared on top.
#include "block_model.h"

#include <suturesim/core/error.h>
#include <suturesim/tissue/linear_solver.h>

#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/lac/vector.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <string>

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

// The direct method's resource guard (LinearSolver::check_memory()): MUMPS's analysis
// estimates the factorisation's memory before it is made, and a limit below it refuses
// the solve as bad input naming Tissue/Linear solver/Maximum memory. The estimate is
// checked against what the factorisation then allocated (INFOG(19)): MUMPS allocates
// what its analysis estimated (measured equal here, 15 MB), so an estimate read from the
// wrong entry or in the wrong unit falls outside [1/2, 1].
TEST(LinearSolver, TheFactorisationsMemoryIsEstimatedBeforeItIsMadeAndBounded)
{
  const std::string tissue = " set Element degree = 1\n set Formulation = mixed\n"
                             " subsection Material\n  set Model = neo-Hookean\n  set Bulk modulus = 29.6e6\n"
                             "  subsection neo-Hookean\n   set Shear modulus = 2.22e6\n  end\n end\n"
                             " subsection Boundary conditions\n  set Fixed = bottom\n  set Traction = top\n"
                             "  subsection Traction function\n"
                             "   set Function expression = 0; 0; -2e5 * t\n  end\n end\n";
  const dealii::Point<3>      upper(0.02, 0.02, 0.01);
  const std::vector<unsigned> cells{12, 12, 6};
  double                      estimate = 0;
  {
    test_support::BlockModel block(tissue, upper, cells);
    ASSERT_TRUE(block.model->solve_static(1.0).converged);
    const auto &stats = block.model->linear_solver().statistics();
    estimate          = stats.factorization_memory_estimate;
    std::printf("[ linear solver ] factorisation memory: %.3g B estimated by MUMPS's analysis, %.3g B allocated\n",
                estimate, stats.factorization_memory);
    ASSERT_GT(stats.factorization_memory, 0);
    EXPECT_LE(estimate, stats.factorization_memory);
    EXPECT_GE(estimate, 0.5 * stats.factorization_memory);
  }
  std::ostringstream limit;
  limit << " subsection Linear solver\n  set Maximum memory = " << 0.5 * estimate << "\n end\n";
  test_support::BlockModel block(tissue + limit.str(), upper, cells);
  std::string              message;
  try
    {
      block.model->solve_static(1.0);
    }
  catch (const InputError &e)
    {
      message = e.what();
    }
  std::printf("[ linear solver ] with half of it as the limit: %s\n", message.c_str());
  EXPECT_NE(message.find("Maximum memory: MUMPS's analysis estimates"), std::string::npos) << message;
  EXPECT_NE(message.find("above this limit"), std::string::npos) << message;
}

namespace
{
  /// The rows of [0, n) this process owns: an even split.
  dealii::IndexSet
  owned_rows(const unsigned n)
  {
    const unsigned  rank = dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD);
    const unsigned  size = dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
    dealii::IndexSet owned(n);
    owned.add_range(n * rank / size, n * (rank + 1) / size);
    return owned;
  }
} // namespace

namespace
{
  /// @p A as the tridiagonal pattern on [0, n), the rows @p owned on this process.
  void
  tridiagonal(dealii::PETScWrappers::MPI::SparseMatrix &A, const dealii::IndexSet &owned, const unsigned n)
  {
    dealii::DynamicSparsityPattern dsp(n, n, owned);
    for (const auto i : owned)
      for (unsigned j = (i > 0 ? i - 1 : 0); j <= std::min<unsigned>(i + 1, n - 1); ++j)
        dsp.add(i, j);
    A.reinit(owned, owned, dsp, MPI_COMM_WORLD);
  }

  /// The stencil (−1 − c, 2, −1 + c) on [0, n), with row and column @p zero (< n) set to
  /// stored zeros when @p zero < n: the same pattern, numerically singular.
  void
  fill_stencil(dealii::PETScWrappers::MPI::SparseMatrix &A, const dealii::IndexSet &owned,
               const unsigned n, const double c, const unsigned zero)
  {
    for (const auto i : owned)
      for (unsigned j = (i > 0 ? i - 1 : 0); j <= std::min<unsigned>(i + 1, n - 1); ++j)
        {
          const double value = j == i ? 2.0 : (j < i ? -1.0 - c : -1.0 + c);
          A.set(i, j, (i == zero || j == zero) ? 0.0 : value);
        }
    A.compress(dealii::VectorOperation::insert);
  }
} // namespace

// A factorisation that fails says why in MUMPS's terms, and does not spoil the next
// one: MUMPS keeps a failed factorisation's INFOG(1) < 0, and PETSc then skips every
// numerical factorisation of that analysis, so before LinearSolver::factorize() started
// again from the analysis, a matrix that failed once failed at every cut-back of the
// step whatever its values (the stitch's L2, docs/interrupted_stitch.md). Here a
// singular matrix, then the regular one with the same pattern; Cholesky and LU.
TEST(LinearSolver, AFailedFactorisationSaysWhyAndDoesNotSpoilTheNext)
{
  const unsigned         n     = 60;
  const dealii::IndexSet owned = owned_rows(n);
  for (const double c : {0.3, 0.0})
    {
      dealii::PETScWrappers::MPI::SparseMatrix A;
      tridiagonal(A, owned, n);
      tissue::LinearSolver::Parameters prm;
      tissue::LinearSolver             solver(prm, MPI_COMM_WORLD);
      solver.set_symmetric(c == 0);
      dealii::PETScWrappers::MPI::Vector x(owned, MPI_COMM_WORLD), b(x), residual(x);
      for (const auto i : owned)
        b(i) = 1.0 + std::sin(i + 1.0);
      b.compress(dealii::VectorOperation::insert);

      fill_stencil(A, owned, n, c, n / 2);
      std::string message;
      try
        {
          solver.solve(A, x, b);
        }
      catch (const SolverError &e)
        {
          message = e.what();
        }
      std::printf("[ linear solver ] c = %.1f, singular: %s\n", c, message.c_str());
      EXPECT_NE(message.find("numerically singular (INFOG(1) = -10"), std::string::npos) << message;

      fill_stencil(A, owned, n, c, n);
      // the same pattern, now regular, in the same solver: no throw, and it is solved
      ASSERT_NO_THROW(solver.solve(A, x, b)) << "c = " << c;
      A.vmult(residual, x);
      residual -= b;
      EXPECT_LT(residual.linfty_norm(), 1e-12 * b.linfty_norm()) << "c = " << c;
    }
}

// The coupled iteration's 3 m solves with one factorisation go to MUMPS in one call
// (LinearSolver::solve_columns): each column must be the solution solve() gives it.
// The matrix is a 1-D convection–diffusion stencil (−1 − c, 2, −1 + c), non-symmetric
// for c ≠ 0 so that LU runs, and symmetric for c = 0 (Cholesky).
TEST(LinearSolver, ManyRightHandSidesInOneCallGiveTheColumnByColumnSolutions)
{
  const unsigned         n     = 120;
  const dealii::IndexSet owned = owned_rows(n);
  for (const double c : {0.3, 0.0})
    for (const std::string method : {"direct", "gmres"})
      {
        dealii::PETScWrappers::MPI::SparseMatrix A;
        tridiagonal(A, owned, n);
        fill_stencil(A, owned, n, c, n);

        tissue::LinearSolver::Parameters prm;
        prm.method         = method;
        prm.preconditioner = "jacobi";
        tissue::LinearSolver solver(prm, MPI_COMM_WORLD);
        solver.set_symmetric(c == 0);

        const unsigned                                      columns = 7;
        std::vector<dealii::PETScWrappers::MPI::Vector> B(columns, dealii::PETScWrappers::MPI::Vector(owned, MPI_COMM_WORLD));
        std::vector<dealii::PETScWrappers::MPI::Vector> X(B), reference(B);
        for (unsigned k = 0; k < columns; ++k)
          {
            for (const auto i : owned)
              B[k](i) = std::sin((k + 1.0) * (i + 1.0));
            B[k].compress(dealii::VectorOperation::insert);
            solver.solve(A, reference[k], B[k], 0, 1e-13);
          }
        solver.solve_columns(A, X, B, 1e-13);
        double worst = 0;
        for (unsigned k = 0; k < columns; ++k)
          {
            dealii::PETScWrappers::MPI::Vector difference = X[k];
            difference -= reference[k];
            worst = std::max(worst, difference.linfty_norm() / reference[k].linfty_norm());
            // and the column solves the system: |A x − b| against |b|
            dealii::PETScWrappers::MPI::Vector residual(owned, MPI_COMM_WORLD);
            A.vmult(residual, X[k]);
            residual -= B[k];
            // (GMRES stops at a relative 2-norm: |r|_inf <= tol |b|_2 <= tol sqrt(n) |b|_inf)
            const double bound = method == "direct" ? 1e-12 : prm.tolerance * std::sqrt(double(n));
            EXPECT_LT(residual.linfty_norm(), bound * B[k].linfty_norm()) << method << ", c = " << c << ", column " << k;
          }
        std::printf("[ linear solver ] %s, c = %.1f: %u columns in one call against one by one: %.2e\n",
                    method.c_str(), c, columns, worst);
        // the direct solve's two paths run the same factors (round-off apart); the Krylov
        // fallback is the same loop as solve()
        EXPECT_LT(worst, 1e-12) << method << ", c = " << c;
      }
}
