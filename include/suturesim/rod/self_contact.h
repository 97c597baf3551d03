#pragma once
/**
 * @file
 * Rod self-contact by penalty on the distance between closest points of non-adjacent
 * segments (seed 002's collision constraint and seed 000's repelling force, made a
 * potential so it enters the implicit solve with a tangent). With gap
 * g = |p(s) − q(t)| − 2r (contact radius 2r: the surfaces touch at g = 0) the energy is
 * the C² penalty
 *   φ(g) = 0                          g ≥ 0
 *        = −k g³/(6δ)                 −δ < g < 0
 *        = k (g²/2 + δg/2 + δ²/6)    g ≤ −δ,
 * quadratic (stiffness k, N/m) beyond the smoothing width δ. The force follows from the
 * envelope theorem; the tangent (rod_model.cc) adds the sensitivity of interior closest
 * points, φ_xx − φ_xu φ_uu⁻¹ φ_ux with u = (s, t), so it is the exact Hessian.
 * Broad phase: collision::SphereTree, refit bottom-up every evaluation.
 */

#include <suturesim/collision/sphere_tree.h>
#include <suturesim/rod/rotation.h>

#include <cstdint>
#include <vector>

namespace suturesim::rod
{
  struct ContactParameters
  {
    bool   enabled   = false;
    double stiffness = 0;    ///< k, N/m
    double smoothing = 0;    ///< δ, m
    double radius    = 0;    ///< r of the rod, m (contact at centreline distance 2r)
    double friction  = 0;    ///< μ of the rod on itself (contact_friction.h), 1; 0 = none
    double stick_stiffness = 1e3; ///< k_t of the elastic stick, N/m
  };

  /// One active contact between segments a and b.
  struct ContactPair
  {
    std::uint32_t a, b;        ///< segments (a < b)
    double        s, t;        ///< closest-point parameters on a and b, in [0, 1]
    double        gap;         ///< g, m
    Vec3          normal;      ///< from b's point to a's point
    double        force;       ///< −φ'(g) ≥ 0, N
    double        stiffness;   ///< φ''(g), N/m
    double        distance;    ///< |p − q|, m
  };

  class SelfContact
  {
  public:
    void
    setup(const ContactParameters &parameters, const std::vector<Vec3> &points,
          const std::vector<double> &rest_lengths);

    /// Broad phase (refit + self overlap) and narrow phase: the active pairs in the
    /// configuration @p points.
    const std::vector<ContactPair> &
    update(const std::vector<Vec3> &points);

    /// The pairs found by the last update().
    const std::vector<ContactPair> &
    pairs() const
    {
      return active;
    }

    /// Penalty energy of the pairs found by the last update().
    double
    energy() const;

    /// Closest points of segments [p0, p1] and [q0, q1]: parameters (s, t) in [0, 1].
    static std::pair<double, double>
    closest_parameters(const Vec3 &p0, const Vec3 &p1, const Vec3 &q0, const Vec3 &q1);

    /// φ(g), −φ'(g), φ''(g).
    std::array<double, 3>
    penalty(double gap) const;

    const ContactParameters &
    parameters() const
    {
      return prm;
    }

    const collision::SphereTree &
    tree() const
    {
      return bvh;
    }

  private:
    ContactParameters                                     prm;
    collision::SphereTree                                 bvh;
    std::vector<double>                                   arc;  // rest arc length at nodes
    std::vector<std::pair<std::uint32_t, std::uint32_t>> candidates;
    std::vector<ContactPair>                              active;
  };
} // namespace suturesim::rod
