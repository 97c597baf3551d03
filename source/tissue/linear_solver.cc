#include <suturesim/core/error.h>
#include <suturesim/tissue/linear_solver.h>

#include <deal.II/base/mpi.h>

#include <Eigen/LU>
// PetscObjectStateGet(), documented (level advanced) but declared only here in PETSc 3.18
#include <petsc/private/petscimpl.h>

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <iostream>
#include <sstream>

namespace suturesim::tissue
{
  namespace
  {
    void
    check(const PetscErrorCode code, const char *what)
    {
      if (code != 0)
        throw SolverError(std::string("PETSc error in ") + what + " (code " +
                          std::to_string(code) + ")");
    }

    /// The outcome of @p ksp's last solve into @p stats (iterations, residual, reason).
    KSPConvergedReason
    outcome(KSP ksp, LinearSolver::Statistics &stats)
    {
      KSPConvergedReason reason;
      PetscInt           its;
      PetscReal          rnorm;
      check(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
      check(KSPGetIterationNumber(ksp, &its), "KSPGetIterationNumber");
      check(KSPGetResidualNorm(ksp, &rnorm), "KSPGetResidualNorm");
      stats.iterations       = static_cast<unsigned>(its);
      stats.residual         = rnorm;
      stats.converged_reason = KSPConvergedReasons[reason];
      return reason;
    }

    /// A PETSc error handler that keeps the first message in @p context (a std::string)
    /// instead of printing PETSc's block of lines.
    PetscErrorCode
    keep_first_message(MPI_Comm, int, const char *, const char *, PetscErrorCode code, PetscErrorType,
                       const char *message, void *context)
    {
      auto &kept = *static_cast<std::string *>(context);
      if (kept.empty() && message != nullptr)
        kept = message;
      return code;
    }
  } // namespace

  void
  LinearSolver::Parameters::declare(dealii::ParameterHandler &prm)
  {
    const Parameters d;
    prm.declare_entry("Method",
                      d.method,
                      dealii::Patterns::Selection("direct|cg|gmres"),
                      "Linear solver of each Newton iteration: 'direct' (MUMPS through PETSc, "
                      "see 'Factorization'; the default: robust for nearly incompressible and "
                      "penalty-coupled tangents, fastest below about 5e4 DoFs), 'cg' "
                      "(symmetric tangents) or 'gmres' (any) with the preconditioner below.");
    prm.declare_entry("Factorization",
                      d.factorization,
                      dealii::Patterns::Selection("auto|cholesky|lu"),
                      "Factorization of 'direct': 'auto' (Cholesky while the matrix is "
                      "symmetric, LU when a point load makes it not: friction at pierce "
                      "points, except in the solve coupled with the suture, which moves "
                      "that part into its low-rank update), 'cholesky' (LDL^T, half the "
                      "work; refused with non-symmetric loads) or 'lu' (any matrix). Unit: "
                      "none.");
    prm.declare_entry("Preconditioner",
                      d.preconditioner,
                      dealii::Patterns::Selection("gamg|boomeramg|jacobi"),
                      "Preconditioner of the Krylov methods: 'gamg' (PETSc smoothed "
                      "aggregation with rigid-body near null space), 'boomeramg' (hypre) or "
                      "'jacobi'.");
    prm.declare_entry("Relative tolerance",
                      dealii::Patterns::Tools::to_string(d.tolerance),
                      dealii::Patterns::Double(0, 1),
                      "Relative residual tolerance of the Krylov methods and of the GMRES "
                      "that reuses a factorisation (Reuse iterations). Unit: 1. Range: (0, 1).");
    prm.declare_entry("Max iterations",
                      std::to_string(d.max_iterations),
                      dealii::Patterns::Integer(1),
                      "Maximum Krylov iterations. Unit: 1. Range: >= 1.");
    prm.declare_entry("Reuse iterations",
                      std::to_string(d.reuse_iterations),
                      dealii::Patterns::Integer(0, 100),
                      "With 'direct': a Newton iteration first solves its system by GMRES "
                      "preconditioned with the factorisation of an earlier tangent (kept "
                      "over iterations and steps), to the same tolerance as a fresh "
                      "factorisation's update, and factorises its own tangent only when "
                      "GMRES needs more than this many iterations; 0: every tangent is "
                      "factorised. Unit: 1. Range: 0-100.");
    prm.declare_entry("Maximum memory",
                      "0",
                      dealii::Patterns::Double(0),
                      "A guard for 'direct': the most memory its factorisation may take, all "
                      "processes together, as MUMPS's analysis estimates it before the first "
                      "factorisation; a larger one is refused (use a coarser mesh, processes on "
                      "more nodes, or cg/gmres). 0: each node's available memory (MemAvailable) "
                      "for its processes' share. Unit: B. Range: >= 0.");
    prm.declare_entry("PETSc options",
                      d.petsc_options,
                      dealii::Patterns::Anything(),
                      "Extra PETSc options for experts, given without the 'suturesim_' "
                      "prefix that is added, e.g. '-pc_gamg_threshold 0.02'. Unit: none.");
  }

  void
  LinearSolver::Parameters::parse(const dealii::ParameterHandler &prm,
                                  const ParameterScope    &scope)
  {
    method         = prm.get("Method");
    preconditioner = prm.get("Preconditioner");
    factorization  = prm.get("Factorization");
    tolerance      = prm.get_double("Relative tolerance");
    max_iterations = prm.get_integer("Max iterations");
    petsc_options  = prm.get("PETSc options");
    reuse_iterations = static_cast<unsigned>(prm.get_integer("Reuse iterations"));
    maximum_memory = prm.get_double("Maximum memory");
    scope.require(tolerance > 0, "Relative tolerance", "must be > 0");
    this->scope = std::make_shared<const ParameterScope>(scope);
  }

  namespace
  {
    /// MUMPS's Cholesky (LDL^T) or LU on @p pc.
    void
    set_factorization(PC pc, const bool cholesky)
    {
      check(PCSetType(pc, cholesky ? PCCHOLESKY : PCLU), "PCSetType");
      check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
    }
  } // namespace

  void
  LinearSolver::set_symmetric(const bool yes, const std::string &why)
  {
    if (yes == symmetric)
      return;
    if (!yes && prm.scope)
      {
        const std::string problem = "needs a symmetric tangent, and " + why + " makes it non-symmetric";
        prm.scope->require(prm.method != "cg", "Method", "cg " + problem + ": use gmres");
        prm.scope->require(prm.method != "direct" || prm.factorization != "cholesky", "Factorization",
                           "cholesky " + problem + ": use auto or lu");
      }
    symmetric = yes;
    if (prm.method == "direct" && prm.factorization == "auto")
      {
        memory_checked = false; // LU takes about twice Cholesky's memory
        factored       = false; // the new type drops the factor
        PC pc;
        check(KSPGetPC(ksp, &pc), "KSPGetPC");
        set_factorization(pc, symmetric);
      }
  }

  LinearSolver::LinearSolver(const Parameters &parameters, MPI_Comm comm)
    : prm(parameters)
    , comm(comm)
  {
    check(KSPCreate(comm, &ksp), "KSPCreate");
    check(KSPSetOptionsPrefix(ksp, "suturesim_"), "KSPSetOptionsPrefix");
    PC pc;
    check(KSPGetPC(ksp, &pc), "KSPGetPC");
    if (prm.method == "direct")
      {
        check(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
        set_factorization(pc, prm.factorization != "lu");
      }
    else
      {
        check(KSPSetType(ksp, prm.method == "cg" ? KSPCG : KSPGMRES), "KSPSetType");
        if (prm.preconditioner == "gamg")
          check(PCSetType(pc, PCGAMG), "PCSetType");
        else if (prm.preconditioner == "boomeramg")
          {
            check(PCSetType(pc, PCHYPRE), "PCSetType");
            check(PCHYPRESetType(pc, "boomeramg"), "PCHYPRESetType");
          }
        else
          check(PCSetType(pc, PCJACOBI), "PCSetType");
        check(KSPSetNormType(ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
        check(KSPSetTolerances(ksp, prm.tolerance, 0.0, 1e30, prm.max_iterations),
              "KSPSetTolerances");
      }
    if (!prm.petsc_options.empty())
      {
        // Options go to the global database under our prefix; KSPSetFromOptions reads them.
        std::string prefixed;
        std::string token;
        std::istringstream in(prm.petsc_options);
        while (in >> token)
          prefixed += (token.rfind("-", 0) == 0 ? "-suturesim_" + token.substr(1) : token) + " ";
        check(PetscOptionsInsertString(nullptr, prefixed.c_str()), "PetscOptionsInsertString");
      }
    // the user's options are input: one that PETSc refuses (an unknown type) is a one-line
    // InputError naming the entry, not PETSc's block of error lines
    std::string refused;
    check(PetscPushErrorHandler(keep_first_message, &refused), "PetscPushErrorHandler");
    const PetscErrorCode code = KSPSetFromOptions(ksp);
    check(PetscPopErrorHandler(), "PetscPopErrorHandler");
    if (code != 0 && !prm.petsc_options.empty())
      throw InputError("Tissue/Linear solver/PETSc options: '" + prm.petsc_options + "': PETSc refused them (" +
                       one_line(refused) + ")");
    check(code, "KSPSetFromOptions");
  }

  LinearSolver::~LinearSolver()
  {
    if (ksp != nullptr)
      KSPDestroy(&ksp);
    if (reuse_ksp != nullptr)
      KSPDestroy(&reuse_ksp);
  }

  void
  LinearSolver::set_near_null_space(std::vector<dealii::PETScWrappers::MPI::Vector> modes)
  {
    // Modified Gram–Schmidt: MatNullSpaceCreate wants orthonormal vectors.
    for (std::size_t i = 0; i < modes.size(); ++i)
      {
        for (std::size_t j = 0; j < i; ++j)
          modes[i].add(-(modes[i] * modes[j]), modes[j]);
        const double norm = modes[i].l2_norm();
        if (norm > 0)
          modes[i] /= norm;
      }
    null_space_modes = std::move(modes);
  }

  namespace
  {
    /// What MUMPS's INFOG(1) < 0 means (MUMPS 5 users' guide, section "Error
    /// diagnostics"); whether more working space (ICNTL(14)) cures it.
    std::pair<std::string, bool>
    mumps_error(const PetscInt infog1)
    {
      switch (infog1)
        {
          case -8:
          case -9:
          case -11:
          case -12:
          case -14:
          case -15:
          case -17:
          case -20:
            return {"its working space, estimated in the analysis, is too small", true};
          case -10:
            return {"the matrix is numerically singular", false};
          case -13:
            return {"a memory allocation failed (out of memory)", false};
          case -19:
            return {"the memory limit ICNTL(23) is too small", false};
          default:
            return {"see MUMPS's users' guide for INFOG(1) = " + std::to_string(infog1), false};
        }
    }

    /// The direct method's factorisation of @p mat on @p ksp (a no-op while @p mat is
    /// unchanged). A failed one starts again from MUMPS's analysis; when MUMPS ran short
    /// of the working space its analysis estimated (INFOG(1) = -8, -9, ...), with the
    /// space's margin ICNTL(14) raised from m to 2 m + 20 % (for the rest of the run: its
    /// later matrices share the pattern), up to three times, each said on stderr.
    /// Otherwise, or then, throws SolverError naming MUMPS's INFOG(1) and what it means.
    void
    factorize(KSP ksp, Mat mat)
    {
      constexpr unsigned max_space_retries = 3;
      PC pc;
      check(KSPGetPC(ksp, &pc), "KSPGetPC");
      check(KSPSetOperators(ksp, mat, mat), "KSPSetOperators");
      for (unsigned attempt = 0;; ++attempt)
        {
          check(KSPSetUp(ksp), "KSPSetUp");
          PCFailedReason failed;
          check(PCGetFailedReason(pc, &failed), "PCGetFailedReason");
          if (failed == PC_NOERROR)
            return;
          Mat      F;
          PetscInt infog1 = 0, infog2 = 0, space = 0;
          check(PCFactorGetMatrix(pc, &F), "PCFactorGetMatrix");
          check(MatMumpsGetInfog(F, 1, &infog1), "MatMumpsGetInfog");
          check(MatMumpsGetInfog(F, 2, &infog2), "MatMumpsGetInfog");
          check(MatMumpsGetIcntl(F, 14, &space), "MatMumpsGetIcntl");
          // MUMPS keeps a failed factorisation's INFOG(1), and PETSc then skips every later
          // numerical factorisation of that analysis: without a fresh start here, a
          // matrix that fails once fails at every cut-back of the step (seen on the
          // stitch's L2, docs/interrupted_stitch.md).
          check(KSPReset(ksp), "KSPReset");
          check(KSPSetOperators(ksp, mat, mat), "KSPSetOperators");
          const auto [meaning, more_space_helps] = mumps_error(infog1);
          if (!more_space_helps || attempt == max_space_retries)
            throw SolverError("MUMPS's factorisation failed: " + meaning + " (INFOG(1) = " +
                              std::to_string(infog1) + ", INFOG(2) = " + std::to_string(infog2) +
                              ", working space +" + std::to_string(space) + " % (ICNTL(14)))");
          // through the options database, which MUMPS's analysis reads under the factor's
          // prefix: a value set on the factor before MUMPS is initialised does not last
          check(PCFactorSetUpMatSolverType(pc), "PCFactorSetUpMatSolverType");
          check(PCFactorGetMatrix(pc, &F), "PCFactorGetMatrix");
          const char *prefix = nullptr;
          check(MatGetOptionsPrefix(F, &prefix), "MatGetOptionsPrefix");
          const std::string option = "-" + std::string(prefix ? prefix : "") + "mat_mumps_icntl_14";
          const std::string raised = std::to_string(2 * space + 20);
          check(PetscOptionsSetValue(nullptr, option.c_str(), raised.c_str()), "PetscOptionsSetValue");
          PetscMPIInt rank = 0;
          MPI_Comm_rank(PetscObjectComm(reinterpret_cast<PetscObject>(ksp)), &rank);
          if (rank == 0)
            std::cerr << "note: MUMPS's factorisation ran short of working space (INFOG(1) = " << infog1
                      << "); again with a margin of " << raised << " % (ICNTL(14))" << std::endl;
        }
    }
  } // namespace

  namespace
  {
    /// The memory this node has available, B: /proc/meminfo's MemAvailable (free memory
    /// and what the kernel can reclaim), else the free pages.
    double
    available_memory()
    {
      std::ifstream in("/proc/meminfo");
      std::string   key, rest;
      double        kilobytes = 0;
      while (in >> key >> kilobytes && std::getline(in, rest))
        if (key == "MemAvailable:")
          return 1024 * kilobytes;
      return static_cast<double>(sysconf(_SC_AVPHYS_PAGES)) * static_cast<double>(sysconf(_SC_PAGESIZE));
    }

    /// A MUMPS size of the factor @p F in bytes (MUMPS gives millions of bytes):
    /// INFOG(@p i), the same on every process, or this process's INFO(@p i) if @p local.
    double
    mumps_bytes(Mat F, const PetscInt i, const bool local = false)
    {
      PetscInt megabytes = 0;
      check(local ? MatMumpsGetInfo(F, i, &megabytes) : MatMumpsGetInfog(F, i, &megabytes), "MatMumpsGetInfo");
      return 1e6 * static_cast<double>(megabytes);
    }

    /// Whether @p pc factorises with MUMPS (PETSc options may choose another package).
    bool
    uses_mumps(PC pc)
    {
      MatSolverType package = nullptr;
      check(PCFactorGetMatSolverType(pc, &package), "PCFactorGetMatSolverType");
      return package != nullptr && std::string(package) == MATSOLVERMUMPS;
    }

    /// MUMPS's analysis alone of @p A (Cholesky or LU as @p pc will factorise it, with
    /// its options): {INFOG(17), this process's INFO(15)} in bytes, the factorisation's
    /// memory estimated over all processes and on this one; {0, 0} when the analysis
    /// failed (the factorisation then says why). Collective.
    std::pair<double, double>
    mumps_estimate(PC pc, Mat A)
    {
      PCType      type   = nullptr;
      const char *prefix = nullptr;
      check(PCGetType(pc, &type), "PCGetType");
      check(PCGetOptionsPrefix(pc, &prefix), "PCGetOptionsPrefix");
      const bool cholesky = std::string(type) == PCCHOLESKY;
      struct Factor // destroyed on every path out, a throw among them
      {
        Mat F = nullptr;
        ~Factor()
        {
          MatDestroy(&F);
        }
      } factor;
      check(MatGetFactor(A, MATSOLVERMUMPS, cholesky ? MAT_FACTOR_CHOLESKY : MAT_FACTOR_LU, &factor.F), "MatGetFactor");
      check(MatSetOptionsPrefix(factor.F, prefix), "MatSetOptionsPrefix"); // the user's -mat_mumps_icntl_* apply
      MatFactorInfo info;
      check(MatFactorInfoInitialize(&info), "MatFactorInfoInitialize");
      // MUMPS orders the matrix itself (PETSc passes it no ordering); a failure is
      // returned, not printed: the factorisation reports it
      check(PetscPushErrorHandler(PetscReturnErrorHandler, nullptr), "PetscPushErrorHandler");
      const PetscErrorCode code = cholesky ? MatCholeskyFactorSymbolic(factor.F, A, nullptr, &info)
                                           : MatLUFactorSymbolic(factor.F, A, nullptr, nullptr, &info);
      check(PetscPopErrorHandler(), "PetscPopErrorHandler");
      PetscInt infog1 = -1;
      if (code == 0)
        check(MatMumpsGetInfog(factor.F, 1, &infog1), "MatMumpsGetInfog");
      if (infog1 < 0)
        return {0, 0};
      return {mumps_bytes(factor.F, 17), mumps_bytes(factor.F, 15, true)};
    }
  } // namespace

  void
  LinearSolver::check_memory(Mat A)
  {
    memory_checked = true;
    PC pc;
    check(KSPGetPC(ksp, &pc), "KSPGetPC");
    if (!uses_mumps(pc))
      return;
    auto [total, mine] = mumps_estimate(pc, A);
    // one decision on every process, whatever each one's analysis returned
    total                               = dealii::Utilities::MPI::min(total, comm);
    stats.factorization_memory_estimate = total;
    if (total == 0)
      return;
    PetscInt rows = 0;
    check(MatGetSize(A, &rows, nullptr), "MatGetSize");
    std::ostringstream why;
    why << "MUMPS's analysis estimates ";
    if (prm.maximum_memory > 0)
      {
        if (total <= prm.maximum_memory)
          return;
        why << total << " B for the factorisation of the " << rows << "-DoF tangent (INFOG(17), all processes), above "
            << "this limit, " << prm.maximum_memory << " B";
      }
    else
      {
        // each node against its own memory: the processes sharing it, summed
        MPI_Comm node;
        MPI_Comm_split_type(comm, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
        const double need = dealii::Utilities::MPI::sum(mine, node), available = available_memory();
        MPI_Comm_free(&node);
        const double over = dealii::Utilities::MPI::max(need > available ? need / available : 0.0, comm);
        if (over == 0)
          return;
        why << "a factorisation of the " << rows << "-DoF tangent that needs " << over
            << " times the memory available on a node (INFO(15) of its processes against its MemAvailable)";
      }
    why << ": use a coarser mesh, processes on more nodes, or Method = cg or gmres"
        << (prm.maximum_memory > 0 ? ", or raise it" : ", or set this to allow it");
    if (prm.scope)
      prm.scope->fail("Maximum memory", why.str());
    throw InputError("Tissue/Linear solver/Maximum memory: " + why.str());
  }

  void
  LinearSolver::factor(Mat A)
  {
    if (!memory_checked)
      check_memory(A);
    PetscObjectState state = 0;
    check(PetscObjectStateGet(reinterpret_cast<PetscObject>(A), &state), "PetscObjectStateGet");
    if (!factored || A != factored_mat || state != factored_state)
      {
        factored = false;
        factorize(ksp, A);
        factored       = true;
        factored_mat   = A;
        factored_state = state;
        ++stats.factorizations;
      }
    PC pc;
    check(KSPGetPC(ksp, &pc), "KSPGetPC");
    if (!uses_mumps(pc))
      return;
    Mat F;
    check(PCFactorGetMatrix(pc, &F), "PCFactorGetMatrix");
    stats.factorization_memory = mumps_bytes(F, 19);
  }

  void
  LinearSolver::solve(const dealii::PETScWrappers::MPI::SparseMatrix &A,
                      dealii::PETScWrappers::MPI::Vector             &x,
                      const dealii::PETScWrappers::MPI::Vector       &b,
                      const double                                    relative_tolerance,
                      const double                                    absolute_tolerance)
  {
    Mat mat = A;
    if (!null_space_modes.empty() && prm.method != "direct")
      {
        std::vector<Vec> vecs;
        for (const auto &v : null_space_modes)
          vecs.push_back(v);
        MatNullSpace nsp;
        check(MatNullSpaceCreate(comm, PETSC_FALSE, static_cast<PetscInt>(vecs.size()),
                                 vecs.data(), &nsp),
              "MatNullSpaceCreate");
        check(MatSetNearNullSpace(mat, nsp), "MatSetNearNullSpace");
        check(MatNullSpaceDestroy(&nsp), "MatNullSpaceDestroy");
      }
    if (prm.method == "direct")
      factor(mat);
    else
      check(KSPSetOperators(ksp, mat, mat), "KSPSetOperators");
    if (prm.method != "direct")
      check(KSPSetTolerances(ksp,
                             relative_tolerance > 0 ? relative_tolerance : prm.tolerance,
                             absolute_tolerance,
                             1e30,
                             prm.max_iterations),
            "KSPSetTolerances");
    check(KSPSolve(ksp, b, x), "KSPSolve");

    const KSPConvergedReason reason = outcome(ksp, stats);
    if (reason < 0)
      throw SolverError("linear solver (" + prm.method + (prm.method == "direct" ? "" : "+" +
                        prm.preconditioner) + ") failed: " + stats.converged_reason +
                        " after " + std::to_string(stats.iterations) + " iterations, residual " +
                        std::to_string(stats.residual));
    x.compress(dealii::VectorOperation::insert);
  }

  namespace
  {
    /// A dense PETSc matrix of @p columns columns laid out like @p like, destroyed
    /// with its scope (a solver error throws between its creation and its use).
    struct DenseColumns
    {
      Mat mat = nullptr;

      DenseColumns(MPI_Comm comm, const Vec like, const std::size_t columns)
      {
        PetscInt local, global;
        check(VecGetLocalSize(like, &local), "VecGetLocalSize");
        check(VecGetSize(like, &global), "VecGetSize");
        check(MatCreateDense(comm, local, PETSC_DECIDE, global,
                             static_cast<PetscInt>(columns), nullptr, &mat),
              "MatCreateDense");
      }
      ~DenseColumns()
      {
        MatDestroy(&mat);
      }
      DenseColumns(const DenseColumns &) = delete;
      DenseColumns &
      operator=(const DenseColumns &) = delete;

      void
      set(const PetscInt j, const Vec v)
      {
        Vec column;
        check(MatDenseGetColumnVecWrite(mat, j, &column), "MatDenseGetColumnVecWrite");
        check(VecCopy(v, column), "VecCopy");
        check(MatDenseRestoreColumnVecWrite(mat, j, &column), "MatDenseRestoreColumnVecWrite");
      }
      void
      get(const PetscInt j, Vec v) const
      {
        Vec column;
        check(MatDenseGetColumnVecRead(mat, j, &column), "MatDenseGetColumnVecRead");
        check(VecCopy(column, v), "VecCopy");
        check(MatDenseRestoreColumnVecRead(mat, j, &column), "MatDenseRestoreColumnVecRead");
      }
    };

    /// X = A⁻¹ B for all the columns of @p B at once: @p solve (rhs, sol) solves the
    /// dense block rhs into sol (a factor's triangular solves see every column in one
    /// pass over the factor).
    void
    solve_block(MPI_Comm comm, const std::function<void(Mat, Mat)> &solve,
                const std::vector<dealii::PETScWrappers::MPI::Vector> &B,
                std::vector<dealii::PETScWrappers::MPI::Vector>       &X)
    {
      DenseColumns rhs(comm, B[0], B.size()), sol(comm, B[0], B.size());
      for (std::size_t j = 0; j < B.size(); ++j)
        rhs.set(static_cast<PetscInt>(j), B[j]);
      solve(rhs.mat, sol.mat);
      for (std::size_t j = 0; j < X.size(); ++j)
        {
          sol.get(static_cast<PetscInt>(j), X[j]);
          X[j].compress(dealii::VectorOperation::insert);
        }
    }
  } // namespace

  void
  LinearSolver::solve_columns(const dealii::PETScWrappers::MPI::SparseMatrix        &A,
                              std::vector<dealii::PETScWrappers::MPI::Vector>       &X,
                              const std::vector<dealii::PETScWrappers::MPI::Vector> &B,
                              const double absolute_tolerance)
  {
    Assert(X.size() == B.size(), dealii::ExcDimensionMismatch(X.size(), B.size()));
    if (prm.method != "direct")
      {
        for (std::size_t j = 0; j < B.size(); ++j)
          solve(A, X[j], B[j], 0, absolute_tolerance);
        return;
      }
    if (B.empty())
      return;
    factor(A);
    solve_block(comm, [&](Mat rhs, Mat sol) {
      check(KSPMatSolve(ksp, rhs, sol), "KSPMatSolve");
      KSPConvergedReason reason;
      check(KSPGetConvergedReason(ksp, &reason), "KSPGetConvergedReason");
      if (reason < 0)
        throw SolverError(std::string("linear solver (direct) failed on ") + std::to_string(B.size()) +
                          " right-hand sides: " + KSPConvergedReasons[reason]);
    }, B, X);
  }

  namespace
  {
    /// The system of LinearSolver::solve_reusing() as PETSc shells: the operator
    /// A + U W Uᵀ and the preconditioner (A₀ + U W Uᵀ)⁻¹ from A₀'s factor F and
    /// Z₀ = A₀⁻¹ U.
    struct LowRankSystem
    {
      Mat                                  A = nullptr, F = nullptr;
      std::vector<Vec>                     U, Z;
      Eigen::MatrixXd                      W;
      Eigen::PartialPivLU<Eigen::MatrixXd> M; ///< I + W Uᵀ Z₀

      /// t = Uᵀ v; PETSc's error code (this runs inside PETSc's callbacks, which must
      /// not throw)
      PetscErrorCode
      project(const Vec v, Eigen::VectorXd &t) const
      {
        t.resize(static_cast<Eigen::Index>(U.size()));
        return VecMDot(v, static_cast<PetscInt>(U.size()), U.data(), t.data());
      }
    };

    PetscErrorCode
    low_rank_mult(Mat shell, Vec x, Vec y)
    {
      LowRankSystem *s = nullptr;
      PetscCall(MatShellGetContext(shell, &s));
      PetscCall(MatMult(s->A, x, y));
      if (s->U.empty())
        return 0;
      Eigen::VectorXd t;
      PetscCall(s->project(x, t));
      const Eigen::VectorXd c = s->W * t;
      PetscCall(VecMAXPY(y, static_cast<PetscInt>(s->U.size()), c.data(), s->U.data()));
      return 0;
    }

    PetscErrorCode
    woodbury_apply(PC pc, Vec y, Vec x)
    {
      LowRankSystem *s = nullptr;
      PetscCall(PCShellGetContext(pc, &s));
      PetscCall(MatSolve(s->F, y, x));
      if (s->U.empty())
        return 0;
      Eigen::VectorXd t;
      PetscCall(s->project(x, t));
      const Eigen::VectorXd c = -s->M.solve(s->W * t);
      PetscCall(VecMAXPY(x, static_cast<PetscInt>(s->Z.size()), c.data(), s->Z.data()));
      return 0;
    }

    /// Whether @p a and @p b hold equal vectors. Collective.
    bool
    same(const std::vector<dealii::PETScWrappers::MPI::Vector> &a,
         const std::vector<dealii::PETScWrappers::MPI::Vector> &b)
    {
      if (a.size() != b.size())
        return false;
      for (std::size_t k = 0; k < a.size(); ++k)
        {
          PetscBool equal = PETSC_FALSE;
          check(VecEqual(a[k], b[k], &equal), "VecEqual");
          if (!equal)
            return false;
        }
      return true;
    }
  } // namespace

  bool
  LinearSolver::can_reuse() const
  {
    return prm.method == "direct" && prm.reuse_iterations > 0 && factored;
  }

  void
  LinearSolver::keep_columns(const std::vector<dealii::PETScWrappers::MPI::Vector> &U,
                             const std::vector<dealii::PETScWrappers::MPI::Vector> &Z)
  {
    if (!can_reuse())
      return;
    kept_U             = U;
    kept_Z             = Z;
    kept_factorization = stats.factorizations;
  }

  bool
  LinearSolver::solve_reusing(const dealii::PETScWrappers::MPI::SparseMatrix        &A,
                              const std::vector<dealii::PETScWrappers::MPI::Vector> &U,
                              const Eigen::MatrixXd                                 &W,
                              const dealii::PETScWrappers::MPI::Vector              &b,
                              dealii::PETScWrappers::MPI::Vector                    &x,
                              const double                                           absolute_tolerance)
  {
    if (!can_reuse())
      return false;
    LowRankSystem s;
    PC            pc;
    check(KSPGetPC(ksp, &pc), "KSPGetPC");
    check(PCFactorGetMatrix(pc, &s.F), "PCFactorGetMatrix");
    if (kept_factorization != stats.factorizations || !same(U, kept_U))
      {
        // Z₀ = A₀⁻¹ U with the kept factor
        kept_U = U;
        kept_Z = U;
        if (!U.empty())
          solve_block(comm, [&](Mat rhs, Mat sol) { check(MatMatSolve(s.F, rhs, sol), "MatMatSolve"); }, U,
                      kept_Z);
        kept_factorization = stats.factorizations;
      }
    s.A = A;
    for (std::size_t k = 0; k < U.size(); ++k)
      {
        s.U.push_back(U[k]);
        s.Z.push_back(kept_Z[k]);
      }
    s.W = W;
    Eigen::MatrixXd UZ(U.size(), U.size());
    for (std::size_t k = 0; k < U.size(); ++k)
      {
        Eigen::VectorXd t;
        check(s.project(s.Z[k], t), "VecMDot");
        UZ.col(static_cast<Eigen::Index>(k)) = t;
      }
    s.M = (Eigen::MatrixXd::Identity(W.rows(), W.cols()) + W * UZ).partialPivLu();

    PetscInt local = 0, global = 0;
    check(VecGetLocalSize(b, &local), "VecGetLocalSize");
    check(VecGetSize(b, &global), "VecGetSize");
    struct Shell // destroyed on every path out
    {
      Mat mat = nullptr;
      ~Shell()
      {
        MatDestroy(&mat);
      }
    } shell;
    check(MatCreateShell(comm, local, local, global, global, &s, &shell.mat), "MatCreateShell");
    check(MatShellSetOperation(shell.mat, MATOP_MULT, reinterpret_cast<void (*)(void)>(low_rank_mult)),
          "MatShellSetOperation");
    if (reuse_ksp == nullptr)
      {
        check(KSPCreate(comm, &reuse_ksp), "KSPCreate");
        check(KSPSetType(reuse_ksp, KSPGMRES), "KSPSetType");
        check(KSPGMRESSetRestart(reuse_ksp, static_cast<PetscInt>(prm.reuse_iterations)), "KSPGMRESSetRestart");
        check(KSPSetPCSide(reuse_ksp, PC_RIGHT), "KSPSetPCSide");
        check(KSPSetNormType(reuse_ksp, KSP_NORM_UNPRECONDITIONED), "KSPSetNormType");
        PC shell_pc;
        check(KSPGetPC(reuse_ksp, &shell_pc), "KSPGetPC");
        check(PCSetType(shell_pc, PCSHELL), "PCSetType");
        check(PCShellSetApply(shell_pc, woodbury_apply), "PCShellSetApply");
      }
    PC shell_pc;
    check(KSPGetPC(reuse_ksp, &shell_pc), "KSPGetPC");
    check(PCShellSetContext(shell_pc, &s), "PCShellSetContext");
    check(KSPSetOperators(reuse_ksp, shell.mat, shell.mat), "KSPSetOperators");
    check(KSPSetTolerances(reuse_ksp, prm.tolerance, absolute_tolerance, 1e30,
                           static_cast<PetscInt>(prm.reuse_iterations)),
          "KSPSetTolerances");
    check(KSPSolve(reuse_ksp, b, x), "KSPSolve");
    const KSPConvergedReason reason = outcome(reuse_ksp, stats);
    stats.reuse_iterations += stats.iterations;
    if (reason <= 0)
      {
        ++stats.reuse_failures;
        return false;
      }
    ++stats.reused_solves;
    x.compress(dealii::VectorOperation::insert);
    return true;
  }
} // namespace suturesim::tissue
