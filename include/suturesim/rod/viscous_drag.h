#pragma once
/**
 * @file
 * A viscous drag on the suture's nodes for quasi-static steps (Suture/Stabilization):
 * c v per unit length of thread, v ≈ (x − xₙ)/Δt with xₙ the node at the last accepted
 * step, lumped to the nodes as
 *   r_i += c ℓ_i (x_i − x_i,n)/Δt,   J_ii += c ℓ_i/Δt I,
 * ℓ_i half the length of each element beside node i. It gives a slack thread, which
 * has no stiffness against rigid motion, a unique quasi-static position (the usual
 * pseudo-dynamic stabilisation of quasi-static contact and cable problems, e.g. the
 * "viscous regularization" of Abaqus' STABILIZE option) and vanishes as the motion stops;
 * its total over the free nodes is recorded so that its share of any force is known.
 */

#include <suturesim/rod/rod_model.h>

#include <vector>

namespace suturesim::rod
{
  class ViscousDrag
  {
  public:
    /// Drag coefficient @p c per unit length (N s/m²) on the nodes of @p model.
    ViscousDrag(const RodModel &model, double c);

    /// The start of a step of length @p dt from the nodes at @p start (kept by the caller).
    void
    begin_step(const std::vector<Vec3> *start, double dt);

    /// Adds node @p i's drag at position @p x to its residual @p r and Jacobian @p J.
    void
    add(std::size_t i, const Vec3 &x, Vec6 &r, Mat6 &J) const;

    /// Σ |c ℓ_i (x_i − x_i,n)/Δt| over the free nodes (the ends excluded) at @p x, N: an
    /// upper bound of what the drag adds to any force recorded.
    double
    total_force(const std::vector<Vec3> &x) const;

    bool
    active() const
    {
      return coefficient > 0;
    }

  private:
    double                   coefficient;
    std::vector<double>      node_length;
    const std::vector<Vec3> *start = nullptr;
    double                   step  = 0;
  };
} // namespace suturesim::rod
