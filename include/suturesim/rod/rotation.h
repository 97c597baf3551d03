#pragma once
/**
 * @file
 * Rotations for the Cosserat rod: unit quaternions (Eigen::Quaterniond), the exponential
 * and logarithm maps between rotation vectors and quaternions, and the scalar function
 * F(s) = 2 asin(√s)/√s with its derivatives, which turns the vector part p of a unit
 * quaternion with positive scalar part into its rotation vector ψ = F(|p|²) p. Writing
 * the logarithm this way makes its first and second derivatives polynomial in p, which
 * is what the element's consistent tangent needs (rod_element.h).
 */

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace suturesim::rod
{
  using Vec3 = Eigen::Vector3d;
  using Mat3 = Eigen::Matrix3d;
  using Quat = Eigen::Quaterniond;

  inline Mat3
  skew(const Vec3 &v)
  {
    Mat3 m;
    m << 0, -v[2], v[1], v[2], 0, -v[0], -v[1], v[0], 0;
    return m;
  }

  /// exp: rotation vector θ (rad) → unit quaternion (cos(|θ|/2), sin(|θ|/2) θ/|θ|).
  inline Quat
  quaternion_exp(const Vec3 &theta)
  {
    const double a = theta.norm();
    if (a < 1e-6)
      {
        // Taylor series to fourth order, then normalised
        const double a2 = a * a;
        Quat         q(1 - a2 / 8 + a2 * a2 / 384, 0, 0, 0);
        q.vec() = (0.5 - a2 / 48) * theta;
        return q.normalized();
      }
    Quat q(std::cos(0.5 * a), 0, 0, 0);
    q.vec() = (std::sin(0.5 * a) / a) * theta;
    return q;
  }

  /// log: unit quaternion → rotation vector of angle in [0, π] (q and −q are the same
  /// rotation).
  inline Vec3
  quaternion_log(const Quat &q_in)
  {
    const Quat   q = q_in.w() < 0 ? Quat(-q_in.w(), -q_in.x(), -q_in.y(), -q_in.z()) : q_in;
    const double n = q.vec().norm();
    if (n < 1e-8)
      return (2.0 / q.w()) * q.vec();
    return (2.0 * std::atan2(n, q.w()) / n) * q.vec();
  }

  /// F(s) = 2 asin(√s)/√s and its first two derivatives in s, for 0 ≤ s < 1.
  struct LogFactor
  {
    double F, dF, d2F;
  };

  LogFactor
  log_factor(double s);

  /// The rotation of @p q applied to @p v.
  inline Vec3
  rotate(const Quat &q, const Vec3 &v)
  {
    return q._transformVector(v);
  }
} // namespace suturesim::rod
