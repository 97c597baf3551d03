#pragma once
/**
 * @file
 * Tear propagation: AT1 phase-field fracture (Pham, Amor, Marigo & Maurini, Int J Damage
 * Mech 20:618, 2011), the gradient-damage model whose elastic limit the fracture-energy
 * criterion already uses (criteria/fracture_energy.cc), so that onset and propagation
 * share one toughness G_c and one length ℓ. For a displacement u and a damage d ∈ [0, 1]
 *
 *   E(u, d) = ∫ g(d) ψ(ε(u)) dx + G_c / c_w ∫ (w(d) / ℓ + ℓ |∇d|²) dx − ∫_Γ t · u ds,
 *   g(d) = (1 − d)² + k,   w(d) = d,   c_w = 4 ∫₀¹ √w = 8/3,
 *   ψ(ε) = λ/2 (tr ε)² + μ ε : ε,
 *
 * minimised alternately (Bourdin, Francfort & Marigo, J Mech Phys Solids 48:797, 2000):
 * u for fixed d is a linear solve (MUMPS); d for fixed u is the bound-constrained
 * quadratic program of damage_field.h. AT1 has an elastic phase: d stays 0 while
 * ψ < ψ_c = 3 G_c / (16 ℓ), and a homogeneous state above it has d = 1 − ψ_c / ψ.
 *
 * With linear elements of size h a crack dissipates G_c (1 + h / (4 c_w' ℓ)) per unit area
 * with c_w' = 2/3 for AT1, i.e. the effective toughness G_c (1 + 3 h / (8 ℓ)) (Bourdin,
 * Francfort & Marigo, J Elasticity 91:5, 2008, §8.1.1): the toughness a comparison with
 * linear elastic fracture mechanics must use (effective_toughness()).
 *
 * Small strain, isotropic linear elasticity (plane strain in 2-D), no tension-compression
 * split of ψ, Q1 for both fields; hanging nodes allowed (p4est refinement along a path).
 * This is the propagation model as verified against LEFM (benchmarks/sent_phase_field);
 * the finite-strain tissue drives the same damage field with the energy it degrades
 * (tissue_model.h, `Tissue/Phase field`).
 */

#include <suturesim/tearing/damage_field.h>

#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/component_mask.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include <functional>
#include <map>
#include <string>
#include <vector>

namespace suturesim::tearing
{
  struct PhaseFieldParameters
  {
    double youngs_modulus = 0; ///< E (Pa)
    double poissons_ratio = 0; ///< ν (1), in [0, 0.5)
    double toughness      = 0; ///< G_c (J/m²)
    double length         = 0; ///< ℓ (m)
    /// k: the stiffness a fully damaged point keeps, relative (1), so that u stays unique
    double residual_stiffness = 1e-6;
    /// the alternate minimisation stops when no damage value changes by more than this (1)
    double tolerance = 1e-4;
    /// and fails after this many iterations
    unsigned max_iterations = 1000;
  };

  template <int dim>
  class PhaseFieldFracture
  {
  public:
    /// u = load × @p displacement on @p components of the boundary @p boundary.
    struct Support
    {
      dealii::types::boundary_id boundary;
      dealii::ComponentMask      components;
      dealii::Tensor<1, dim>     displacement = {}; ///< m at load factor 1
    };
    /// u = 0 on @p components at the mesh vertex at @p point.
    struct Pin
    {
      dealii::Point<dim>    point;
      dealii::ComponentMask components;
    };
    struct Loading
    {
      std::vector<Support> supports;
      std::vector<Pin>     pins;
      /// the traction (Pa) on each boundary at load factor 1
      std::map<dealii::types::boundary_id, dealii::Tensor<1, dim>> tractions;
      /// the initial crack: d = 1 at the damage nodes where it returns true
      std::function<bool(const dealii::Point<dim> &)> cracked;
    };

    /// The alternate minimisation of one load.
    struct Step
    {
      unsigned iterations = 0;
      bool     converged  = false;
      /// whether solve()'s @p stop ended it before convergence
      bool   stopped = false;
      double change  = 0; ///< the last iteration's largest damage change
    };

    PhaseFieldFracture(MPI_Comm comm, const PhaseFieldParameters &parameters,
                       const dealii::parallel::distributed::Triangulation<dim> &tria, Loading loading);
    ~PhaseFieldFracture();
    PhaseFieldFracture(const PhaseFieldFracture &) = delete;
    PhaseFieldFracture &
    operator=(const PhaseFieldFracture &) = delete;

    /// Minimises E alternately at load factor @p load (tractions and support
    /// displacements × load) from the current
    /// state; @p stop, called after each iteration, may end it early (a crack that runs).
    /// SolverError when the damage problem fails or the iterations run out.
    Step
    solve(double load, const std::function<bool()> &stop = {});
    /// Makes the current state the accepted one: its damage is the new lower bound.
    void
    accept();
    /// Returns to the last accepted state (the initial crack at first).
    void
    restore();

    /// ∫ g(d) ψ dx and G_c / c_w ∫ (d / ℓ + ℓ |∇d|²) dx (J per unit thickness in 2-D).
    double
    elastic_energy() const;
    double
    fracture_energy() const;
    /// The largest @p coordinate(x) over the damage nodes with d ≥ @p threshold;
    /// −∞ when there is none.
    double
    damage_extent(const std::function<double(const dealii::Point<dim> &)> &coordinate, double threshold) const;
    /// The smallest and the largest damage value.
    std::pair<double, double>
    damage_range() const;
    /// The displacement at @p point (a mesh vertex), on every process.
    dealii::Tensor<1, dim>
    displacement_at(const dealii::Point<dim> &point) const;
    /// The smallest cell's edge length h = |K|^(1/dim) (m) among the cells where
    /// @p where is true of the centre (all when empty).
    double
    smallest_cell_size(const std::function<bool(const dealii::Point<dim> &)> &where = {}) const;
    /// G_c (1 + 3 h / (8 ℓ)): the toughness the discretised crack dissipates.
    double
    effective_toughness(double h) const;
    /// ψ_c = 3 G_c / (16 ℓ): the energy density at which damage starts.
    double
    damage_threshold() const;

    dealii::types::global_dof_index
    n_dofs() const;
    /// Writes displacement and damage to @p file (.vtu, collectively); WriteError.
    void
    write_vtu(const std::string &file, double time, unsigned index) const;

  private:
    void
    setup();
    /// hanging nodes, pins and supports at load factor @p load
    void
    make_displacement_constraints(double load);
    void
    solve_displacement(double load);
    /// The damage for the current u; returns the largest change of d.
    double
    solve_damage();

    MPI_Comm                                                 comm;
    PhaseFieldParameters                                     parameters;
    const dealii::parallel::distributed::Triangulation<dim> &tria;
    Loading                                                  loading;
    double                                                   lambda, mu;

    dealii::FESystem<dim>           fe_u;
    dealii::DoFHandler<dim>         dof_u;
    dealii::IndexSet                owned_u, relevant_u;
    dealii::AffineConstraints<double> constraints_u;
    DamageField<dim>                damage;

    dealii::PETScWrappers::MPI::SparseMatrix stiffness;
    dealii::PETScWrappers::MPI::Vector       u, u_ghost, u_accepted;
  };
} // namespace suturesim::tearing
