/**
 * Seed 001 §4's hole: the tissue point is joined to the nearest node of the thread (the
 * suture's nodes, continued along the needle at the same spacing from the swage) and
 * held there by the full tie whatever the force; after an accepted step it moves to
 * the next node when its pull k_t (ζ − ζ_a) exceeds its friction μN, one node per step,
 * points on one node keeping their order and slipping as a group (multiple slipping):
 * the rule of coupling/node_slip.h.
 */
#include <suturesim/coupling/node_slip.h>
#include <suturesim/realtime/pierce_model.h>

#include <algorithm>
#include <cmath>

namespace suturesim::realtime
{
  namespace
  {
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
      tangential(const coupling::FrictionParameters &friction, const double zeta, const double anchor,
                 double) const override
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
            joints[k].node = std::lround((points[k].anchor - n.swage) / n.link);
            // the tissue pulls the joint towards where the point lies: k_t (ζ − ζ_a)
            joints[k].pull  = friction.stiffness * (points[k].zeta - points[k].anchor);
            joints[k].limit = coupling::friction_limit(friction, points[k].normal);
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

    const bool registered = PierceModel::Registry::instance().add(
      {"node-slip",
       "seed 001 section 4: the tissue point joined to the nearest thread node (the suture's "
       "nodes, continued along the needle at the same spacing), moved to the next node when "
       "its pull exceeds mu N, one node per step; points on one node keep their order and "
       "slip as a group (multiple slipping).",
       nullptr, [](const ParameterValues &) { return std::unique_ptr<PierceModel>(new NodeSlip); }});
  } // namespace
} // namespace suturesim::realtime
