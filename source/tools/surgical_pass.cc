#include <suturesim/tools/surgical_pass.h>

#include <cmath>
#include <stdexcept>

namespace suturesim::tools
{
  SurgicalPass
  plan_pass(const CurvedNeedle &needle, const PassParameters &p)
  {
    const double R = needle.radius(), Phi = needle.arc_angle();
    if (!(p.normal.norm() > 0))
      throw std::invalid_argument("surgical pass: the surface normal is zero");
    const Vector3d n = p.normal.normalized();
    Vector3d       b = p.bite_direction - p.bite_direction.dot(n) * n;
    if (!(b.norm() > 1e-9 * p.bite_direction.norm()))
      throw std::invalid_argument("surgical pass: the bite direction lies along the normal");
    b.normalize();

    SurgicalPass pass;
    if (p.bite_depth > 0)
      {
        if (p.bite_depth > R)
          throw std::invalid_argument("surgical pass: a bite deeper than the needle radius "
                                      "(the needle would enter backwards)");
        pass.entry_angle = std::acos(1 - p.bite_depth / R);
      }
    else
      {
        if (!(p.entry_angle > 0 && p.entry_angle <= M_PI / 2))
          throw std::invalid_argument("surgical pass: entry angle must lie in (0, pi/2]");
        pass.entry_angle = p.entry_angle;
      }
    const double alpha = pass.entry_angle;
    const double h     = R * std::cos(alpha);
    pass.bite_depth    = R - h;
    pass.bite_width    = 2 * R * std::sin(alpha);
    pass.entry         = p.entry;
    pass.centre        = p.entry + R * std::sin(alpha) * b + h * n;
    pass.exit          = p.entry + pass.bite_width * b;
    if (!(p.angular_speed > 0) || !(p.pull_duration > 0) || !(p.approach >= 0) || !(p.tighten_duration > 0))
      throw std::invalid_argument("surgical pass: angular speed, pull and tighten durations must be > 0");
    if (2 * alpha + Phi >= 2 * M_PI)
      throw std::invalid_argument("surgical pass: the needle's arc closes on itself inside the tissue");

    // world angles θ in the arc's plane, from b towards n, about e = b × n
    const Vector3d e       = b.cross(n);
    const double   theta_E = std::atan2(-std::cos(alpha), -std::sin(alpha));
    const double   eps     = p.approach / R;
    // body frame: x → b, y → n, z → e; the tip sits at body angle Φ, so a turn ψ puts
    // it at world angle ψ + Φ and the swage at ψ
    Eigen::Matrix3d frame;
    frame << b, n, e;
    const Quaterniond base(frame);
    const double      psi_start = theta_E - Phi - eps;
    const double      psi_end   = theta_E + 2 * alpha + eps;
    const double      w         = p.angular_speed;
    const double      t0        = p.start_time;
    pass.t_tip_entry            = t0 + eps / w;
    pass.t_tip_exit             = pass.t_tip_entry + 2 * alpha / w;
    pass.t_swage_exit           = pass.t_tip_exit + Phi / w;
    pass.t_turn_end             = t0 + (psi_end - psi_start) / w;
    pass.t_end                  = pass.t_turn_end + p.pull_duration;

    // keyframes every π/12 at most: slerp turns the short way, and the position (the
    // centre) stays put
    const unsigned segments = static_cast<unsigned>(std::ceil((psi_end - psi_start) / (M_PI / 12)));
    for (unsigned k = 0; k <= segments; ++k)
      {
        const double psi = psi_start + (psi_end - psi_start) * k / segments;
        pass.trajectory.add(t0 + (psi - psi_start) / w,
                            {pass.centre, base * Quaterniond(Eigen::AngleAxisd(psi, Vector3d::UnitZ()))});
      }
    const Pose last = pass.trajectory.pose(pass.t_turn_end);
    pass.trajectory.add(pass.t_end, {last.position + p.pull, last.orientation});
    pass.t_tightened = pass.t_end;
    if (!p.tighten.isZero())
      {
        pass.t_tightened = pass.t_end + p.tighten_duration;
        pass.trajectory.add(pass.t_tightened, {last.position + p.pull + p.tighten, last.orientation});
      }
    return pass;
  }
} // namespace suturesim::tools
