#pragma once
/**
 * @file
 * Small vectors and quaternions as JSON arrays, for the states a checkpoint holds
 * (io/checkpoint.h). Header-only and free of deal.II, so that the realtime library's
 * classes (plain C++/Eigen) can describe their state too; deal.II's Point and Tensor
 * go through the same templates.
 */

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <nlohmann/json.hpp>

namespace suturesim::io
{
  /// A vector of three components (Eigen's, deal.II's Point or Tensor) as a JSON array.
  template <class Vector>
  nlohmann::json
  triple(const Vector &v)
  {
    return {v[0], v[1], v[2]};
  }

  /// triple() back.
  template <class Vector>
  Vector
  triple_as(const nlohmann::json &j)
  {
    Vector v;
    for (unsigned d = 0; d < 3; ++d)
      v[d] = j.at(d).get<double>();
    return v;
  }

  /// A quaternion as (w, x, y, z).
  inline nlohmann::json
  quaternion_array(const Eigen::Quaterniond &q)
  {
    return {q.w(), q.x(), q.y(), q.z()};
  }

  inline Eigen::Quaterniond
  quaternion(const nlohmann::json &j)
  {
    return {j.at(0).get<double>(), j.at(1).get<double>(), j.at(2).get<double>(), j.at(3).get<double>()};
  }
} // namespace suturesim::io
