#include <suturesim/tools/curved_needle.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace suturesim::tools
{
  CurvedNeedle::CurvedNeedle(const double radius, const double arc_angle, const double wire_diameter)
    : R(radius)
    , phi_max(arc_angle)
    , d(wire_diameter)
  {
    if (!(R > 0) || !(phi_max > 0 && phi_max < 2 * M_PI) || !(d > 0 && d < R))
      throw std::invalid_argument("curved needle: need R > 0, 0 < arc angle < 2 pi, 0 < d < R");
  }

  CurvedNeedle
  CurvedNeedle::double_pointed(const double length, const double wire_diameter)
  {
    if (!(length > 0) || !(wire_diameter > 0 && wire_diameter < length / 2))
      throw std::invalid_argument("double-pointed needle: need a length > 0 and 0 < d < length / 2");
    CurvedNeedle needle;
    needle.d           = wire_diameter;
    needle.half_length = length / 2;
    return needle;
  }

  double
  CurvedNeedle::arc_angle_of(const std::string &shape)
  {
    if (shape == "3/8")
      return 0.75 * M_PI;
    if (shape == "1/2")
      return M_PI;
    throw std::invalid_argument("needle shape '" + shape + "': use 3/8 or 1/2");
  }

  Vector3d
  CurvedNeedle::body_point(const double zeta) const
  {
    if (straight())
      return {0, half_length - std::clamp(zeta, 0.0, half_length), 0};
    const double phi = phi_max - std::clamp(zeta, 0.0, length()) / R;
    return {R * std::cos(phi), R * std::sin(phi), 0};
  }

  Vector3d
  CurvedNeedle::body_tangent(const double zeta) const
  {
    if (straight())
      return Vector3d::UnitY();
    const double phi = phi_max - std::clamp(zeta, 0.0, length()) / R;
    return {-std::sin(phi), std::cos(phi), 0};
  }

  double
  CurvedNeedle::closest(const Pose &pose, const Vector3d &x) const
  {
    const Vector3d X = pose.inverse_apply(x);
    if (straight())
      return half_length - std::clamp(X[1], 0.0, half_length);
    if (X.head<2>().squaredNorm() == 0)
      return 0; // the centre: every point of the arc is as near; take the tip
    double phi = std::atan2(X[1], X[0]);
    // the arc occupies [0, Φ]; angles outside go to the nearer end, measured around
    // the circle both ways
    if (phi < 0)
      phi += 2 * M_PI;
    if (phi > phi_max)
      phi = (phi - phi_max < 2 * M_PI - phi) ? phi_max : 0;
    return R * (phi_max - phi);
  }
} // namespace suturesim::tools
