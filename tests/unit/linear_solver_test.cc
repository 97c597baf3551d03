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

#include <Eigen/LU>
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
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

// A Newton iteration that reuses an earlier tangent's factorisation
// (LinearSolver::solve_reusing(); Tissue/Linear solver/Reuse iterations) solves the
// current system (A + U W Uᵀ) x = b to its tolerance: GMRES preconditioned with the
// kept factor of A₀, extended exactly by the current low-rank term (Woodbury, Z₀ = A₀⁻¹U
// kept or solved again for a new U). Checked on the stencil above (c = 0.3: LU, c = 0:
// Cholesky) perturbed as a tangent is from one iteration to the next, against
// the system's residual and against the solution of a fresh factorisation of A + U W Uᵀ
// by Woodbury with A's own factor; an unchanged matrix takes one iteration (the
// preconditioner is then the exact inverse), and a matrix far from A₀ is refused
// (false) rather than solved loosely.
namespace
{
  /// x = (A + U W Uᵀ)⁻¹ b by Woodbury with a fresh factorisation of A.
  dealii::PETScWrappers::MPI::Vector
  woodbury_reference(const dealii::PETScWrappers::MPI::SparseMatrix        &A,
                     const std::vector<dealii::PETScWrappers::MPI::Vector> &U,
                     const Eigen::MatrixXd &W, const dealii::PETScWrappers::MPI::Vector &b, const bool symmetric)
  {
    tissue::LinearSolver::Parameters prm;
    tissue::LinearSolver             solver(prm, MPI_COMM_WORLD);
    solver.set_symmetric(symmetric);
    dealii::PETScWrappers::MPI::Vector              x(b);
    std::vector<dealii::PETScWrappers::MPI::Vector> Z(U);
    solver.solve(A, x, b);
    solver.solve_columns(A, Z, U);
    const auto      k = static_cast<Eigen::Index>(U.size());
    Eigen::MatrixXd UZ(k, k);
    Eigen::VectorXd Ux(k);
    for (Eigen::Index i = 0; i < k; ++i)
      {
        Ux[i] = U[i] * x;
        for (Eigen::Index j = 0; j < k; ++j)
          UZ(i, j) = U[i] * Z[j];
      }
    const Eigen::VectorXd c = (Eigen::MatrixXd::Identity(k, k) + W * UZ).partialPivLu().solve(W * Ux);
    for (Eigen::Index j = 0; j < k; ++j)
      x.add(-c[j], Z[j]);
    return x;
  }

  /// |(A + U W Uᵀ) x − b|₂
  double
  low_rank_residual(const dealii::PETScWrappers::MPI::SparseMatrix        &A,
                    const std::vector<dealii::PETScWrappers::MPI::Vector> &U, const Eigen::MatrixXd &W,
                    const dealii::PETScWrappers::MPI::Vector &x, const dealii::PETScWrappers::MPI::Vector &b)
  {
    dealii::PETScWrappers::MPI::Vector r(b);
    A.vmult(r, x);
    Eigen::VectorXd Ux(static_cast<Eigen::Index>(U.size()));
    for (std::size_t i = 0; i < U.size(); ++i)
      Ux[static_cast<Eigen::Index>(i)] = U[i] * x;
    const Eigen::VectorXd c = W * Ux;
    for (std::size_t i = 0; i < U.size(); ++i)
      r.add(c[static_cast<Eigen::Index>(i)], U[i]);
    r -= b;
    return r.l2_norm();
  }
} // namespace

TEST(LinearSolver, AKeptFactorisationSolvesTheNextTangentToTheSameTolerance)
{
  const unsigned         n     = 120;
  const dealii::IndexSet owned = owned_rows(n);
  for (const double c : {0.3, 0.0})
    {
      const bool                               symmetric = c == 0;
      // the stencil shifted to a condition number of about 10, so that the tolerance
      // below is far above round-off
      dealii::PETScWrappers::MPI::SparseMatrix A;
      tridiagonal(A, owned, n);
      fill_stencil(A, owned, n, c, n);
      for (const auto i : owned)
        A.add(i, i, 0.5);
      A.compress(dealii::VectorOperation::add);
      tissue::LinearSolver::Parameters prm;
      prm.reuse_iterations = 20;
      prm.tolerance        = 1e-13; // GMRES's relative tolerance: the absolute one below decides
      tissue::LinearSolver solver(prm, MPI_COMM_WORLD);
      solver.set_symmetric(symmetric);
      EXPECT_FALSE(solver.can_reuse()); // nothing factorised yet

      // six columns of U with support spread over the rows, a W like a condensed
      // body's stiffness (symmetric, or not with c ≠ 0)
      std::vector<dealii::PETScWrappers::MPI::Vector> U(6, dealii::PETScWrappers::MPI::Vector(owned, MPI_COMM_WORLD));
      for (unsigned k = 0; k < U.size(); ++k)
        {
          for (const auto i : owned)
            U[k](i) = std::exp(-0.01 * std::pow(double(i) - 20.0 * k - 10.0, 2));
          U[k].compress(dealii::VectorOperation::insert);
        }
      Eigen::MatrixXd W(6, 6);
      for (Eigen::Index i = 0; i < 6; ++i)
        for (Eigen::Index j = 0; j < 6; ++j)
          W(i, j) = 0.1 * std::cos(1.0 + i + 2.0 * j) + (i == j ? 0.5 : 0.0);
      if (symmetric)
        W = (0.5 * (W + W.transpose())).eval();
      dealii::PETScWrappers::MPI::Vector b(owned, MPI_COMM_WORLD), x(b);
      for (const auto i : owned)
        b(i) = 1.0 + std::sin(i + 1.0);
      b.compress(dealii::VectorOperation::insert);

      // A₀ factorised by a solve, its columns kept as the coupled solve keeps them
      std::vector<dealii::PETScWrappers::MPI::Vector> Z(U);
      solver.solve(A, x, b);
      solver.solve_columns(A, Z, U);
      solver.keep_columns(U, Z);
      ASSERT_TRUE(solver.can_reuse());
      const double tolerance = 1e-12 * b.l2_norm();

      // the same matrix: the preconditioner is the exact inverse
      ASSERT_TRUE(solver.solve_reusing(A, U, W, b, x, tolerance));
      EXPECT_LE(solver.statistics().iterations, 1u);
      EXPECT_LT(low_rank_residual(A, U, W, x, b), tolerance);

      // the next tangent: every entry moved by up to 1 % (symmetrically), and a new U (its
      // last column moved), so Z₀ is solved again with the kept factor
      std::vector<std::array<double, 3>> moved;
      for (const auto i : owned)
        for (unsigned j = (i > 0 ? i - 1 : 0); j <= std::min<unsigned>(i + 1, n - 1); ++j)
          moved.push_back({{double(i), double(j), A.el(i, j) * (1 + 0.01 * std::sin(3.0 * (i + j)))}});
      for (const auto &[i, j, value] : moved)
        A.set(static_cast<unsigned>(i), static_cast<unsigned>(j), value);
      A.compress(dealii::VectorOperation::insert);
      for (const auto i : owned)
        U[5](i) = std::exp(-0.01 * std::pow(double(i) - 95.0, 2));
      U[5].compress(dealii::VectorOperation::insert);
      const unsigned factorizations = solver.statistics().factorizations;
      ASSERT_TRUE(solver.solve_reusing(A, U, W, b, x, tolerance)) << "c = " << c;
      const unsigned iterations = solver.statistics().iterations;
      EXPECT_EQ(solver.statistics().factorizations, factorizations); // no new factorisation
      EXPECT_LT(low_rank_residual(A, U, W, x, b), tolerance) << "c = " << c;
      dealii::PETScWrappers::MPI::Vector difference = woodbury_reference(A, U, W, b, symmetric);
      difference -= x;
      const double error = difference.linfty_norm() / x.linfty_norm();
      std::printf("[ linear solver ] c = %.1f: the next tangent with a kept factorisation: %u GMRES iterations, "
                  "against a fresh factorisation %.2e\n", c, iterations, error);
      EXPECT_GT(iterations, 1u);
      EXPECT_LT(error, 1e-10) << "c = " << c;

      // a matrix far from A₀ (its diagonal halved): refused within the limit, not solved loosely
      std::vector<double> diagonal;
      for (const auto i : owned)
        diagonal.push_back(A.el(i, i));
      unsigned row = 0;
      for (const auto i : owned)
        A.set(i, i, 0.5 * diagonal[row++]);
      A.compress(dealii::VectorOperation::insert);
      EXPECT_FALSE(solver.solve_reusing(A, U, W, b, x, tolerance)) << "c = " << c;
      EXPECT_EQ(solver.statistics().reuse_failures, 1u);
      EXPECT_EQ(solver.statistics().reused_solves, 2u);
    }
}
