#pragma once
/**
 * @file
 * Which points lie inside a tetrahedral volume, and how deep: the check that no suture
 * node has passed through the tissue's surface outside its pierce points (issue 6).
 * A point is inside when it lies in one of the tetrahedra (barycentric coordinates all
 * ≥ 0, each tetrahedron's bounding box first); its depth is its distance to the
 * nearest boundary triangle (collision/proximity.h). Brute force over the cells: meant
 * for outputs and checks, not for the haptic loop. Plain C++/Eigen.
 */

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace suturesim::collision
{
  struct VolumePenetration
  {
    std::vector<std::size_t> points; ///< columns of the points deeper than the tolerance
    std::vector<double>      depths; ///< their depths, m
  };

  /// Whether @p p lies in tetrahedron (a, b, c, d), faces included.
  bool
  inside_tetrahedron(const Eigen::Vector3d &p, const Eigen::Vector3d &a, const Eigen::Vector3d &b,
                     const Eigen::Vector3d &c, const Eigen::Vector3d &d);

  /// The columns of @p points that lie inside the volume of @p cells (vertex columns of
  /// @p x) deeper than @p tolerance (m) below its boundary @p surface, with their depths.
  VolumePenetration
  volume_penetration(const Eigen::Matrix3Xd &x, const std::vector<std::array<std::uint32_t, 4>> &cells,
                     const std::vector<std::array<std::uint32_t, 3>> &surface, const Eigen::Matrix3Xd &points,
                     double tolerance);
} // namespace suturesim::collision
