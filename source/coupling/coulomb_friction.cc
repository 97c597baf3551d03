#include <suturesim/coupling/coulomb_friction.h>

#include <cmath>

namespace suturesim::coupling
{
  FrictionResult
  coulomb_friction(const FrictionParameters &p, const double zeta, const double anchor,
                   const double normal)
  {
    FrictionResult r;
    const double   capacity = p.mu * std::max(normal, 0.0);
    const double   gap      = zeta - anchor;
    const double   trial    = -p.stiffness * gap;
    if (std::abs(trial) <= capacity)
      {
        r.force      = trial;
        r.derivative = -p.stiffness;
        r.anchor     = anchor;
        return r;
      }
    const double sign = gap > 0 ? 1.0 : -1.0;
    r.force           = -sign * capacity;
    r.derivative      = 0;
    r.anchor          = p.stiffness > 0 ? zeta - sign * capacity / p.stiffness : zeta;
    r.slipping        = true;
    return r;
  }

  NormalForce
  normal_force(const double grip, const double tie, const double smoothing)
  {
    if (smoothing <= 0)
      return {grip + tie, 1.0};
    const double root = std::sqrt(tie * tie + smoothing * smoothing);
    // d/df f²/√(f² + ε²) = f (f² + 2ε²)/(f² + ε²)^{3/2}
    return {grip + tie * tie / root, tie * (tie * tie + 2 * smoothing * smoothing) / (root * root * root)};
  }
} // namespace suturesim::coupling
