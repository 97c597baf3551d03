/**
 * Seed 002's collision constraints (§3): "When two nodes collide (checked at the end of
 * each dynamics step), their spherical collision volumes overlap. The nodes are moved
 * apart until they are not colliding, and a collision constraint is added to both nodes,
 * ensuring they will not move in the next timestep. If a node collides with multiple
 * other nodes, its final location is the average of the displacements of each
 * collision." Collisions are found between segments (closest points) rather than node
 * spheres, so that segments crossing between their nodes are caught too; a segment's
 * displacement is shared by its end nodes as w_a = (1 − s)/((1 − s)² + s²),
 * w_b = s/((1 − s)² + s²), which moves the closest point by exactly the displacement.
 * Nodes a tool holds do not move: a segment whose nodes are free realises a share m = 1
 * of its displacement, one with a held node m = Σ_free wᵢ bᵢ < 1 (bᵢ = 1 − s, s), one
 * with both held 0; each side then moves by δ/max(m_a + m_b, 1) of the overlap δ, half
 * when both are free, all of it when the other side is held (measured on a strand pressed
 * by a tool: equal halves left 29 % of 2r overlapping after the correction under XPBD),
 * never more than δ. Pairs of two held segments get no response and are not counted.
 * The averaged correction repeats on the pairs found, at their new closest points, until
 * none overlaps by more than 0.1 % of 2r ("moved apart until they are not colliding"), at
 * most 64 rounds a step.
 *
 * `Hold = false` keeps the correction and drops the hold: the moved nodes are free in the
 * next step, so a strand pressed on another can slide along it (a position projection as
 * in position-based dynamics, Müller et al. 2007, J. Vis. Commun. Image R. 18:109, §3.5).
 * Seed 002's hold stops a follow-the-leader strand that rubs along another: the rope
 * behind a moving end is held step after step and the end's link stretches instead
 * (docs/knots.md: the figure-eight).
 */
#include <suturesim/realtime/self_collision.h>

#include <algorithm>

namespace suturesim::realtime
{
  namespace
  {
    class TransientConstraints : public SelfCollision
    {
    public:
      TransientConstraints(const ParameterValues &p, const SelfCollisionSetup &s)
        : SelfCollision(s, 2 * s.radius)
        , hold(p.boolean("Hold"))
        , shift(Matrix3Xd::Zero(3, s.suture.size()))
        , count(s.suture.size(), 0)
      {}

      std::string
      name() const override
      {
        return "transient collision constraints (seed 002)";
      }

      void
      detect(const Matrix3Xd &) override
      {}

      void
      add_forces(const Matrix3Xd &, Matrix3Xd &) const override
      {}

      void
      after_step(Nodes &n) override
      {
        find_pairs(n.x, 2 * setup.radius);
        const std::uint32_t b0   = setup.suture.begin;
        const auto          free = [&](const std::uint32_t node) {
          return !(n.held[b0 + node] & Nodes::boundary);
        };
        // the share of a displacement of its closest point that a segment's free nodes
        // realise through push()
        const auto mobility = [&](const std::uint32_t segment, const double s) {
          if (free(segment) && free(segment + 1))
            return 1.0;
          const double norm = (1 - s) * (1 - s) + s * s;
          return (free(segment) ? (1 - s) * (1 - s) / norm : 0.0) + (free(segment + 1) ? s * s / norm : 0.0);
        };
        pairs.erase(std::remove_if(pairs.begin(), pairs.end(),
                                   [&](const Pair &c) { return mobility(c.a, c.s) + mobility(c.b, c.t) == 0; }),
                    pairs.end());
        if (pairs.empty())
          return;
        const double reach = 2 * setup.radius;
        const auto   push  = [&](const std::uint32_t segment, const double s, const Vector3d &d) {
          const double norm = (1 - s) * (1 - s) + s * s;
          for (const auto &[node, w] : {std::pair{segment, (1 - s) / norm}, std::pair{segment + 1, s / norm}})
            if (free(node))
              {
                shift.col(node) += w * d;
                ++count[node];
              }
        };
        // "moved apart until they are not colliding": a node in several pairs moves by
        // the average of their displacements, which leaves each of them part of its
        // overlap, so the averaged correction repeats on the pairs found (their closest
        // points again) until none overlaps by more than `tolerance` of 2r, at most
        // `rounds` times
        for (unsigned round = 0; round < rounds && (round == 0 || remeasure(n.x, (1 - tolerance) * reach)); ++round)
          {
            shift.setZero();
            std::fill(count.begin(), count.end(), 0);
            for (const auto &c : pairs)
              if (c.distance < reach)
                {
                  // apart along the line of closest points: half the overlap each when
                  // both sides are free
                  const double   m = mobility(c.a, c.s) + mobility(c.b, c.t);
                  const Vector3d d = (reach - c.distance) / std::max(m, 1.0) * c.normal;
                  push(c.a, c.s, d);
                  push(c.b, c.t, -d);
                }
            for (std::uint32_t k = 0; k < count.size(); ++k)
              if (count[k] > 0)
                {
                  // held where the last round that moved it left it
                  n.x.col(b0 + k) += shift.col(k) / count[k];
                  if (hold)
                    {
                      n.target.col(b0 + k) = n.x.col(b0 + k);
                      n.set_held(b0 + k, Nodes::transient, true);
                    }
                }
          }
        count_after(n.x);
      }

    private:
      /// Rounds of the averaged correction per step at most: a node wedged between pairs
      /// that cannot all be met would otherwise be moved forever. The averaging makes
      /// each round remove only part of a shared node's overlaps (two pairs at right
      /// angles on one node: 0.8 % of 2r still left after 8 rounds, tested).
      static constexpr unsigned rounds = 64;
      /// The overlap, as a fraction of 2r, that ends the rounds (0.2 µm on a 3-0 suture).
      static constexpr double tolerance = 1e-3;
      bool                      hold; ///< seed 002's hold for the next step
      Matrix3Xd                 shift;
      std::vector<unsigned>     count;
    };

    const bool registered = SelfCollision::Registry::instance().add(
      {"transient-constraint",
       "colliding nodes are moved apart and held for the next step (seed 002 sec. 3), or "
       "only moved apart (Hold = false).",
       [](ParameterDeclarations &d) {
         d.add_bool("Hold", true,
                    "Whether moved nodes are held for the next step, as seed 002 does (true), "
                    "or only moved apart and free to slide along each other (false). "
                    "Unit: none. Range: true or false.");
       },
       [](const ParameterValues &p, const SelfCollisionSetup &s) {
         return std::unique_ptr<SelfCollision>(new TransientConstraints(p, s));
       }});
  } // namespace
} // namespace suturesim::realtime
