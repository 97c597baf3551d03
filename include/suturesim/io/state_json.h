#pragma once
/**
 * @file
 * Eigen's small vectors and quaternions as JSON arrays, for the states a checkpoint holds
 * (io/checkpoint.h). Header-only, so that the realtime library's classes (plain
 * C++/Eigen) can describe their state too.
 */

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <nlohmann/json.hpp>

namespace suturesim::io
{
  inline nlohmann::json
  to_array(const Eigen::Vector3d &v)
  {
    return {v[0], v[1], v[2]};
  }

  inline Eigen::Vector3d
  vector3(const nlohmann::json &j)
  {
    return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>()};
  }

  /// (w, x, y, z)
  inline nlohmann::json
  to_array(const Eigen::Quaterniond &q)
  {
    return {q.w(), q.x(), q.y(), q.z()};
  }

  inline Eigen::Quaterniond
  quaternion(const nlohmann::json &j)
  {
    return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>(), j.at(3).get<double>()};
  }
} // namespace suturesim::io
