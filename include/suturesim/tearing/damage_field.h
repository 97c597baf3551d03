#pragma once
/**
 * @file
 * The damage half of AT1 phase-field fracture (Pham, Amor, Marigo & Maurini, Int J Damage
 * Mech 20:618, 2011). For an elastic energy density ψ ≥ 0 of the undamaged material (Pa),
 * given at quadrature points, the damage d minimises
 *
 *   ∫ (1 − d)² ψ dx + G_c / c_w ∫ (d / ℓ + ℓ |∇d|²) dx,   c_w = 4 ∫₀¹ √d dd = 8/3,
 *
 * over d_accepted ≤ d ≤ 1 (irreversibility: a tear never heals). The problem is quadratic
 * in d; the bounds make it a quadratic program, solved by PETSc's reduced-space
 * active-set Newton method (SNESVINEWTONRSLS) with MUMPS. A homogeneous ψ gives d = 0 up
 * to ψ_c = 3 G_c / (16 ℓ) and d = 1 − ψ_c / ψ above it.
 *
 * Q1 on the displacement's triangulation; hanging nodes allowed (their rows hold their
 * constraint equations, and they are free of bounds: a mean of bounded values).
 *
 * The small-strain specimen (phase_field.h) and the finite-strain tissue
 * (tissue_model.h, `Tissue/Phase field`) pass the energy they degrade by (1 − d)²: the
 * specimen ψ with g = (1 − d)² + k, the tissue (1 − k) ψ with its g = (1 − k)(1 − d)² + k
 * (tissue/cell_assembler.h, degradation()). The damage problem is stated here once.
 */

#include <deal.II/base/point.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>
#include <deal.II/numerics/data_out.h>

#include <functional>
#include <utility>
#include <vector>

namespace suturesim::tearing
{
  template <int dim>
  class DamageField
  {
  public:
    using Cell = typename dealii::Triangulation<dim>::active_cell_iterator;
    /// Fills ψ (Pa, the undamaged material's) at the points of quadrature() on a
    /// locally owned cell.
    using Driving = std::function<void(const Cell &, std::vector<double> &)>;

    /// @p toughness G_c (J/m²) and @p length ℓ (m), both > 0 (the caller checks them);
    /// ψ sampled at the Gauss points of @p quadrature_points per direction (the
    /// displacement's, so that both halves of the staggered solve see the same points).
    DamageField(MPI_Comm comm, const dealii::parallel::distributed::Triangulation<dim> &tria, double toughness,
                double length, unsigned quadrature_points = 2);
    ~DamageField();
    DamageField(const DamageField &) = delete;
    DamageField &
    operator=(const DamageField &) = delete;

    /// d = 1, accepted, at the damage nodes where @p cracked is true (an initial crack).
    void
    crack(const std::function<bool(const dealii::Point<dim> &)> &cracked);

    /// Minimises over d for the energy density @p psi; returns the largest change of d.
    /// SolverError when PETSc's solve fails.
    double
    solve(const Driving &psi);
    /// Makes the current damage the accepted one: the new lower bound.
    void
    accept();
    /// Returns to the accepted damage.
    void
    restore();
    /// d at this process's own damage nodes, in their order: its part of a checkpoint.
    std::vector<double>
    owned_values() const;
    /// d = @p values at this process's own damage nodes (owned_values()'s order), and
    /// accepted: a checkpoint taken back. std::invalid_argument when the number differs.
    void
    restore_owned_values(const std::vector<double> &values);

    /// The quadrature of solve()'s ψ.
    const dealii::Quadrature<dim> &
    quadrature() const
    {
      return quadrature_d;
    }
    const dealii::DoFHandler<dim> &
    dof_handler() const
    {
      return dof_d;
    }
    /// d with its ghost entries (for FEValues on dof_handler()'s cells).
    const dealii::PETScWrappers::MPI::Vector &
    ghosted() const
    {
      return d_ghost;
    }
    /// d (1) at the points of @p quadrature on every locally owned cell, by the cell's
    /// active index (empty for the others).
    std::vector<std::vector<double>>
    cell_values(const dealii::Quadrature<dim> &quadrature) const;

    /// The nodal values of d on every locally owned cell, by the cell's active index
    /// (empty for the others): a plain copy that threads may read.
    std::vector<dealii::Vector<double>>
    cell_dof_values() const;
    /// d at @p unit, a point of the reference cell, from its cell's @p dof_values.
    double
    value(const dealii::Vector<double> &dof_values, const dealii::Point<dim> &unit) const;

    /// G_c / c_w ∫ (d / ℓ + ℓ |∇d|²) dx (J; J per unit thickness in 2-D).
    double
    fracture_energy() const;
    /// The smallest and the largest damage value.
    std::pair<double, double>
    range() const;
    /// The largest growth of d since the last accept().
    double
    growth() const;
    /// The largest @p coordinate(x) over the damage nodes with d ≥ @p threshold; −∞
    /// when there is none.
    double
    extent(const std::function<double(const dealii::Point<dim> &)> &coordinate, double threshold) const;
    /// ψ_c = 3 G_c / (16 ℓ) (Pa): the energy density at which damage starts.
    double
    threshold() const;
    dealii::types::global_dof_index
    n_dofs() const
    {
      return dof_d.n_dofs();
    }
    /// Adds d as the nodal field "damage" to @p out (attached to the same triangulation).
    void
    add_to(dealii::DataOut<dim> &out) const;

  private:
    void
    set_bounds();
    /// max |d − @p other| over the damage nodes
    double
    distance_to(const dealii::PETScWrappers::MPI::Vector &other) const;

    MPI_Comm                                                 comm;
    double                                                   gc, ell;
    dealii::FE_Q<dim>                                        fe_d;
    dealii::DoFHandler<dim>                                  dof_d;
    dealii::QGauss<dim>                                      quadrature_d;
    dealii::IndexSet                                         owned, relevant;
    dealii::AffineConstraints<double>                        constraints;
    dealii::PETScWrappers::MPI::SparseMatrix                 matrix;
    dealii::PETScWrappers::MPI::Vector                       d, d_ghost, d_accepted, rhs, lower, upper;
  };
} // namespace suturesim::tearing
