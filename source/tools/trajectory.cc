#include <suturesim/tools/trajectory.h>

#include <algorithm>

namespace suturesim::tools
{
  Pose
  interpolate(const Pose &a, const Pose &b, const double tau)
  {
    return {(1 - tau) * a.position + tau * b.position, a.orientation.slerp(tau, b.orientation)};
  }

  void
  Trajectory::add(const double t, const Pose &pose)
  {
    keys[t] = {pose.position, pose.orientation.normalized()};
  }

  Pose
  Trajectory::pose(const double t) const
  {
    if (keys.empty())
      return Pose();
    const auto next = keys.upper_bound(t);
    if (next == keys.begin())
      return next->second;
    if (next == keys.end())
      return std::prev(next)->second;
    const auto prev = std::prev(next);
    return interpolate(prev->second, next->second, (t - prev->first) / (next->first - prev->first));
  }

  std::pair<Vector3d, Vector3d>
  Trajectory::velocity(const double t) const
  {
    const auto next = keys.upper_bound(t);
    if (keys.empty() || next == keys.begin() || next == keys.end())
      return {Vector3d::Zero(), Vector3d::Zero()};
    const auto   prev = std::prev(next);
    const double dt   = next->first - prev->first;
    // slerp turns at constant rate about the axis of q_b q_a⁻¹ (world frame)
    const Eigen::AngleAxisd turn(next->second.orientation * prev->second.orientation.conjugate());
    double                  angle = turn.angle();
    Vector3d                axis  = turn.axis();
    if (angle > M_PI) // slerp takes the short way
      angle -= 2 * M_PI;
    return {(next->second.position - prev->second.position) / dt, axis * angle / dt};
  }

  std::vector<double>
  Trajectory::kinks() const
  {
    std::vector<double> times;
    std::pair<Vector3d, Vector3d> before{Vector3d::Zero(), Vector3d::Zero()}; // at rest before the first
    for (auto k = keys.begin(); k != keys.end(); ++k)
      {
        const auto next  = std::next(k);
        const auto after = next == keys.end() ? std::pair{Vector3d::Zero(), Vector3d::Zero()}
                                              : velocity(0.5 * (k->first + next->first));
        const auto jumps = [](const Vector3d &a, const Vector3d &b) {
          return (a - b).norm() > 1e-6 * std::max(a.norm(), b.norm());
        };
        if (jumps(before.first, after.first) || jumps(before.second, after.second))
          times.push_back(k->first);
        before = after;
      }
    return times;
  }

  double
  Trajectory::start_time() const
  {
    return keys.empty() ? 0 : keys.begin()->first;
  }

  double
  Trajectory::end_time() const
  {
    return keys.empty() ? 0 : keys.rbegin()->first;
  }
} // namespace suturesim::tools
