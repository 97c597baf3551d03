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
 *  - "detect-only": finds the pairs closer than 2r after each step and applies nothing:
 *    the counts below for a run without a response (how deep segments pass through
 *    each other); the motion is that of "off";
 *  - "off".
 * All find their pairs the same way: the chain's sphere tree (seed 000 Algorithm 1)
 * refitted bottom-up, its self-overlaps, and the closest points of non-adjacent segments
 * (segments closer along the thread than the reach always touch and are skipped).
 * Each counts what it found over the run (SelfCollisionCounts), without allocating.
 */

#include <suturesim/collision/sphere_tree.h>
#include <suturesim/core/registry.h>
#include <suturesim/core/model_parameters.h>
#include <suturesim/realtime/system.h>

#include <cstdint>
#include <limits>
#include <vector>

namespace suturesim::realtime
{
  /// What a self-collision response found over a run, counted per (sub)step.
  struct SelfCollisionCounts
  {
    /// Σ over the (sub)steps of the pairs the response acted on ("events": pair-steps).
    std::uint64_t pair_steps = 0;
    std::size_t   max_pairs  = 0; ///< most pairs in one (sub)step
    /// Least distance o_ij of a found pair in the state a (sub)step left, after the
    /// response's corrections (m); ∞ while no pair came closer than the reach.
    double min_distance = std::numeric_limits<double>::infinity();
    /// Least o_ij as detected, before a position correction (m): what the dynamics
    /// drove the segments to; equal to min_distance for responses that act by force.
    double min_distance_detected = std::numeric_limits<double>::infinity();
    double reach                 = 0; ///< pairs closer than this are found, m
  };

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
      double        detected; ///< the distance when found, m (remeasure() changes distance)
    };
    const std::vector<Pair> &
    list() const
    {
      return pairs;
    }

    const SelfCollisionCounts &
    counts() const
    {
      return counted;
    }

    /// Distance between suture segments @p a and @p b (suture-local) at @p x, m.
    double
    distance(const Matrix3Xd &x, std::uint32_t a, std::uint32_t b) const;
    /// The vector from b's closest point to a's at @p x (m), their parameters into @p s
    /// and @p t: the one measurement of find_pairs(), remeasure() and distance().
    Vector3d
    separation(const Matrix3Xd &x, std::uint32_t a, std::uint32_t b, double &s, double &t) const;

  protected:
    /// @p reach: the distance within which find_pairs() is called (for the counts), m.
    SelfCollision(const SelfCollisionSetup &setup, double reach);

    /// Finds the pairs of non-adjacent segments closer than @p reach (m) at @p x.
    void
    find_pairs(const Matrix3Xd &x, double reach);

    /// The closest points, distance and normal of every listed pair again at @p x (after
    /// a correction moved them); true if one is still closer than @p reach.
    bool
    remeasure(const Matrix3Xd &x, double reach);

    /// Counts the pairs of the last find_pairs(), which the response acts on by force:
    /// their distances are those of the state the last step left.
    void
    count_pairs();
    /// Counts them after a position correction, which left the state @p x.
    void
    count_after(const Matrix3Xd &x);

    SelfCollisionSetup    setup;
    collision::SphereTree tree;
    collision::LeafPairs  candidates;
    std::vector<Pair>     pairs;
    SelfCollisionCounts   counted;
  };

  /// Builds the self-collision response named @p name (nullptr for "off").
  std::unique_ptr<SelfCollision>
  make_self_collision(const std::string &name, const ParameterValues &values,
                      const SelfCollisionSetup &setup);
} // namespace suturesim::realtime
