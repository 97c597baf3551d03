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
 * Constraints here: nodes held by a tool (hard), nodes held for one step by a
 * collision (seed 002's collision constraints, set by the self-collision and tissue
 * contact responses), and soft constraints where the suture passes through pierced
 * tissue (set by the needle coupling). A soft constraint at material coordinate s lies
 * in segment k = ⌊s/l⌋ at fraction f = s/l − k: that segment is laid through the tissue
 * point p along the local direction of the thread t (the chord of its neighbours),
 * x_k = p − f l t, x_{k+1} = p + (1 − f) l t, and both nodes are constraints of the FTL
 * update (two constraints in one segment share it). With `Hole placement = kink` the
 * thread bends at p instead: x_k = p + f l b̂, x_{k+1} = p + (1 − f) l â, b̂ and â towards
 * nodes k − 1 and k + 2, and a node between two points in neighbouring segments lies on
 * their chord, so no node jumps as a point passes one (points within a link of each
 * other along the thread, as a wound's two faces are). The sections between hard and soft
 * constraints carry the quasi-spring tension, measured from constraint to constraint
 * along the thread: T = k_q max(0, L_path − (s_b − s_a)). A soft constraint is pulled by
 * T₋ê₋ + T₊ê₊, ê± the thread's directions leaving it: towards the first node beyond its
 * segment (seed 002), or along the chord to the thread's point `Turn length` away.
 *
 * A cut link (cut(), a thread cut after a knot) parts the chain: no section's tension
 * reaches across it, no node follows a constraint across it, and a section with a cut
 * has no two-sided averaging: each side follows its own constraint, and a piece with no
 * constraint stays where it lies (gravity aside).
 */
#include <suturesim/realtime/suture_model.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

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
        , per_link(p.text("Tension law") == "per link")
        , turn_length(p.real("Turn length"))
        , kinked(p.text("Hole placement") == "kink")
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

        place_soft_constraints(s);

        if (constraints.empty())
          follow(0, count - 1, +1, p);
        else
          {
            // outward from the outermost constraints, each as far as the first cut
            const std::int64_t below = last_cut(0, std::int64_t(constraints.front()) - 1);
            const std::int64_t above = first_cut(constraints.back(), std::int64_t(count) - 2);
            follow(constraints.front(), below < 0 ? 0 : below + 1, -1, p);
            follow(constraints.back(), above < 0 ? count - 1 : above, +1, p);
            for (std::size_t k = 0; k + 1 < constraints.size(); ++k)
              {
                const std::uint32_t a = constraints[k], c = constraints[k + 1];
                if (c - a < 2)
                  continue;
                if (const std::int64_t cut = first_cut(a, std::int64_t(c) - 1); cut >= 0)
                  {
                    // parted: each side follows its own constraint up to the cut
                    follow(a, cut, +1, p);
                    follow(c, last_cut(a, std::int64_t(c) - 1) + 1, -1, p);
                    continue;
                  }
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
        anchors_of(s, s.nodes.x, soft);
        force.setZero();
        // the anchor at this node, then its neighbours on either side
        const auto at = std::find_if(anchors.begin(), anchors.end(),
                                     [&](const Anchor &a) { return a.hard && a.node == i; });
        if (at == anchors.end())
          return true;
        const std::size_t k = at - anchors.begin();
        for (const int side : {-1, +1})
          {
            const std::int64_t j = std::int64_t(k) + side, neighbour = std::int64_t(i) + side;
            if (j < 0 || j >= std::int64_t(anchors.size()) || neighbour < 0 || neighbour >= s.suture.size())
              continue;
            const double T = section_tension(s.nodes.x, s.suture.begin, anchors[std::min<std::int64_t>(k, j)],
                                             anchors[std::max<std::int64_t>(k, j)]);
            force += T * (s.nodes.x.col(s.suture.begin + neighbour) - s.nodes.x.col(node)).normalized();
          }
        return true;
      }

      void
      segment_tension(const System &s, std::vector<double> &tension) const override
      {
        tension.assign(s.suture.size() - 1, 0.0);
        anchors_of(s, s.nodes.x, soft);
        for (std::size_t a = 0; a + 1 < anchors.size(); ++a)
          {
            const double T = section_tension(s.nodes.x, s.suture.begin, anchors[a], anchors[a + 1]);
            // segments whose middle lies in the section
            for (std::uint32_t k = 0; k + 1 < s.suture.size(); ++k)
              {
                const double middle = (k + 0.5) * link;
                if (middle >= anchors[a].s && middle < anchors[a + 1].s)
                  tension[k] = T;
              }
          }
      }

      double
      holding_stiffness() const override
      {
        return k_q;
      }

      bool
      takes_soft_constraints() const override
      {
        return true;
      }

      void
      set_soft_constraints(const std::vector<SoftConstraint> &c) override
      {
        soft = c;
      }

      void
      soft_constraint_loads(const System &s, const Matrix3Xd &x, const std::vector<SoftConstraint> &c,
                            std::vector<SoftConstraintLoad> &loads) const override
      {
        loads.assign(c.size(), SoftConstraintLoad());
        anchors_of(s, x, c);
        for (std::size_t a = 0; a < anchors.size(); ++a)
          {
            if (anchors[a].hard)
              continue;
            auto &load = loads[anchors[a].soft];
            if (a > 0)
              {
                load.before    = section_tension(x, s.suture.begin, anchors[a - 1], anchors[a],
                                              &load.stiffness_before);
                load.to_before = leaving_direction(x, s.suture.begin, s.suture.size(), anchors[a], anchors[a - 1], -1);
              }
            if (a + 1 < anchors.size())
              {
                load.after    = section_tension(x, s.suture.begin, anchors[a], anchors[a + 1],
                                             &load.stiffness_after);
                load.to_after = leaving_direction(x, s.suture.begin, s.suture.size(), anchors[a], anchors[a + 1], +1);
              }
          }
      }

      void
      cut(System &, const std::uint32_t segment) override
      {
        if (segment >= cuts.size())
          throw std::invalid_argument("ftl suture: no link " + std::to_string(segment) + " to cut");
        n_cuts += !cuts[segment];
        cuts[segment] = 1;
      }

    protected:
      void
      add_interactions(System &s, const std::uint32_t first) override
      {
        const std::uint32_t count = s.suture.size();
        cuts.assign(count > 0 ? count - 1 : 0, 0);
        for (std::uint32_t i = first; i < s.suture.end; ++i)
          s.nodes.set_held(i, Nodes::geometric, true);
        p.resize(3, count);
        forward.resize(3, count);
        backward.resize(3, count);
        constraints.reserve(count);
        anchors.reserve(count + 16);
        soft.reserve(16);
        k_q = quasi_spring > 0 ? quasi_spring : axial_stiffness;
      }

    private:
      /// The first (last) cut link in [@p from, @p to], or −1.
      std::int64_t
      first_cut(const std::int64_t from, const std::int64_t to) const
      {
        if (n_cuts == 0) // the uncut thread, every step: no search
          return -1;
        for (std::int64_t k = std::max<std::int64_t>(from, 0); k <= to && k < std::int64_t(cuts.size()); ++k)
          if (cuts[k])
            return k;
        return -1;
      }
      std::int64_t
      last_cut(const std::int64_t from, const std::int64_t to) const
      {
        if (n_cuts == 0)
          return -1;
        for (std::int64_t k = std::min<std::int64_t>(to, std::int64_t(cuts.size()) - 1); k >= from && k >= 0; --k)
          if (cuts[k])
            return k;
        return -1;
      }

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

      /// A section end: a node held by a tool, or a soft constraint.
      struct Anchor
      {
        double        s = 0;    ///< material coordinate, m
        Vector3d      position; ///< m
        std::int64_t  k = 0;    ///< segment (nodes k, k + 1) it lies in
        bool          hard = false;
        std::uint32_t node = 0; ///< hard: the suture node
        std::size_t   soft = 0; ///< soft: index in the list given
      };

      /// The anchors of the suture (nodes held by tools and @p c), ascending in s, into
      /// the work list.
      void
      anchors_of(const System &s, const Matrix3Xd &x, const std::vector<SoftConstraint> &c) const
      {
        const std::uint32_t count = s.suture.size();
        anchors.clear();
        for (std::uint32_t i = 0; i < count; ++i)
          if (s.nodes.held[s.suture.begin + i] & Nodes::boundary)
            anchors.push_back({i * link, x.col(s.suture.begin + i), std::min<std::int64_t>(i, count - 2), true, i, 0});
        for (std::size_t j = 0; j < c.size(); ++j)
          anchors.push_back({c[j].s, c[j].position, segment_of(c[j].s, count), false, 0, j});
        // std::sort, not stable_sort: the latter allocates, and the haptic step must not
        std::sort(anchors.begin(), anchors.end(), [](const Anchor &a, const Anchor &b) {
          return a.s < b.s || (a.s == b.s && a.hard && !b.hard);
        });
      }

      std::int64_t
      segment_of(const double s, const std::uint32_t count) const
      {
        return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(s / link)), 0, count - 2);
      }

      /// The unit direction in which the thread leaves anchor @p a towards @p side (−1:
      /// the first node, +1: the last) as far as its neighbouring anchor @p other. With
      /// no turn length, seed 002's: towards the first node beyond the segment laid
      /// through the point (between l and 2l away), since the segment itself only
      /// repeats the direction it was laid along. With a turn length L_t, the chord to
      /// the thread's point at arc length L_t from the anchor, so the turn a hole sees is
      /// measured over one physical length whatever the links' (l < L_t). Either way the
      /// chord to the neighbour when the thread reaches it first (it shares the segment,
      /// or, bent at the holes, lies before that node), or when the node sits on the
      /// anchor (no direction).
      Vector3d
      leaving_direction(const Matrix3Xd &x, const std::uint32_t first, const std::uint32_t count, const Anchor &a,
                        const Anchor &other, const int side) const
      {
        const Vector3d to_other = other.position - a.position;
        Vector3d       d        = to_other;
        if (other.k != a.k && !(turn_length > 0))
          {
            const std::int64_t n = std::clamp<std::int64_t>(side < 0 ? a.k - 1 : a.k + 2, 0, count - 1);
            const bool nearer    = kinked && (side < 0 ? other.s > n * link : other.s < n * link);
            if (const Vector3d to_node = x.col(first + n) - a.position; !nearer && to_node.norm() > 1e-3 * link)
              d = to_node;
          }
        else if (other.k != a.k)
          {
            // the polyline from the anchor: its segment's far node, the nodes up to the
            // neighbour's segment, then the neighbour
            Vector3d     from = a.position;
            double       walked = 0;
            std::int64_t node = side < 0 ? a.k : a.k + 1;
            const std::int64_t stop = side < 0 ? other.k + 1 : other.k;
            for (;; node += side)
              {
                const bool     last = side < 0 ? node < stop : node > stop;
                const Vector3d to   = last ? other.position : Vector3d(x.col(first + node));
                const double   step = (to - from).norm();
                if (walked + step >= turn_length && step > 0)
                  {
                    d = from + (turn_length - walked) / step * (to - from) - a.position;
                    break;
                  }
                if (last)
                  break; // the neighbour is nearer than L_t: d is the chord to it
                walked += step;
                from = to;
              }
            if (!(d.norm() > 1e-3 * link))
              d = to_other; // the thread folded back onto the anchor
          }
        const double l = d.norm();
        return l > 0 ? Vector3d(d / l) : Vector3d::Zero();
      }

      /// Quasi-spring tension of the section between anchors a and b (a.s ≤ b.s): the
      /// thread's length L from a to b against the material length m between them,
      /// T = k_q (L − m) (seed 002) or T = k_q l (L − m)/max(m, l) (per link: the section's
      /// n = m/l links in series, one link at least); @p stiffness gets −∂T/∂m, the slip
      /// rule's rate.
      double
      section_tension(const Matrix3Xd &x, const std::uint32_t first, const Anchor &a, const Anchor &b,
                      double *stiffness = nullptr) const
      {
        double L = 0;
        if (a.k == b.k)
          L = (b.position - a.position).norm();
        else
          {
            L = (x.col(first + a.k + 1) - a.position).norm() + (b.position - x.col(first + b.k)).norm();
            for (std::int64_t k = a.k + 1; k < b.k; ++k)
              L += (x.col(first + k + 1) - x.col(first + k)).norm();
          }
        const double m = b.s - a.s;
        // parted by a cut: the two ends are free, and nothing pulls across
        if (first_cut(a.k, b.hard ? std::int64_t(b.node) - 1 : b.k) >= 0)
          {
            if (stiffness != nullptr)
              *stiffness = 0;
            return 0;
          }
        if (!per_link)
          {
            if (stiffness != nullptr)
              *stiffness = k_q;
            return std::max(0.0, k_q * (L - m));
          }
        // a section shorter than a link is as stiff as one link (k_q): the discretisation
        // resolves no shorter spring, and a point just past a hard constraint (the swage)
        // would otherwise see k_q l/m → ∞ and the explicit coupling blow up
        const double m_eff = std::max(m, link);
        if (stiffness != nullptr)
          *stiffness = m < link ? k_q : k_q * link * std::max(L, m) / (m * m);
        return std::max(0.0, k_q * link * (L - m) / m_eff);
      }

      /// Lays the segment of each soft constraint through its tissue point (or bends the
      /// thread there, `Hole placement = kink`) and makes its nodes constraints of the FTL
      /// update (held nodes stay where the tool has them).
      void
      place_soft_constraints(const System &s)
      {
        if (soft.empty())
          return;
        const std::uint32_t count = s.suture.size(), b = s.suture.begin;
        placed.setZero(3, count);
        placed_count.assign(count, 0);
        for (std::size_t j = 0; j < soft.size(); ++j)
          {
            const std::int64_t k = segment_of(soft[j].s, count);
            Vector3d           at[2];
            bool               places[2] = {true, true};
            hole_nodes(j, k, count, at, places);
            for (int m = 0; m < 2; ++m)
              if (places[m] && !(s.nodes.held[b + k + m] & Nodes::boundary))
                {
                  placed.col(k + m) += at[m];
                  ++placed_count[k + m];
                }
          }
        for (std::uint32_t i = 0; i < count; ++i)
          if (placed_count[i] > 0)
            {
              p.col(i) = placed.col(i) / placed_count[i];
              constraints.push_back(i);
            }
        std::sort(constraints.begin(), constraints.end());
        constraints.erase(std::unique(constraints.begin(), constraints.end()), constraints.end());
      }

      /// Where soft constraint @p j (of the ascending list) puts the two nodes of its
      /// segment @p k, @p at, and whether it places each at all, @p places. Seed 002: the
      /// segment straight through the point along t, the chord of its neighbours. Bent at
      /// the point (a kink at the hole, so no node jumps as the point passes from one
      /// segment to the next): each node towards the node beyond it; points that share a
      /// segment bend it at each (its first node hangs off the first point, its last off
      /// the last, the thread running from point to point); and the one node between
      /// points in neighbouring segments lies on their chord at its share of the material
      /// between them, as the thread would run if they shared a segment. (Two points
      /// further apart than a link still move their nodes when one of them crosses into
      /// the segment after next: by (1 − f) l times the stretch of the thread between them.)
      void
      hole_nodes(const std::size_t j, const std::int64_t k, const std::uint32_t count, Vector3d (&at)[2],
                 bool (&places)[2]) const
      {
        const auto        &c = soft[j];
        const double       f = std::clamp(c.s / link - k, 0.0, 1.0);
        const std::int64_t lo = std::max<std::int64_t>(k - 1, 0), hi = std::min<std::int64_t>(k + 2, count - 1);
        Vector3d           t  = p.col(hi) - p.col(lo);
        t                     = t.norm() > 0 ? Vector3d(t.normalized()) : Vector3d::UnitX();
        Vector3d back = -t, ahead = t;
        const std::int64_t before = j > 0 ? segment_of(soft[j - 1].s, count) : -2;
        const std::int64_t after  = j + 1 < soft.size() ? segment_of(soft[j + 1].s, count) : count;
        if (kinked)
          {
            if (lo < k && (p.col(lo) - c.position).norm() > 0)
              back = (p.col(lo) - c.position).normalized();
            if (hi > k + 1 && (p.col(hi) - c.position).norm() > 0)
              ahead = (p.col(hi) - c.position).normalized();
            places[0] = before != k;
            places[1] = after != k;
          }
        at[0] = c.position + f * link * back;
        at[1] = c.position + (1 - f) * link * ahead;
        if (kinked && before == k - 1)
          at[0] = on_chord(soft[j - 1], c, k);
        if (kinked && after == k + 1)
          at[1] = on_chord(c, soft[j + 1], k + 1);
      }

      /// Node @p node (between soft constraints @p a and @p b in material order) on the
      /// chord from a to b at its material fraction.
      Vector3d
      on_chord(const SoftConstraint &a, const SoftConstraint &b, const std::int64_t node) const
      {
        const double span = b.s - a.s;
        const double w    = span > 0 ? std::clamp((node * link - a.s) / span, 0.0, 1.0) : 0.5;
        return a.position + w * (b.position - a.position);
      }

      double                     quasi_spring, fall_speed, k_q = 0;
      bool                       per_link;
      double                     turn_length; ///< L_t, m; 0: seed 002's node beyond the segment
      bool                       kinked;      ///< the thread bent at a soft constraint
      Matrix3Xd                  p, forward, backward, placed;
      std::vector<std::uint32_t> constraints;
      std::vector<int>           placed_count;
      std::vector<SoftConstraint> soft;
      mutable std::vector<Anchor> anchors;
      std::vector<char>           cuts;       ///< per link: 1 once cut
      std::size_t                 n_cuts = 0; ///< how many
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
         d.add_selection("Tension law", "per section", "per section|per link",
                         "'per section': T = k_q (L - m) for each section between "
                         "constraints, whatever its length (seed 002 sec. 3: 'a displacement "
                         "of one end of a short suture creates the same amount of tension as "
                         "[on] a long suture', so short stitches stretch); 'per link': "
                         "T = k_q l (L - m)/max(m, l), the section's m/l links of stiffness "
                         "k_q in series (an elastic thread of EA = k_q l; a section shorter "
                         "than a link is one link). Unit: none.");
         d.add_real("Turn length", 0, 0, 1,
                    "Arc length over which the thread's direction leaving a pierce point is "
                    "measured, for the hole's normal force N = N0 + |T- e- + T+ e+| (N0 the "
                    "pierce point's grip) and its pull on the tissue; 0 = seed 002's, towards "
                    "the first node beyond the segment laid through the point (1 to 2 links "
                    "away, so the wrap depends on the link length). Set it above the link "
                    "length; a neighbouring pierce point nearer than it caps it. "
                    "Unit: m. Range: 0 to 1.");
         d.add_selection("Hole placement", "segment", "segment|kink",
                         "How the thread is laid through a pierce point (a soft constraint) in "
                         "link k at fraction f: 'segment', seed 002's, link k straight through "
                         "the point along the chord of its neighbours (the turn at the hole then "
                         "sits at the link's nodes, and they jump when the point passes into the "
                         "next link); 'kink', the thread bent at the point, node k at f l from it "
                         "towards node k - 1 and node k + 1 at (1 - f) l towards node k + 2. "
                         "Unit: none.");
         d.add_real("Gravity speed", 0.02, 0, 100,
                    "Constant speed at which free nodes fall (seed 002); 0 = no gravity. "
                    "Unit: m/s. Range: >= 0.");
       },
       [](const ParameterValues &p) { return std::unique_ptr<SutureModel>(new FtlSuture(p)); }});
  } // namespace
} // namespace suturesim::realtime
