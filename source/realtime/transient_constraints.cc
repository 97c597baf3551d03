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
 */
#include <suturesim/realtime/self_collision.h>

namespace suturesim::realtime
{
  namespace
  {
    class TransientConstraints : public SelfCollision
    {
    public:
      TransientConstraints(const ParameterValues &, const SelfCollisionSetup &s)
        : SelfCollision(s, 2 * s.radius)
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
        if (pairs.empty())
          return;
        const std::uint32_t b0 = setup.suture.begin;
        shift.setZero();
        std::fill(count.begin(), count.end(), 0);
        const auto push = [&](const std::uint32_t segment, const double s, const Vector3d &d) {
          const double norm = (1 - s) * (1 - s) + s * s;
          for (const auto &[node, w] : {std::pair{segment, (1 - s) / norm}, std::pair{segment + 1, s / norm}})
            if (!(n.held[b0 + node] & Nodes::boundary))
              {
                shift.col(node) += w * d;
                ++count[node];
              }
        };
        for (const auto &c : pairs)
          {
            // each side moves half the overlap, apart along the line of closest points
            const Vector3d half = 0.5 * (2 * setup.radius - c.distance) * c.normal;
            push(c.a, c.s, half);
            push(c.b, c.t, -half);
          }
        for (std::uint32_t k = 0; k < count.size(); ++k)
          if (count[k] > 0)
            {
              n.x.col(b0 + k) += shift.col(k) / count[k];
              n.target.col(b0 + k) = n.x.col(b0 + k);
              n.set_held(b0 + k, Nodes::transient, true);
            }
        count_after(n.x);
      }

    private:
      Matrix3Xd             shift;
      std::vector<unsigned> count;
    };

    const bool registered = SelfCollision::Registry::instance().add(
      {"transient-constraint",
       "colliding nodes are moved apart and held for the next step (seed 002 sec. 3).",
       nullptr,
       [](const ParameterValues &p, const SelfCollisionSetup &s) {
         return std::unique_ptr<SelfCollision>(new TransientConstraints(p, s));
       }});
  } // namespace
} // namespace suturesim::realtime
