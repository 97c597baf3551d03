#include <suturesim/core/coulomb_law.h>
#include <suturesim/coupling/coulomb_friction.h>

#include <cmath>

namespace suturesim::coupling
{
  FrictionResult
  coulomb_friction(const FrictionParameters &p, const double zeta, const double anchor,
                   const double normal, const FrictionBranch *branch)
  {
    FrictionResult r;
    const double   capacity = friction_limit(p, normal);
    const double   gap      = zeta - anchor;
    const double   trial    = -p.stiffness * gap;
    r.capacity              = capacity;
    if (branch ? !branch->slipping : coulomb_sticks(p.stiffness, capacity, gap))
      {
        r.force      = trial;
        r.derivative = -p.stiffness;
        r.anchor     = anchor;
        return r;
      }
    const double sign = branch ? branch->sign : gap > 0 ? 1.0 : -1.0;
    r.force           = -sign * capacity;
    r.derivative      = 0;
    r.anchor          = zeta - sign * coulomb_slip_gap(p.stiffness, capacity);
    r.slipping        = true;
    return r;
  }

  void
  FrictionParameters::declare(ParameterDeclarations &d)
  {
    const FrictionParameters defaults;
    d.add_real("Friction coefficient", defaults.mu, 0, 10,
               "Coulomb mu between tissue and thread (seed 000 eq. 2). Unit: 1. Range: [0, 10].");
    d.add_real("Stick stiffness", defaults.stiffness, 0, 1e12,
               "k_t of the elastic stick before slip (regularised Coulomb). Unit: N/m. Range: > 0.");
    d.add_real("Grip", defaults.grip, 0, 1e6,
               "Normal force N0 of the hole on a straight thread; N = N0 + |f_perp|. Unit: N. Range: >= 0.");
  }

  FrictionParameters
  FrictionParameters::parse(const ParameterValues &v)
  {
    FrictionParameters p;
    p.mu        = v.real("Friction coefficient");
    p.stiffness = v.real("Stick stiffness");
    p.grip      = v.real("Grip");
    v.require(p.stiffness > 0, "Stick stiffness", "must be > 0 N/m");
    return p;
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
