#include <suturesim/coupling/node_slip.h>
#include <suturesim/realtime/pierce_model.h>

#include <algorithm>
#include <cmath>

namespace suturesim::realtime
{
  coupling::FrictionResult
  PierceModel::tangential(const coupling::FrictionParameters &friction, const double zeta,
                          const double anchor, const double normal) const
  {
    return coupling::coulomb_friction(friction, zeta, anchor, normal);
  }

  void
  PierceModel::settle(std::vector<PierceSlip> &points, const coupling::FrictionParameters &friction,
                      const ThreadNodes &) const
  {
    for (auto &p : points)
      {
        const auto r = coupling::coulomb_friction(friction, p.zeta, p.anchor, p.normal);
        p.anchor     = r.anchor;
        p.slipping   = r.slipping;
        p.friction   = r.force;
      }
  }

  namespace
  {
    /// Seed 004's node-path constraint with Coulomb stick–slip: the base behaviour.
    class NodePath : public PierceModel
    {};

    /// Seed 002: node-path on the needle, soft constraints of the FTL suture past the swage.
    class SoftConstraint : public PierceModel
    {
    public:
      bool
      soft_on_suture() const override
      {
        return true;
      }
    };

    /// Seed 001 §4: joined to a node, slipping node by node.
    class NodeSlip : public PierceModel
    {
    public:
      NodeSlip()
      {
        joints.reserve(16); // a pass makes two pierce points; room for a few stitches
      }

      double
      order_gap(double) const override
      {
        return 0; // several points may share a node, in their list's order
      }
      double
      first_anchor(const double zeta, const ThreadNodes &n) const override
      {
        // seed 001 joins the hole to the nearest node of the thread
        const long i = std::lround((zeta - n.swage) / n.link);
        return n.swage + std::clamp(i, n.first, n.last) * n.link;
      }
      bool
      capped_stick() const override
      {
        return false;
      }
      coupling::FrictionResult
      tangential(const coupling::FrictionParameters &friction, const double zeta,
                 const double anchor, double) const override
      {
        coupling::FrictionResult r;
        r.force      = -friction.stiffness * (zeta - anchor);
        r.derivative = -friction.stiffness;
        r.anchor     = anchor;
        return r;
      }
      void
      settle(std::vector<PierceSlip> &points, const coupling::FrictionParameters &friction,
             const ThreadNodes &n) const override
      {
        joints.resize(points.size()); // within the reserved capacity: no allocation in the step
        for (std::size_t k = 0; k < points.size(); ++k)
          {
            joints[k].node  = std::lround((points[k].anchor - n.swage) / n.link);
            // the tissue pulls the joint towards where the point lies: k_t (ζ − ζ_a)
            joints[k].pull  = friction.stiffness * (points[k].zeta - points[k].anchor);
            joints[k].limit = friction.mu * points[k].normal;
          }
        coupling::node_slip(joints, n.first, n.last);
        for (std::size_t k = 0; k < points.size(); ++k)
          {
            points[k].friction = -joints[k].pull;
            points[k].slipping = joints[k].moved != 0;
            points[k].anchor   = n.swage + joints[k].node * n.link;
          }
      }

    private:
      mutable std::vector<coupling::NodeSlipPoint> joints;
    };

    const bool registered_node_path = PierceModel::Registry::instance().add(
      {"node-path",
       "seed 004's node-path constraint: the tissue point tied across the thread, and along "
       "it to an anchor that slides continuously once the stick force reaches mu N "
       "(regularised Coulomb by return mapping).",
       nullptr, [](const ParameterValues &) { return std::unique_ptr<PierceModel>(new NodePath); }});
    const bool registered_soft = PierceModel::Registry::instance().add(
      {"soft-constraint",
       "seed 002 section 4: node-path on the needle (slip eq. 2), past the swage a soft "
       "constraint of the FTL suture pulled by its quasi-spring tensions, slipping by eq. (3) "
       "with a Coulomb threshold (needs Suture model = ftl and a force-based integrator).",
       nullptr,
       [](const ParameterValues &) { return std::unique_ptr<PierceModel>(new SoftConstraint); }});
    const bool registered_node_slip = PierceModel::Registry::instance().add(
      {"node-slip",
       "seed 001 section 4: the tissue point joined to the nearest thread node (the suture's "
       "nodes, continued along the needle at the same spacing), moved to the next node when "
       "its pull exceeds mu N, one node per step; points on one node keep their order and "
       "slip as a group (multiple slipping).",
       nullptr, [](const ParameterValues &) { return std::unique_ptr<PierceModel>(new NodeSlip); }});
  } // namespace
} // namespace suturesim::realtime
