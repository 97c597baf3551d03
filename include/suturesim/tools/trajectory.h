#pragma once
/**
 * @file
 * Rigid poses and their motion by keyframes, shared by both model paths (plain C++ and
 * Eigen: the realtime path uses them in its hot loop, the accurate path to place the
 * needle at each load step).
 *
 * A pose maps body coordinates to world coordinates, x = p + R X. Between keyframes
 * (t_k, p_k, q_k) the position is interpolated linearly and the orientation by
 * spherical linear interpolation (slerp, Shoemake 1985, "Animating rotation with
 * quaternion curves", SIGGRAPH): constant angular velocity about a fixed axis between
 * two keyframes. Before the first and after the last keyframe the pose is held.
 */

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <map>
#include <string>
#include <vector>

namespace suturesim::tools
{
  using Eigen::Quaterniond;
  using Eigen::Vector3d;

  struct Pose
  {
    Vector3d    position    = Vector3d::Zero();
    Quaterniond orientation = Quaterniond::Identity();

    /// World coordinates of body point @p X.
    Vector3d
    apply(const Vector3d &X) const
    {
      return position + orientation * X;
    }
    /// Body coordinates of world point @p x.
    Vector3d
    inverse_apply(const Vector3d &x) const
    {
      return orientation.conjugate() * (x - position);
    }
  };

  /// Linear position and slerp orientation between @p a (τ = 0) and @p b (τ = 1).
  Pose
  interpolate(const Pose &a, const Pose &b, double tau);

  class Trajectory
  {
  public:
    /// Adds (or replaces) the keyframe at time @p t (s).
    void
    add(double t, const Pose &pose);

    bool
    empty() const
    {
      return keys.empty();
    }

    /// The pose at time @p t; the identity pose when there are no keyframes.
    Pose
    pose(double t) const;

    /// Linear velocity (m/s) and angular velocity (rad/s, world frame) at @p t, those of
    /// the segment containing t (right-sided at keyframes); zero outside the keyframes.
    std::pair<Vector3d, Vector3d>
    velocity(double t) const;

    /// The keyframe times at which the velocity (linear or angular) jumps by more than
    /// 1e-6 of the larger one: the motion's kinks, where adaptive steps must end. A
    /// keyframe between two segments of one steady turn (slerp keyframes) is not one.
    std::vector<double>
    kinks() const;

    double
    start_time() const;
    double
    end_time() const;

    const std::map<double, Pose> &
    keyframes() const
    {
      return keys;
    }

  private:
    std::map<double, Pose> keys;
  };
} // namespace suturesim::tools
