#include <suturesim/realtime/pierce_model.h>

namespace suturesim::realtime
{
  std::string
  PierceModel::automatic(const SutureModel *suture, const bool position_based)
  {
    return suture != nullptr && suture->takes_soft_constraints() && !position_based ? "soft-constraint"
                                                                                    : "node-path";
  }

  coupling::FrictionResult
  PierceModel::tangential(const coupling::FrictionParameters &friction, const double zeta, const double anchor,
                          const double normal) const
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
} // namespace suturesim::realtime
