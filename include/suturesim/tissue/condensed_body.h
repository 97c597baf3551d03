#pragma once
/**
 * @file
 * A body coupled to the tissue through some of its point loads (the suture through its
 * pierce points and contacts), solved together with the tissue in one Newton iteration
 * by nonlinear elimination: at every tissue iterate u the body is brought to its own
 * equilibrium q(y) with the tissue's points held at y = N u, and its response is
 * condensed onto those points. The tissue's residual R(u, q(y(u))) then has the exact
 * tangent
 *   K + Nᵀ G N,   G = F_q D⁻¹ H,
 * K the tissue's own tangent (with the point loads' ∂f/∂x), F_q = ∂f/∂q the loads'
 * change with the body's unknowns, D = ∂R_b/∂q the body's Jacobian and H = ∂R_b/∂y its
 * change with the points (differentiating R_b(q(y), y) = 0 gives dq/dy = −D⁻¹ H). A
 * partitioned iteration between the two solves contracts only by how much softer the
 * coupling is than the bodies; this is Newton's method on the pair (the "Schur complement
 * on the interface" of domain decomposition; Quarteroni & Valli 1999, §1.3).
 */

#include <deal.II/base/point.h>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace suturesim::tissue
{
  class CondensedBody
  {
  public:
    virtual ~CondensedBody() = default;

    /// The tissue's point loads (indices among them) the body acts through, m of them.
    virtual std::vector<std::size_t>
    coupled_points() const = 0;

    /// Brings the body to equilibrium with the tissue's point loads at @p x (one per
    /// point load, m) and returns G (3m × 3m, the points of coupled_points() in order,
    /// three coordinates each). False, with @p failure saying why, when the body's own
    /// solve fails.
    virtual bool
    equilibrate(const std::vector<dealii::Point<3>> &x, Eigen::MatrixXd &G, std::string &failure) = 0;

    /// A state a coupled solve brought the body to equilibrium in (observe()).
    struct Trial
    {
      unsigned iteration = 0;     ///< the iterate it is a trial for (0: the solve's start)
      unsigned halvings  = 0;     ///< of the Newton update before this trial
      double   step      = 0;     ///< the fraction of the update taken, 1
      double   residual  = 0;     ///< the tissue's free residual norm there, N; NaN when not reached
      bool     taken     = false; ///< whether the solve went on from it
      double   moved     = 0;     ///< the largest DoF's change from the iterate before, α |Δu|∞, m
    };
    /// Called by TissueModel::solve_coupled() after each trial state, the start's
    /// included (and after one whose equilibrate() failed); for a body that watches
    /// the solve (scene/coupled_newton_trace.h). Ignored by default.
    virtual void
    observe(const Trial &)
    {}
  };
} // namespace suturesim::tissue
