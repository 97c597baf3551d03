#pragma once
/**
 * @file
 * The accurate tissue model: finite-strain hyperelastic FE on a distributed hexahedral
 * mesh (p4est), PETSc MPI matrices and vectors, Total Lagrangian. Owns the degrees of
 * freedom, assembly, the Newton solve of one quasi-static load level, the pieces an
 * implicit time integrator needs (residual and Jacobian of M v̇ + C v + R(u) = 0), and
 * the measurements written per step: reaction forces on every Dirichlet boundary,
 * displacements at probe points, and the VTU fields.
 *
 * Implemented in tissue_model.cc (DoFs, constraints, state), tissue_assembly.cc (the
 * assembly, over the threads of the process), tissue_newton.cc
 * (solve_static()), tissue_model_coupled.cc (solve_coupled()), tissue_output.cc
 * (reactions, probes, VTU) and tissue_dynamics.cc (mass, damping, the residual and
 * Jacobian of the dynamics); the parameters are in tissue_parameters.h.
 */

#include <suturesim/mesh/mesh_loader.h>
#include <suturesim/tearing/damage_field.h>
#include <suturesim/tearing/process_zone.h>
#include <suturesim/tearing/tear_criterion.h>
#include <suturesim/tissue/boundary_conditions.h>
#include <suturesim/tissue/cell_assembler.h>
#include <suturesim/tissue/linear_solver.h>
#include <suturesim/tissue/material.h>
#include <suturesim/tissue/condensed_body.h>
#include <suturesim/tissue/point_loads.h>
#include <suturesim/tissue/tissue_parameters.h>

#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include <Eigen/Core>

#include <nlohmann/json_fwd.hpp>

#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace suturesim::tissue
{
  /// What one Newton solve did, for summary.json and the convergence tests.
  struct NewtonReport
  {
    bool                converged = false;
    unsigned            iterations = 0;
    std::vector<double> residual_norms;  ///< N, free DoFs, one per assembled iterate
    std::vector<double> increment_norms; ///< m
    unsigned            backtracks        = 0;
    unsigned            linear_iterations = 0;
    double              assembly_seconds  = 0;
    double              solve_seconds     = 0;
    std::string         failure;
  };

  /// The tissue's boundary as triangles over the mesh vertices on it: two per boundary
  /// face (its corners; the faces of a Q2 mesh are flattened to bilinear patches),
  /// oriented outward, with the x, y, z DoFs of every vertex. The same on every rank.
  struct BoundarySurface
  {
    Eigen::Matrix3Xd                                             reference; ///< X, m
    std::vector<std::array<std::uint32_t, 3>>                    triangles;
    std::vector<dealii::types::boundary_id>                      ids; ///< per triangle: its face's
    std::vector<std::array<dealii::types::global_dof_index, 3>> dofs;
  };

  struct Reaction
  {
    std::string          boundary;
    dealii::Tensor<1, 3> force; ///< N, force the support exerts on the tissue
  };

  class TissueModel
  {
  public:
    using Vector = dealii::PETScWrappers::MPI::Vector;

    TissueModel(MPI_Comm                                  comm,
                const TissueParameters                   &parameters,
                const Material                           &material,
                const BoundaryConditions                 &boundary_conditions,
                dealii::parallel::distributed::Triangulation<3> &triangulation,
                dealii::TimerOutput                      &timer);

    /// Distributes DoFs, builds sparsity, matrices, probes and reaction sets.
    void
    setup();

    dealii::types::global_dof_index
    n_dofs() const
    {
      return dof_handler.n_dofs();
    }

    /// Solves the quasi-static equilibrium at load level (time) @p t starting from the
    /// current state. On failure the state is whatever the last iterate was; callers
    /// restore it with restore_state(). @p force_floor (N) raises the absolute residual
    /// tolerance for this solve: a coupled solve needs the residual no smaller than the
    /// force its coupling resolves (e.g. a pierce tie's stiffness times the coupling
    /// tolerance), and chasing the relative tolerance of a solve that starts near
    /// equilibrium costs iterations for nothing.
    NewtonReport
    solve_static(double t, double force_floor = 0);

    /// solve_static() with @p body solved along (tissue/condensed_body.h): at every
    /// iterate the body is brought to equilibrium with the tissue's points held, and
    /// the Newton update solves (K + Nᵀ G N) Δu = −R by the Sherman–Morrison–Woodbury
    /// formula, with 3m more solves of the factorised K (m points: the coupled ones,
    /// then the other spread ones whose tangents K leaves out; low_rank_update()). The
    /// step is halved while an element inverts or the residual's norm does not fall
    /// (full steps while the boundary still moves); each trial state is shown to
    /// @p body (CondensedBody::observe()). Implemented in tissue_model_coupled.cc.
    NewtonReport
    solve_coupled(double t, double force_floor, CondensedBody &body);

    void
    save_state();
    void
    restore_state();

    /// This process's part of the state, for a checkpoint (io/checkpoint.h): the values
    /// of its DoFs and its cells' mixed fields p̃, J̃, in the order of this mesh, partition
    /// and numbering, and with the phase field its damage nodes' d; restore_local_state()
    /// takes them back on the same (the damage as accepted: the lower bound of the next
    /// step, as after save_state()).
    nlohmann::json
    local_state() const;
    void
    restore_local_state(const nlohmann::json &state);

    /// Reaction forces on every Dirichlet boundary at the current state and time. In
    /// dynamics, pass v and v̇: the support then also carries M v̇ + C v.
    std::vector<Reaction>
    reactions(double t, const Vector *velocity = nullptr, const Vector *acceleration = nullptr);

    /// Loads at material points that follow the deformation (needle coupling); nullptr
    /// removes them. Call again whenever @p loads' set of points changes (collective).
    void
    set_point_loads(const PointLoads *loads);

    /// Tells the linear solver whether the tangent will be symmetric
    /// (LinearSolver::set_symmetric(); @p why names the cause when it is not), before any
    /// point load exists: a setting that cannot solve it fails at setup, not mid-run.
    void
    expect_symmetric_tangent(bool symmetric, const std::string &why);

    /// Current position x = X + u(X) of point @p k of the point loads (collective), m.
    dealii::Point<3>
    point_position(std::size_t k) const;

    /// The reference position X of this process's DoF @p dof (its support point) and its
    /// component; NaN coordinates when this process does not own it (diagnostics: a
    /// loop over the cells).
    std::pair<dealii::Point<3>, unsigned>
    dof_location(dealii::types::global_dof_index dof) const;
    /// The last assembled residual's largest free entry in magnitude among this process's
    /// DoFs (N; the equilibrium part) and its DoF; not collective (diagnostics: a trace on
    /// one process reads it from CondensedBody::observe()).
    std::pair<double, dealii::types::global_dof_index>
    largest_free_residual() const;

    /// The boundary as triangles (collective), its vertices the boundary faces' corners
    /// (on a locally refined mesh hanging ones among them; the triangles then meet at
    /// T-junctions, without gaps since a hanging node stays on its coarse edge).
    BoundarySurface
    boundary_surface() const;

    /// Current positions x = X + u of the surface's vertices (collective), m.
    void
    surface_positions(const BoundarySurface &surface, Eigen::Matrix3Xd &x) const;

    /// Displacements at the probe points (m), in the order of the parameters.
    std::vector<dealii::Tensor<1, 3>>
    probe_displacements() const;

    /// Tear criteria at the current state (collective; tearing/tear_criterion.h): for
    /// each of @p criteria's criteria (outer) and each of @p zones (inner), the measure
    /// sampled at every quadrature point of every rank that lies in the zone. Keeps each
    /// criterion's cell mean of m / m_c for the next write_vtu() ("tear_<name>"). In
    /// tissue_tearing.cc.
    std::vector<std::vector<tearing::ZoneSample>>
    evaluate_tearing(const tearing::TearCriteria &criteria, const tearing::ProcessZones &zones);

    /// Writes tissue_<index>.vtu into @p directory (collective); returns the file name.
    std::string
    write_vtu(const std::string &directory, unsigned index, double t) const;

    /// Phase-field tearing (`Tissue/Phase field`; tearing/damage_field.h), staggered: the
    /// damage that minimises the damage energy for the current state's degradable energy
    /// (1 − k)(Ψ_iso(C̄) + Ψ_vol(J̃) in expansion), at least the damage of the last
    /// save_state() (which accepts it; restore_state() returns to it), and the degradation
    /// g = (1 − k)(1 − d)² + k that the assemblies use from then on (cell_assembler.h,
    /// volumetric_share()). Returns the largest change of d; 0 and nothing done without
    /// the phase field.
    double
    advance_damage();
    /// A step's alternate minimisation with the phase field (Bourdin, Francfort & Marigo,
    /// J Mech Phys Solids 48:797, 2000), after an equilibrium that converged: the damage
    /// of that equilibrium (advance_damage()), @p equilibrium again with it, until a damage
    /// solve changes d by at most `Phase field/Tolerance`, so that the step ends with a
    /// displacement and a damage that belong together. @p equilibrium solves and returns
    /// its failure ("" when it converged). Returns "" when the step settled, else why
    /// not: @p equilibrium's failure, the damage solve's (SolverError), or the passes
    /// run out (`Max passes`). @p changes receives each damage solve's largest change of d
    /// (empty without the phase field, when nothing is done).
    std::string
    minimise_alternately(const std::function<std::string()> &equilibrium, std::vector<double> &changes);
    /// The damage's part of a step's record ({max, growth, passes, changes,
    /// fracture_energy}: the damage solves of minimise_alternately() and their @p changes);
    /// null without the phase field.
    nlohmann::json
    damage_record(const std::vector<double> &changes) const;
    /// The damage field; nullptr without the phase field.
    const tearing::DamageField<3> *
    damage_field() const
    {
      return damage.get();
    }

    const std::vector<std::pair<std::string, dealii::Point<3>>> &
    probes() const
    {
      return parameters.probes;
    }

    const BoundaryConditions &
    boundary_conditions() const
    {
      return bc;
    }

    // --- implicit dynamics: y = [u; v], F(t, y, ẏ) = 0 --------------------------------
    // F_u = u̇ − v,  F_v = M v̇ + (a_M M + a_K K_t(u)) v + R(u, t) on free DoFs;
    // F_u = u − g(t), F_v = v − ġ(t) on Dirichlet DoFs (algebraic).

    void
    set_rayleigh_damping(double mass_coefficient, double stiffness_coefficient);

    /// Evaluates F; returns false if an element inverted (IDA then cuts the step).
    bool
    dynamic_residual(double        t,
                     const Vector &u,
                     const Vector &v,
                     const Vector &u_dot,
                     const Vector &v_dot,
                     Vector       &F_u,
                     Vector       &F_v);

    /// Assembles A = (1 + α a_K) K_t + (α² + α a_M) M at u; false if an element inverted.
    bool
    setup_dynamic_jacobian(double t, const Vector &u, double alpha);

    /// Solves the Jacobian system [αI, −I; K_t, αM + C] [x_u; x_v] = [b_u; b_v] exactly
    /// (Dirichlet rows: identity), by eliminating x_v and the Dirichlet values.
    void
    solve_dynamic_jacobian(const Vector &b_u,
                           const Vector &b_v,
                           Vector       &x_u,
                           Vector       &x_v,
                           double        tolerance);

    /// ġ(0) and g̈(0) into the Dirichlet entries of u̇ and v̇: IDA's consistent initial
    /// conditions keep the derivatives of algebraic components as given.
    void
    initial_boundary_rates(Vector &u_dot, Vector &v_dot) const;

    /// Locally owned DoFs and the Dirichlet DoFs among them (IDA's algebraic set).
    const dealii::IndexSet &
    locally_owned() const
    {
      return locally_owned_dofs;
    }
    dealii::IndexSet
    dirichlet_dofs() const;

    /// Sets the displacement state (for output and reactions during dynamics).
    void
    set_displacement(const Vector &u);

    const Vector &
    displacement() const
    {
      return solution;
    }

    const LinearSolver &
    linear_solver() const
    {
      return *solver;
    }

    /// The tangent K the last assembly left (its pattern is the cells' couplings only).
    const dealii::PETScWrappers::MPI::SparseMatrix &
    tangent() const
    {
      return system_matrix;
    }

  private:
    /// g at the quadrature points from the damage (cell_degradation)
    void
    update_degradation();
    /// g at quadrature point @p q of the cell with active index @p cell (1 without damage)
    double
    degradation(unsigned cell, unsigned q) const
    {
      return damage ? cell_degradation[cell][q] : 1.0;
    }
    /// Constraints at time t with inhomogeneity g(t) − u (so that one Newton update
    /// lands on the boundary values); returns max |g − u| over Dirichlet DoFs.
    double
    make_constraints(double t, const Vector &u_ghost, dealii::AffineConstraints<double> &c) const;

    /// Assembles −R into system_rhs (and K into system_matrix if @p with_matrix) at
    /// @p u_ghost. With @p velocity, adds Rayleigh damping. The mixed fields are Newton
    /// unknowns (cell_assembler.h) when the parameters ask for it, unless @p exact_mixed
    /// (the dynamics, whose residual must be a function of u). Returns false if any cell
    /// inverted (collective).
    bool
    assemble(double                                   t,
             const Vector                            &u_ghost,
             bool                                     with_matrix,
             const dealii::AffineConstraints<double> &c,
             const Vector                            *velocity_ghost = nullptr,
             bool                                     exact_mixed    = false);

    /// Subtracts the reference traction's share ∫ N t₀ dA over @p cell's loaded boundary
    /// faces from the cell residual @p r (reentrant: @p face_values is the caller's).
    void
    add_traction(const dealii::DoFHandler<3>::active_cell_iterator &cell,
                 const dealii::Function<3>                         &traction,
                 dealii::FEFaceValues<3>                           &face_values,
                 dealii::Vector<double>                            &r) const;

    /// The residual's norm over the free DoFs, N. With the mixed fields as Newton
    /// unknowns, sqrt(|r_u|² + |r_c|²) of the equilibrium part r_u and the constraint
    /// part r_c = Gᵀ (R_J + K_JJ M⁻¹ R_p) of the condensed residual, so that a state
    /// whose constraints do not hold is not taken for converged.
    double
    free_residual_norm() const;

    /// Newton update of the mixed fields that are Newton unknowns (no-op otherwise):
    /// begin_mixed_update() recovers every cell's Δp̃, ΔJ̃ from the displacement update
    /// @p update (constraints distributed), step_mixed(α) sets p̃₀ + α Δp̃, J̃₀ + α ΔJ̃.
    void
    begin_mixed_update(const Vector &update);
    void
    step_mixed(double alpha);

    /// Whether the state is on its boundary values, to round-off, given the largest
    /// |g − u| over the Dirichlet DoFs @p gap.
    bool
    boundary_reached(double gap) const;
    /// The largest constraint residual of the cells' mixed fields when they are Newton
    /// unknowns (0 otherwise; collective): M⁻¹R_p (1) and R_J / (κ V_cell) (1). The
    /// free-DoF residual can miss them: a uniform error in p̃ exerts no force on the free
    /// DoFs of a body held on every face (docs/tearing.md, "Found on the way").
    double
    mixed_residual() const;
    /// The end test of a Newton iterate @p it (the residual criteria of
    /// NewtonParameters or an update at round-off, with the mixed fields' own residuals
    /// below 1e-6; divergence; the iteration limit): true
    /// when the iteration must stop, with @p report converged or saying why not.
    bool
    newton_stop(unsigned it, double r_norm, double r_ref, double du_norm, double du_max, double gap,
                double force_floor, NewtonReport &report) const;

    /// Positions X + W v of every point load for the vector @p v (collective; see
    /// EmbeddedPoints); with @p displacement false, W v alone (the points' share of an
    /// update).
    std::vector<dealii::Point<3>>
    point_values(const Vector &v, bool displacement) const;

    /// The Newton update (K + Nᵀ (G − L) N) Δu = −R by the Sherman–Morrison–Woodbury
    /// identity, Δu = z0 − Z (I + (G − L) N Z)⁻¹ (G − L) N z0 with z0 = K⁻¹(−R) and
    /// Z = K⁻¹Nᵀ (one call for the 3m columns of the @p all_points) from one factorisation of
    /// the assembled K: G (3m × 3m) the stiffness of a body condensed onto the points
    /// (solve_coupled(); zero for none), L their tangents' parts that K leaves out
    /// (EmbeddedPoints::low_rank()). Points whose rows and columns of G − L are zero
    /// (contact pairs apart) are left out of N: they add nothing, and each would cost
    /// three columns of Z. No points left: Δu = z0. Returns the Krylov iterations of
    /// z0's solve, to @p tolerance; throws SolverError.
    unsigned
    low_rank_update(const std::vector<std::size_t> &all_points, const Eigen::MatrixXd &G, double tolerance,
                    Vector &update);

    /// g, ġ, g̈ at the locally owned Dirichlet DoFs (order of owned_dirichlet).
    void
    boundary_values(double               t,
                    std::vector<double> &g,
                    std::vector<double> &g_dot,
                    std::vector<double> &g_ddot) const;

    /// a·b over the free (non-Dirichlet) DoFs.
    double
    free_dot(const Vector &a, const Vector &b) const;

    void
    assemble_mass_matrix();

    /// The tangent's sparsity: the cells' couplings under the constraints (point loads
    /// stay within their cell's; spread ones are a low-rank update).
    void
    make_system_matrix();

    /// Fills reaction_dofs (setup()).
    void
    find_reaction_dofs();
    /// Finds the cell and rank of every probe (setup()); throws InputError for a probe
    /// outside the mesh.
    void
    locate_probes();

    std::vector<Vector>
    rigid_body_modes() const;

    MPI_Comm                                        comm;
    TissueParameters                                parameters;
    const Material                                 &material;
    const BoundaryConditions                       &bc;
    dealii::parallel::distributed::Triangulation<3> &tria;
    dealii::TimerOutput                            &timer;

    dealii::MappingQ1<3>     mapping;
    dealii::FESystem<3>      fe;
    dealii::DoFHandler<3>    dof_handler;
    dealii::QGauss<3>        quadrature;
    dealii::QGauss<2>        face_quadrature;
    std::unique_ptr<CellAssembler> cell_assembler;
    std::unique_ptr<EmbeddedPoints> embedded;
    const PointLoads               *point_loads = nullptr;
    std::unique_ptr<LinearSolver>  solver;

    dealii::IndexSet                        locally_owned_dofs, locally_relevant_dofs;
    dealii::AffineConstraints<double>       constraints;
    std::vector<dealii::types::global_dof_index> owned_dirichlet;
    dealii::PETScWrappers::MPI::SparseMatrix system_matrix, mass_matrix, jacobian_full;
    Vector solution, solution_ghost, saved_solution, system_rhs, full_residual, constraint_force;
    /// p̃, J̃ of every cell (active cell index); Newton unknowns when pressure_unknowns
    std::vector<MixedCell> cell_mixed, saved_cell_mixed;
    /// phase-field tearing: the damage, and g at every quadrature point of each locally
    /// owned cell (by active cell index)
    std::unique_ptr<tearing::DamageField<3>> damage;
    std::vector<std::vector<double>>        cell_degradation;
    /// Cell data for write_vtu(), from the last evaluate_tearing().
    std::vector<std::pair<std::string, dealii::Vector<float>>> tear_fields;
    bool                   pressure_unknowns = false;

    /// Per Dirichlet boundary: locally owned DoFs on it with their component.
    std::vector<std::vector<std::pair<dealii::types::global_dof_index, unsigned>>> reaction_dofs;

    struct ProbeLocation
    {
      bool                                      here = false;
      dealii::DoFHandler<3>::active_cell_iterator cell;
      dealii::Point<3>                          unit_point;
    };
    std::vector<ProbeLocation> probe_locations;

    double length_scale  = 1; ///< m, mesh diameter (round-off test of Newton updates)
    double rayleigh_mass = 0, rayleigh_stiffness = 0;
    double jacobian_alpha = 0;
  };
} // namespace suturesim::tissue
