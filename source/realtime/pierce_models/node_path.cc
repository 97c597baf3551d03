/**
 * Seed 004's node-path constraint with Coulomb stick–slip, the base behaviour of
 * realtime/pierce_model.h: the tissue point is tied across the thread (the coupling's
 * transverse tie, compliance 1/k⊥) and along it to an anchor ζ_a, any thread coordinate;
 * the stick along the thread is elastic (k_t) with Coulomb's limit μN by return mapping
 * (coupling/coulomb_friction.h), so the anchor slides continuously once the stick force
 * reaches μN. Under XPBD the stick multiplier is clamped to the limit instead (static
 * friction as a position constraint, Müller et al. 2020 §3.5).
 */
#include <suturesim/realtime/pierce_model.h>

namespace suturesim::realtime
{
  namespace
  {
    class NodePath : public PierceModel
    {};

    const bool registered = PierceModel::Registry::instance().add(
      {"node-path",
       "seed 004's node-path constraint: the tissue point tied across the thread, and along "
       "it to an anchor that slides continuously once the stick force reaches mu N "
       "(regularised Coulomb by return mapping).",
       nullptr, [](const ParameterValues &) { return std::unique_ptr<PierceModel>(new NodePath); }});
  } // namespace
} // namespace suturesim::realtime
