#pragma once
/**
 * @file
 * Forces at material points of the tissue that depend on where those points are now —
 * the needle tip's touch and the pierce points (coupling/). The coupling implements
 * PointLoads; EmbeddedPoints finds each material point X in its cell (reference
 * coordinates ξ, no remeshing) and adds, to that cell,
 *   residual  r_i −= N_i(ξ) · f(x),           x = X + Σ_j N_j(ξ) u_j,
 *   tangent   K_ij −= N_i(ξ) · (∂f/∂x) N_j(ξ),
 * so that R = f_int − f_ext keeps its sign convention and Newton stays quadratic when
 * ∂f/∂x is exact (a penalty spring: f = −k d, ∂f/∂x = −k: K gains +k N_iN_j).
 */

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <map>
#include <vector>

namespace suturesim::tissue
{
  class PointLoads
  {
  public:
    virtual ~PointLoads() = default;

    /// Reference positions X_k (m); they must not change during a Newton solve.
    virtual const std::vector<dealii::Point<3>> &
    points() const = 0;

    /// Force on the tissue at point @p k whose current position is @p x (N), and its
    /// derivative ∂f/∂x (N/m).
    virtual void
    force(std::size_t k, const dealii::Point<3> &x, dealii::Tensor<1, 3> &f,
          dealii::Tensor<2, 3> &df_dx) const = 0;

    /// Whether every ∂f/∂x of force() is symmetric, so that the tissue's tangent stays
    /// symmetric and a Cholesky factorisation solves it (tissue/linear_solver.h).
    virtual bool
    symmetric_tangent() const
    {
      return true;
    }
  };

  class EmbeddedPoints
  {
  public:
    EmbeddedPoints(const dealii::Mapping<3> &mapping, const dealii::FiniteElement<3> &fe,
                   const dealii::DoFHandler<3> &dof_handler, MPI_Comm comm);

    /// Finds the cell of every point of @p loads (collective): the lowest rank owning a
    /// cell that holds it assembles it. Throws std::invalid_argument naming a point
    /// outside the mesh.
    void
    locate(const PointLoads &loads);

    /// Adds the loads at the points inside @p cell to its residual @p r and, if given,
    /// tangent @p K (cell-local, the cell's DoF order), at the cell's displacements
    /// @p u_local.
    void
    add(const dealii::DoFHandler<3>::active_cell_iterator &cell, const dealii::Vector<double> &u_local,
        dealii::Vector<double> &r, dealii::FullMatrix<double> *K) const;

    /// Adds the nodal forces of a force @p f at point @p k, Σ_i N_i(ξ) f, into @p rhs
    /// through @p constraints (constrained entries left alone), on the rank that owns
    /// the point.
    template <typename VectorType>
    void
    add_point_force(std::size_t k, const dealii::Tensor<1, 3> &f, const dealii::AffineConstraints<double> &constraints,
                    VectorType &rhs) const;

    /// Current position of point @p k from the ghosted displacement @p u (on the rank
    /// that owns it; the others return NaN): x = X + u(X).
    template <typename VectorType>
    dealii::Point<3>
    position(std::size_t k, const VectorType &u) const;

  private:
    const dealii::Mapping<3>        &mapping;
    const dealii::FiniteElement<3>  &fe;
    const dealii::DoFHandler<3>     &dof_handler;
    MPI_Comm                         comm;
    const PointLoads                *loads = nullptr;
    struct Located
    {
      std::size_t      k;
      dealii::Point<3> unit;
    };
    std::map<unsigned int, std::vector<Located>> by_cell; ///< active cell index → its points
    std::vector<std::pair<dealii::DoFHandler<3>::active_cell_iterator, dealii::Point<3>>> where;
    std::vector<bool> mine;
  };
} // namespace suturesim::tissue
