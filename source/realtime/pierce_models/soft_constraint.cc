/**
 * Seed 002 §3–4: node-path on the needle (the tie of realtime/needle_coupling.h; slip
 * by eq. 2, the return mapping with a = 1/k_t and a Coulomb threshold); once a point
 * has passed the swage into the suture's second segment (the first is held by the
 * needle, position and tangent at the swage), the model takes it over from the tie: it
 * is a soft constraint of a suture that takes them (FTL, SutureModel::
 * takes_soft_constraints()). The thread is laid through the tissue point, and the point
 * is pulled by the quasi-spring tension of the thread on either side,
 *   f = T₋ e₋ + T₊ e₊
 * ("pierced vertices [are] pulled by suture tension"; e± the unit directions of the
 * thread leaving the point). The thread slides through the hole when the tension
 * difference D = T₋ − T₊ exceeds the friction μN, the normal force being the grip plus
 * the resultant of the two tensions, N = N₀ + |T₋ e₋ + T₊ e₊| (the wrap: zero on a
 * straight pass, 2T sin(θ/2) at a bend of θ):
 *   Δs = sign(D) (|D| − μN) / (k₋ + k₊),
 * the slip that brings D back to the limit, k± = −∂T±/∂(material length) of each section
 * (SoftConstraintLoad; 2 k_q for seed 002's tension law). This is seed 002 eq. (3)'s
 * first term with a = 1/(k₋ + k₊) and a Coulomb threshold in place of its constant
 * friction; its second term (the mesh force along the thread) is left out: the
 * quasi-static tissue point is in balance with the tensions it feels. The suture is
 * moved geometrically, so only the tissue point feels the tensions.
 */
#include <suturesim/realtime/pierce_model.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace suturesim::realtime
{
  namespace
  {
    class SoftConstraintModel : public PierceModel
    {
    public:
      void
      attach(SutureModel *s, const bool position_based) override
      {
        if (s == nullptr || !s->takes_soft_constraints() || position_based)
          throw std::invalid_argument("pierce model 'soft-constraint' needs a suture that takes soft "
                                      "constraints (Suture model = ftl) and a force-based integrator");
        suture = s;
        loads.reserve(16); // a pass makes two pierce points; room for a few stitches
      }

      bool
      takes_over(const bool on_suture, const std::uint32_t segment) const override
      {
        return suture != nullptr && on_suture && segment >= 1;
      }

      void
      taken_forces(const System &sys, const Matrix3Xd &x, const std::vector<SoftConstraint> &points,
                   std::vector<Vector3d> &forces) const override
      {
        suture->soft_constraint_loads(sys, x, points, loads);
        forces.resize(points.size()); // within the caller's reserve: no allocation in the step
        for (std::size_t k = 0; k < points.size(); ++k)
          forces[k] = loads[k].before * loads[k].to_before + loads[k].after * loads[k].to_after;
      }

      void
      taken_slip(const System &sys, const Matrix3Xd &x, const std::vector<SoftConstraint> &points,
                 const coupling::FrictionParameters &friction, std::vector<TakenSlip> &slips) const override
      {
        suture->soft_constraint_loads(sys, x, points, loads);
        slips.resize(points.size());
        for (std::size_t k = 0; k < points.size(); ++k)
          {
            const auto  &l     = loads[k];
            const double D     = l.before - l.after;
            const double N     = friction.grip + (l.before * l.to_before + l.after * l.to_after).norm();
            const double limit = coupling::friction_limit(friction, N);
            // sliding ds into the section before lowers its tension by k_b ds and raises
            // the other's by k_a ds: the slip that leaves exactly μN between them
            const double rate = l.stiffness_before + l.stiffness_after;
            const bool   slip = std::abs(D) > limit && rate > 0;
            // the tissue point feels T₊ − T₋ = −D along the thread (towards its far end),
            // the convention of every pierce model's friction (and the accurate path's)
            slips[k] = {slip ? std::copysign((std::abs(D) - limit) / rate, D) : 0.0, slip, N,
                        -std::clamp(D, -limit, limit)};
          }
      }

      void
      taken_accepted(const std::vector<SoftConstraint> &points) override
      {
        if (suture != nullptr)
          suture->set_soft_constraints(points);
      }

    private:
      SutureModel                             *suture = nullptr;
      mutable std::vector<SoftConstraintLoad> loads;
    };

    const bool registered = PierceModel::Registry::instance().add(
      {"soft-constraint",
       "seed 002 section 4: node-path on the needle (slip eq. 2), past the swage a soft "
       "constraint of the FTL suture pulled by its quasi-spring tensions, slipping by eq. (3) "
       "with a Coulomb threshold (needs Suture model = ftl and a force-based integrator).",
       nullptr, [](const ParameterValues &) { return std::unique_ptr<PierceModel>(new SoftConstraintModel); }});
  } // namespace
} // namespace suturesim::realtime
