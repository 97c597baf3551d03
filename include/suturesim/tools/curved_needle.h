#pragma once
/**
 * @file
 * A rigid curved suture needle: a circular arc of radius R over an angle Φ (3/8 circle:
 * Φ = 3π/4; 1/2 circle: Φ = π), wire diameter d, swage (where the suture is attached)
 * at one end and the tip at the other.
 *
 * Body frame: the arc centre at the origin, the arc in the x–y plane, the swage at
 * angle 0, X_s = (R, 0, 0), the tip at angle Φ, X_t = R (cos Φ, sin Φ, 0); the
 * needle is traversed counter-clockwise about +z from swage to tip. Positions along it
 * are measured by the thread coordinate ζ from the tip, ζ = R (Φ − φ) at angle φ:
 * ζ = 0 at the tip, ζ = L = R Φ at the swage, where the suture continues (ζ > L on the
 * suture). Tissue that the needle pierces enters at ζ = 0 and slides towards larger ζ.
 * The unit tangent t(ζ) points the way the needle advances (towards the tip),
 * t = (−sin φ, cos φ, 0).
 *
 * A straight needle pointed at both ends (double_pointed(): the Endo Stitch's, seed 001
 * §5) is the limit R → ∞ with the suture attached at its middle. Body frame: the middle
 * at the origin, the needle along y, the leading point at (0, ℓ, 0) for a needle 2ℓ
 * long. The thread runs from the leading point to the middle, ζ = ℓ − y ∈ [0, ℓ], with
 * t = (0, 1, 0): a hole slides along the leading half and, at the middle, onto the
 * suture. The trailing half is not part of the thread (it follows the suture through
 * the same hole). Which point leads is the holder's business
 * (realtime::World::reverse_needle).
 */

#include <suturesim/tools/trajectory.h>

namespace suturesim::tools
{
  class CurvedNeedle
  {
  public:
    /// @p radius R (m), @p arc_angle Φ (rad, in (0, 2π)), @p wire_diameter d (m).
    CurvedNeedle(double radius, double arc_angle, double wire_diameter);

    /// A straight needle @p length long (m, point to point), pointed at both ends, the
    /// suture attached at its middle; std::invalid_argument unless 0 < @p wire_diameter <
    /// @p length / 2.
    static CurvedNeedle
    double_pointed(double length, double wire_diameter);

    /// Whether it is double_pointed() (straight): radius() and arc_angle() are then 0.
    bool
    straight() const
    {
      return R == 0;
    }

    /// Φ of a needle shape by name: "3/8" (3π/4) or "1/2" (π); throws
    /// std::invalid_argument otherwise.
    static double
    arc_angle_of(const std::string &shape);

    double
    radius() const
    {
      return R;
    }
    double
    arc_angle() const
    {
      return phi_max;
    }
    double
    wire_diameter() const
    {
      return d;
    }
    /// Length L of the thread's needle part, tip to swage: R Φ, or ℓ for a straight
    /// needle. m.
    double
    length() const
    {
      return straight() ? half_length : R * phi_max;
    }

    /// Body-frame point and unit tangent (direction of advance) at thread coordinate
    /// @p zeta ∈ [0, L] (clamped).
    Vector3d
    body_point(double zeta) const;
    Vector3d
    body_tangent(double zeta) const;

    /// World point, tangent, tip and swage in pose @p pose.
    Vector3d
    point(const Pose &pose, double zeta) const
    {
      return pose.apply(body_point(zeta));
    }
    Vector3d
    tangent(const Pose &pose, double zeta) const
    {
      return pose.orientation * body_tangent(zeta);
    }
    Vector3d
    tip(const Pose &pose) const
    {
      return point(pose, 0);
    }
    Vector3d
    swage(const Pose &pose) const
    {
      return point(pose, length());
    }

    /// The thread coordinate of the point of the arc nearest to world point @p x (the
    /// arc's end when the nearest point of the full circle lies outside it).
    double
    closest(const Pose &pose, const Vector3d &x) const;

  private:
    CurvedNeedle() = default;

    double R = 0, phi_max = 0, d = 0;
    double half_length = 0; ///< ℓ of a straight needle, m
  };
} // namespace suturesim::tools
