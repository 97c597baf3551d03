#pragma once
/**
 * @file
 * The linear solve of a Newton iteration, configured on PETSc's KSP directly so that
 * every PETSc option stays reachable:
 *  - "direct": Cholesky (symmetric tangents) or LU by MUMPS (parallel and serial alike),
 *    by default chosen from the tangent's symmetry (set_symmetric()): MUMPS's symmetric
 *    mode reads one triangle of the matrix, so a non-symmetric tangent factorised by
 *    Cholesky is silently a different matrix and Newton's direction is wrong (measured:
 *    docs/interrupted_stitch.md, "The coupled Newton's stall on a refined mesh"). The
 *    solve coupled with the suture keeps its matrix symmetric by moving the pierce
 *    points' skew part into its low-rank update (EmbeddedPoints::set_condensed()). The
 *    default method: the tangents of nearly
 *    incompressible tissue and, later, of penalty coupling are ill-conditioned, and at the
 *    sizes of suturing scenes (≤ 1e5 DoFs) a factorisation on 2 cores is as fast as a
 *    Krylov solve while never failing to converge (see README, Performance).
 *  - "cg" / "gmres" with "gamg" (smoothed aggregation with the six rigid-body modes as
 *    near null space, the right AMG for elasticity) or "boomeramg" (hypre) or "jacobi".
 */

#include <suturesim/core/parameter_file.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include <petscksp.h>

#include <memory>
#include <string>
#include <vector>

namespace suturesim::tissue
{
  class LinearSolver
  {
  public:
    struct Parameters
    {
      std::string method          = "direct";
      std::string factorization   = "auto";
      std::string preconditioner  = "gamg";
      double      tolerance       = 1e-10;
      unsigned    max_iterations  = 2000;
      std::string petsc_options   = "";
      /// Where these were read, for errors that name their entry.
      std::shared_ptr<const ParameterScope> scope;

      static void
      declare(dealii::ParameterHandler &prm);
      void
      parse(const dealii::ParameterHandler &prm, const ParameterScope &scope);
    };

    /// Statistics of the most recent solve.
    struct Statistics
    {
      unsigned    iterations = 0;
      double      residual   = 0;
      std::string converged_reason;
    };

    LinearSolver(const Parameters &parameters, MPI_Comm comm);
    ~LinearSolver();
    LinearSolver(const LinearSolver &) = delete;
    LinearSolver &
    operator=(const LinearSolver &) = delete;

    /// Near null space for AMG: the six rigid-body modes, one vector each, locally owned
    /// entries filled (orthonormalised here).
    void
    set_near_null_space(std::vector<dealii::PETScWrappers::MPI::Vector> modes);

    /// Whether the matrices solve() will get are symmetric (the default: a
    /// hyperelastic tangent is). Factorization 'auto' then takes Cholesky, else LU;
    /// 'cholesky' and the method 'cg' refuse a non-symmetric one with an InputError
    /// naming their entry, @p why saying what makes it so.
    void
    set_symmetric(bool symmetric, const std::string &why = "");

    /// Solves A x = b; throws SolverError when the Krylov method does not converge.
    /// @p relative_tolerance overrides the parameter when > 0 (IDA); a Krylov method
    /// stops at @p absolute_tolerance (the residual a Newton iteration needs, so it
    /// never chases round-off).
    void
    solve(const dealii::PETScWrappers::MPI::SparseMatrix &A,
          dealii::PETScWrappers::MPI::Vector             &x,
          const dealii::PETScWrappers::MPI::Vector       &b,
          double                                          relative_tolerance = 0,
          double                                          absolute_tolerance = 0);

    /// Solves A X = B for the columns of @p B with the factorisation or preconditioner
    /// that the last solve() of @p A set up. The direct method passes all columns to
    /// MUMPS's solve phase at once (PETSc's KSPMatSolve), which reads the factors once
    /// per block of right-hand sides instead of once per column: the triangular solves
    /// are memory-bound, and the coupled iteration needs 3 m + 1 of them per
    /// factorisation for m coupled points (docs/interrupted_stitch.md). A Krylov method
    /// solves column by column to @p absolute_tolerance.
    void
    solve_columns(const dealii::PETScWrappers::MPI::SparseMatrix        &A,
                  std::vector<dealii::PETScWrappers::MPI::Vector>       &X,
                  const std::vector<dealii::PETScWrappers::MPI::Vector> &B,
                  double                                                 absolute_tolerance = 0);

    const Statistics &
    statistics() const
    {
      return stats;
    }

    const Parameters &
    parameters() const
    {
      return prm;
    }

  private:
    Parameters                                       prm;
    MPI_Comm                                         comm;
    KSP                                              ksp = nullptr;
    std::vector<dealii::PETScWrappers::MPI::Vector>  null_space_modes;
    Statistics                                       stats;
    bool                                             symmetric = true;
  };
} // namespace suturesim::tissue
