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

#include <Eigen/Core>

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
      /// the most GMRES iterations solve_reusing() may spend with a kept factorisation
      /// before the tangent is factorised afresh; 0: every tangent is factorised
      unsigned reuse_iterations = 0;
      /// the most memory the direct method's factorisation may take, all processes
      /// together, B; 0: each node's available memory (check_memory())
      double maximum_memory = 0;
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
      /// the direct method's factorisation, all processes together, B: as MUMPS's
      /// analysis estimated it before the first (INFOG(17)) and as the last allocated
      /// (INFOG(19)); 0 for the Krylov methods
      double factorization_memory_estimate = 0;
      double factorization_memory          = 0;
      /// the direct method's numerical factorisations, the solves solve_reusing() made
      /// with a kept one, their GMRES iterations in all, and its attempts that did not
      /// converge within Reuse iterations (each followed by a factorisation); all since
      /// construction
      unsigned factorizations   = 0;
      unsigned reused_solves    = 0;
      unsigned reuse_iterations = 0;
      unsigned reuse_failures   = 0;
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

    /// Whether solve_reusing() may be tried: the direct method with Reuse iterations > 0
    /// and a factorisation kept from an earlier solve.
    bool
    can_reuse() const;

    /// Solves (A + U W Uᵀ) x = b, W a small dense matrix (U's columns × U's columns), with
    /// the factorisation of an earlier matrix A₀ kept: right-preconditioned GMRES whose
    /// preconditioner is the exact inverse of A₀ + U W Uᵀ by the Sherman–Morrison–Woodbury
    /// identity, (A₀ + U W Uᵀ)⁻¹ = A₀⁻¹ − Z₀ (I + W Uᵀ Z₀)⁻¹ W Uᵀ A₀⁻¹ with Z₀ = A₀⁻¹ U
    /// (kept while U and the factorisation are; else one block solve). This is the
    /// factorisation lagged over Newton iterations and steps with the Newton step still
    /// solved to @p absolute_tolerance (PETSc's -snes_lag_preconditioner; Brown & Saad
    /// 1990, "Hybrid Krylov methods for nonlinear systems of equations"): the tangent of
    /// a quasi-static step changes little from one iteration to the next, and a
    /// triangular solve costs a small part of a factorisation. Returns false, @p x
    /// undefined, when GMRES did not reach @p absolute_tolerance (unpreconditioned
    /// residual, all rows) within Reuse iterations: the caller then factorises A.
    bool
    solve_reusing(const dealii::PETScWrappers::MPI::SparseMatrix        &A,
                  const std::vector<dealii::PETScWrappers::MPI::Vector> &U,
                  const Eigen::MatrixXd                                 &W,
                  const dealii::PETScWrappers::MPI::Vector              &b,
                  dealii::PETScWrappers::MPI::Vector                    &x,
                  double                                                 absolute_tolerance);

    /// Keeps Z = A⁻¹ U from the factorisation the last solve made (the columns as the
    /// solve returned them), for solve_reusing() with the same U.
    void
    keep_columns(const std::vector<dealii::PETScWrappers::MPI::Vector> &U,
                 const std::vector<dealii::PETScWrappers::MPI::Vector> &Z);

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
    /// The resource guard of the direct method, before its first factorisation of @p A
    /// (and again when Factorization auto turns to LU): MUMPS's analysis alone, with the
    /// scene's MUMPS options, estimates the factorisation's memory (MUMPS 5 users' guide,
    /// "Information parameters": INFOG(17) over all processes, INFO(15) on each). An
    /// estimate above Maximum memory (all processes), or when it is 0 above a node's
    /// available memory (/proc/meminfo's MemAvailable against the INFO(15) of the
    /// processes sharing the node), is an InputError naming Maximum memory on every
    /// process: refused before the memory is taken rather than the process killed by
    /// the kernel once it is. Nothing is checked when PETSc options chose another package.
    void
    check_memory(Mat A);

    /// The direct method's factorisation of @p A for solve() and solve_columns():
    /// check_memory() before the first, then factorize() (a no-op while @p A is
    /// unchanged), and the memory MUMPS allocated into the statistics (INFOG(19)).
    void
    factor(Mat A);

    Parameters                                       prm;
    MPI_Comm                                         comm;
    KSP                                              ksp = nullptr;
    std::vector<dealii::PETScWrappers::MPI::Vector>  null_space_modes;
    Statistics                                       stats;
    bool                                             symmetric = true;
    bool                                             memory_checked = false;
    /// whether the PC holds a factorisation, of which matrix and in which state
    /// (PETSc refactorises when either changes)
    bool             factored       = false;
    Mat              factored_mat   = nullptr;
    PetscObjectState factored_state = 0;
    /// solve_reusing()'s GMRES, and the U and Z₀ = A₀⁻¹U it keeps for the factorisation
    /// numbered kept_factorization (Statistics::factorizations when it was made)
    KSP                                             reuse_ksp          = nullptr;
    std::vector<dealii::PETScWrappers::MPI::Vector> kept_U, kept_Z;
    unsigned                                        kept_factorization = 0;
  };
} // namespace suturesim::tissue
