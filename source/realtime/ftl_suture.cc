/**
 * Follow-the-leader suture (seed 002 §3, after Brown et al.; seed 000 §III): links of
 * fixed length l; constrained nodes "dictate the shape" and are not moved. "When a node
 * with a constraint is moved, the adjacent nodes move towards the constrained node's new
 * position until they are a preset distance from [it]", and so on outward. "When a
 * section of the suture has a constraint on each end, each node in that section follows
 * each constraint in turn", and the two results are "averaged for each node, weighted
 * according to distance from each constraint" (two-sided constraint averaging).
 *
 * Quasi-spring tension (seed 002 §3): between consecutive hard or soft constraints the
 * tension is T = k_q (Σ|links| − n l), n the number of links, "in the direction of the
 * next node"; k_q (N/m) turns the seed's length into a force. A slack section carries
 * no tension (T ≥ 0: a thread does not push). Gravity (seed 002): "moving each
 * unconstrained node not adjacent to a constraint downwards prior to each dynamics
 * step" — a constant fall speed.
 *
 * Constraints here: nodes held by a tool (hard) and nodes held for one step by a
 * collision (seed 002's collision constraints, set by the self-collision and tissue
 * contact responses). Soft constraints at pierce points come with the coupling.
 */
#include <suturesim/realtime/suture_model.h>

#include <algorithm>

namespace suturesim::realtime
{
  namespace
  {
    class FtlSuture : public SutureModel
    {
    public:
      explicit FtlSuture(const ParameterValues &p)
        : quasi_spring(p.real("Quasi-spring constant"))
        , fall_speed(p.real("Gravity speed"))
      {}

      bool
      geometric() const override
      {
        return true;
      }

      void
      before_step(System &s, const double dt) override
      {
        Nodes              &n = s.nodes;
        const std::uint32_t b = s.suture.begin, count = s.suture.size();
        constraints.clear();
        for (std::uint32_t i = 0; i < count; ++i)
          {
            const bool c = n.held[b + i] & (Nodes::boundary | Nodes::transient);
            p.col(i)     = c ? n.target.col(b + i) : n.x.col(b + i);
            if (c)
              constraints.push_back(i);
          }

        // gravity: unconstrained nodes not next to a constraint fall at a constant speed
        if (!s.gravity.isZero() && fall_speed > 0)
          {
            const Vector3d fall = fall_speed * dt * s.gravity.normalized();
            for (std::uint32_t i = 0; i < count; ++i)
              if (!constrained(i) && !(i > 0 && constrained(i - 1)) &&
                  !(i + 1 < count && constrained(i + 1)))
                p.col(i) += fall;
          }

        if (constraints.empty())
          follow(0, count - 1, +1, p);
        else
          {
            follow(constraints.front(), 0, -1, p);
            follow(constraints.back(), count - 1, +1, p);
            for (std::size_t k = 0; k + 1 < constraints.size(); ++k)
              {
                const std::uint32_t a = constraints[k], c = constraints[k + 1];
                if (c - a < 2)
                  continue;
                forward = p;
                backward = p;
                follow(a, c - 1, +1, forward);
                follow(c, a + 1, -1, backward);
                for (std::uint32_t i = a + 1; i < c; ++i)
                  {
                    const double w = double(c - i) / (c - a);
                    p.col(i)       = w * forward.col(i) + (1 - w) * backward.col(i);
                  }
              }
          }
        for (std::uint32_t i = 0; i < count; ++i)
          n.target.col(b + i) = p.col(i);
      }

      bool
      holding_force(const System &s, const std::uint32_t node, Vector3d &force) const override
      {
        if (!s.suture.contains(node))
          return false;
        const std::uint32_t i = node - s.suture.begin;
        force.setZero();
        for (const int side : {-1, +1})
          {
            const auto other = hard_neighbour(s, i, side);
            if (other < 0)
              continue;
            const double T = section_tension(s, std::min<std::int64_t>(i, other), std::max<std::int64_t>(i, other));
            force += T * (s.nodes.x.col(s.suture.begin + i + side) - s.nodes.x.col(node)).normalized();
          }
        return true;
      }

      void
      segment_tension(const System &s, std::vector<double> &tension) const override
      {
        tension.assign(s.suture.size() - 1, 0.0);
        std::int64_t last = -1;
        for (std::uint32_t i = 0; i < s.suture.size(); ++i)
          if (s.nodes.held[s.suture.begin + i] & Nodes::boundary)
            {
              if (last >= 0)
                {
                  const double T = section_tension(s, last, i);
                  for (std::uint32_t k = last; k < i; ++k)
                    tension[k] = T;
                }
              last = i;
            }
      }

    protected:
      void
      add_interactions(System &s, const std::uint32_t first) override
      {
        const std::uint32_t count = s.suture.size();
        for (std::uint32_t i = first; i < s.suture.end; ++i)
          s.nodes.set_held(i, Nodes::geometric, true);
        p.resize(3, count);
        forward.resize(3, count);
        backward.resize(3, count);
        constraints.reserve(count);
        k_q = quasi_spring > 0 ? quasi_spring : axial_stiffness;
      }

    private:
      bool
      constrained(const std::uint32_t i) const
      {
        return std::binary_search(constraints.begin(), constraints.end(), i);
      }

      /// FTL from node @p from (kept) to node @p to in direction @p dir: each node moves
      /// toward its predecessor until it is l away.
      void
      follow(const std::int64_t from, const std::int64_t to, const int dir, Matrix3Xd &q) const
      {
        for (std::int64_t i = from + dir; dir > 0 ? i <= to : i >= to; i += dir)
          {
            Vector3d d = q.col(i) - q.col(i - dir);
            double   L = d.norm();
            if (!(L > 0))
              {
                // coincident: keep the direction of the previous link, or any
                d = i - 2 * dir >= 0 && i - 2 * dir < q.cols() ? Vector3d(q.col(i - dir) - q.col(i - 2 * dir))
                                                                : Vector3d::UnitX();
                L = d.norm() > 0 ? d.norm() : 1;
                if (!(d.norm() > 0))
                  d = Vector3d::UnitX();
              }
            q.col(i) = q.col(i - dir) + (link / L) * d;
          }
      }

      /// The nearest node on side @p side of @p i that a tool holds, −1 if none.
      std::int64_t
      hard_neighbour(const System &s, const std::uint32_t i, const int side) const
      {
        for (std::int64_t k = std::int64_t(i) + side; k >= 0 && k < s.suture.size(); k += side)
          if (s.nodes.held[s.suture.begin + k] & Nodes::boundary)
            return k;
        return -1;
      }

      /// Quasi-spring tension of the section between suture nodes a < c.
      double
      section_tension(const System &s, const std::int64_t a, const std::int64_t c) const
      {
        double L = 0;
        for (std::int64_t k = a; k < c; ++k)
          L += (s.nodes.x.col(s.suture.begin + k + 1) - s.nodes.x.col(s.suture.begin + k)).norm();
        return std::max(0.0, k_q * (L - (c - a) * link));
      }

      double                     quasi_spring, fall_speed, k_q = 0;
      Matrix3Xd                  p, forward, backward;
      std::vector<std::uint32_t> constraints;
    };

    const bool registered = SutureModel::Registry::instance().add(
      {"ftl",
       "follow-the-leader links of fixed length with two-sided constraint averaging and "
       "quasi-spring tension T = k_q (sum |links| - n l) (seed 002 sec. 3, seed 000 sec. "
       "III); positioned geometrically, not integrated.",
       [](ParameterDeclarations &d) {
         d.add_real("Quasi-spring constant", 0, 0, 1e12,
                    "k_q turning the stretch between constraints into tension; 0 = EA/l. "
                    "Unit: N/m. Range: >= 0.");
         d.add_real("Gravity speed", 0.02, 0, 100,
                    "Constant speed at which free nodes fall (seed 002); 0 = no gravity. "
                    "Unit: m/s. Range: >= 0.");
       },
       [](const ParameterValues &p) { return std::unique_ptr<SutureModel>(new FtlSuture(p)); }});
  } // namespace
} // namespace suturesim::realtime
