#pragma once
/**
 * @file
 * Suture self-collision, registered by response (Realtime/Self-collision):
 *  - "repelling-force": seed 000 eq. (1), F = k_c exp(k_o (2d − o_ij)) between segments
 *    i, j at distance o_ij, d the suture's width (diameter), pushing the closest points
 *    apart; cut off where F < 10⁻³ k_c;
 *  - "transient-constraint": seed 002 §3, colliding nodes "are moved apart until they
 *    are not colliding, and a collision constraint is added to both nodes, ensuring they
 *    will not move in the next timestep"; a node in several collisions moves by the
 *    average of their displacements;
 *  - "off".
 * Both find their pairs the same way: the chain's sphere tree (seed 000 Algorithm 1)
 * refitted bottom-up, its self-overlaps, and the closest points of non-adjacent segments
 * (segments closer along the thread than the reach always touch and are skipped).
 */

#include <suturesim/collision/sphere_tree.h>
#include <suturesim/core/registry.h>
#include <suturesim/core/model_parameters.h>
#include <suturesim/realtime/system.h>

#include <vector>

namespace suturesim::realtime
{
  struct SelfCollisionSetup
  {
    NodeRange suture;
    double    radius = 0; ///< m
    double    link   = 0; ///< rest segment length, m
    const Matrix3Xd *positions = nullptr; ///< the system's positions at set-up
  };

  class SelfCollision : public ContactSet
  {
  public:
    using Registry = BasicRegistry<SelfCollision, ParameterDeclarations, const ParameterValues &,
                                   const SelfCollisionSetup &>;

    std::size_t
    active() const override
    {
      return pairs.size();
    }

    /// A pair of segments a < b (suture-local indices) closer than the reach.
    struct Pair
    {
      std::uint32_t a, b;
      double        s, t;     ///< closest-point parameters on a and b
      double        distance; ///< o_ij, m
      Vector3d      normal;   ///< from b's closest point to a's
    };
    const std::vector<Pair> &
    list() const
    {
      return pairs;
    }

  protected:
    explicit SelfCollision(const SelfCollisionSetup &setup);

    /// Finds the pairs of non-adjacent segments closer than @p reach (m) at @p x.
    void
    find_pairs(const Matrix3Xd &x, double reach);

    SelfCollisionSetup    setup;
    collision::SphereTree tree;
    collision::LeafPairs  candidates;
    std::vector<Pair>     pairs;
  };

  /// Builds the self-collision response named @p name (nullptr for "off").
  std::unique_ptr<ContactSet>
  make_self_collision(const std::string &name, const ParameterValues &values,
                      const SelfCollisionSetup &setup);
} // namespace suturesim::realtime
