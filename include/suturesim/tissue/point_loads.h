#pragma once
/**
 * @file
 * Forces at material points of the tissue that depend on where those points are now —
 * the needle tip's touch and the pierce points (coupling/). The coupling implements
 * PointLoads; EmbeddedPoints represents each point k on the mesh (reference
 * coordinates, no remeshing) by constant weights W_kI over displacement DoFs I:
 *   position  x_k = X_k + Σ_I W_kI u_I e_c(I),
 *   residual  r_I −= W_kI f_c(I)(x_k),
 *   tangent   K_IJ −= W_kI (∂f/∂x)_c(I)c(J) W_kJ   (in K, or as a low-rank update),
 * so that R = f_int − f_ext keeps its sign convention and Newton stays quadratic when
 * ∂f/∂x is exact (a penalty spring: f = −k d, ∂f/∂x = −k: K gains +k W_I W_J). The
 * same weights interpolate the point's motion and spread its force, so the coupling
 * does work f·δx and the tangent is symmetric whenever ∂f/∂x is.
 *
 * A point load (spread radius ρ = 0) takes W_kI = N_I(ξ), the shape functions at the
 * point in its cell. Its displacement has no mesh limit: under a point force F in an
 * elastic solid u ~ F/(8πμ r) (Kelvin's solution; Timoshenko & Goodier, "Theory of
 * Elasticity", 1970, §136), and a mesh of size h measures it at r ~ h. With ρ > 0 the
 * point stands for the tissue within ρ of X in the reference configuration, weighted by
 * the kernel φ(s) = (1 − s²)², s = |X' − X|/ρ (mesh/spread_kernel.h, shared with the
 * realtime path):
 *   W_kI = ∫_{|X'−X|<ρ} φ N_I dV / ∫ φ dV,
 * the smoothed delta of immersed-boundary methods, which interpolate and spread with
 * the same kernel (Peskin 2002, Acta Numerica 11:479–517, §6). The integrals use a
 * Gauss rule iterated until its points are no further than ρ/4 apart, so that the
 * weights are resolved on any mesh and their mesh limit is the kernel's. Hanging-node
 * constraints are folded into the weights; rows and columns that the solve's
 * constraints fix (Dirichlet values) are left to those constraints. A spread point's
 * tangent is not assembled into K but added by the solve as a rank-3 update
 * (EmbeddedPoints::low_rank()): in K it would be a dense block over the ball.
 */

#include <deal.II/base/mpi.h>
#include <deal.II/base/point.h>
#include <deal.II/base/tensor.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/affine_constraints.h>
#include <deal.II/lac/petsc_sparse_matrix.h>
#include <deal.II/lac/petsc_vector.h>

#include <map>
#include <utility>
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

    /// Whether point @p k's ∂f/∂x is symmetric: a coupled solve that condenses the
    /// non-symmetric points' skew parts (EmbeddedPoints::set_condensed()) leaves a
    /// symmetric tangent when every other point's is.
    virtual bool
    symmetric_at(std::size_t /*k*/) const
    {
      return symmetric_tangent();
    }

    /// Radius ρ of the tissue that carries point @p k's force (m): 0 for a point load;
    /// see EmbeddedPoints for the kernel.
    virtual double
    spread_radius(std::size_t /*k*/) const
    {
      return 0;
    }

    /// Whether the tissue at reference point @p Y lies beyond a cut (the wound's faces)
    /// from spread point @p k: the point then takes none of it, neither its motion nor a
    /// share of its force, as the visibility criterion of meshless methods leaves out
    /// what a crack hides (Belytschko, Lu & Gu 1994, Int J Numer Meth Eng 37:229–256,
    /// §6). Default: no cut, every tissue point within the radius.
    virtual bool
    cut_off(std::size_t /*k*/, const dealii::Point<3> & /*Y*/) const
    {
      return false;
    }
  };

  class EmbeddedPoints
  {
  public:
    using Matrix = dealii::PETScWrappers::MPI::SparseMatrix;
    using Vector = dealii::PETScWrappers::MPI::Vector;

    EmbeddedPoints(const dealii::Mapping<3> &mapping, const dealii::FiniteElement<3> &fe,
                   const dealii::DoFHandler<3> &dof_handler, MPI_Comm comm);

    /// Finds every point of @p loads (collective): the lowest rank owning a cell that
    /// holds it evaluates its force law; its weights, with the hanging-node lines of
    /// @p constraints folded in, are known on every rank. Throws std::invalid_argument
    /// naming a point outside the mesh.
    void
    locate(const PointLoads &loads, const dealii::AffineConstraints<double> &constraints);

    /// Whether some point is spread (ρ > 0).
    bool
    spread() const
    {
      return any_spread;
    }

    /// Adds the loads at displacements @p u (collective) to the residual @p full
    /// (R = f_int − f_ext, every owned row), to the right-hand side @p rhs (−R, the rows
    /// @p c leaves free) and, if given, to the tangent @p K (those rows and columns; a
    /// fixed column's inhomogeneity moved to @p rhs as AffineConstraints does), except
    /// the low-rank part of the points' ∂f/∂x (low_rank()), kept for the solve.
    void
    assemble(const Vector &u, const dealii::AffineConstraints<double> &c, Matrix *K, Vector &rhs,
             Vector &full);

    /// Points named here (the coupled solve's, TissueModel::solve_coupled()) have the
    /// skew part S = ½(A − Aᵀ) of their ∂f/∂x = A left to the low-rank update
    /// (low_rank()), so that friction on the thread leaves a symmetric matrix for MUMPS's
    /// Cholesky; empty (the default): none.
    void
    set_condensed(const std::vector<std::size_t> &points);

    /// Whether assemble() leaves part of point @p k's ∂f/∂x = A out of the tangent K, as
    /// L_k (low_rank_tangent()), for the solve to add as the low-rank update Nᵀ(−L)N by
    /// the Sherman–Morrison–Woodbury identity (TissueModel::low_rank_update()):
    ///  - a spread point (ρ > 0), the whole of A: its weights span every DoF within ρ, and
    ///    W A Wᵀ in K would couple them all, a dense block of (3n)² entries for n nodes in
    ///    the ball (about 1 900 DoFs per point for Q2 cells of 0.75 mm and ρ = 2 mm) that
    ///    MUMPS factorises as a dense front, in a pattern rebuilt whenever the points
    ///    move (docs/accurate_tissue.md, "Spread loads as a low-rank update");
    ///  - a point set_condensed() names, its skew part S.
    bool
    low_rank(std::size_t k) const
    {
      return spread_point[k] || (k < condensed.size() && condensed[k]);
    }

    /// Every point low_rank() names, in order.
    std::vector<std::size_t>
    low_rank_points() const;

    /// L_k of point @p k at the last assemble(): A for a spread point, S for a condensed
    /// one, zero for the rest.
    const dealii::Tensor<2, 3> &
    low_rank_tangent(std::size_t k) const
    {
      return low[k];
    }

    /// Whether the tangent assemble() adds is symmetric: every ∂f/∂x it keeps is.
    bool
    symmetric() const;

    /// Adds the nodal forces of a force @p f at point @p k, Σ_I W_kI f, into the owned
    /// rows of @p rhs that @p constraints leave free.
    void
    add_point_force(std::size_t k, const dealii::Tensor<1, 3> &f, const dealii::AffineConstraints<double> &constraints,
                    Vector &rhs) const;

    /// Current positions of all points from the displacement @p u (collective; the
    /// same on every rank): x_k = X_k + Σ_I W_kI u_I.
    std::vector<dealii::Point<3>>
    positions(const Vector &u) const;

    /// The weights of point @p k: (DoF, component, W), by DoF.
    struct Weight
    {
      dealii::types::global_dof_index dof;
      unsigned                        component;
      double                          value;

      /// For Utilities::MPI::all_gather().
      template <class Archive>
      void
      serialize(Archive &archive, const unsigned int /*version*/)
      {
        archive &dof &component &value;
      }
    };
    const std::vector<Weight> &
    weights(std::size_t k) const
    {
      return weight[k];
    }

  private:
    /// The cell that holds @p X and its unit point there (collective); @p here: this
    /// rank owns it (the lowest rank that does). Throws std::invalid_argument for a
    /// point outside the mesh.
    std::pair<dealii::DoFHandler<3>::active_cell_iterator, dealii::Point<3>>
    find(const dealii::Point<3> &X, bool &here) const;

    /// Every rank's @p raw weights of one point normalised to sum to one, folded through
    /// the hanging-node lines of @p constraints and summed (collective); empty when they
    /// sum to zero.
    std::vector<Weight>
    gather(const std::map<dealii::types::global_dof_index, Weight> &raw,
           const dealii::AffineConstraints<double>                 &constraints) const;

    /// The weights of point @p k at @p X over the locally owned cells near it (the kernel,
    /// without what PointLoads::cut_off() leaves out), this rank's part.
    std::map<dealii::types::global_dof_index, Weight>
    local_weights(std::size_t k, const dealii::Point<3> &X, double rho) const;

    const dealii::Mapping<3>        &mapping;
    const dealii::FiniteElement<3>  &fe;
    const dealii::DoFHandler<3>     &dof_handler;
    MPI_Comm                         comm;
    const PointLoads                *loads = nullptr;
    std::vector<std::vector<Weight>> weight;
    std::vector<bool>                mine; ///< this rank evaluates the point's force law
    std::vector<bool>                spread_point; ///< ρ > 0
    std::vector<bool>                condensed;
    std::vector<dealii::Tensor<2, 3>> low; ///< low_rank_tangent()
    bool                             any_spread = false;
  };
} // namespace suturesim::tissue
