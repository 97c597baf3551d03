#pragma once
/**
 * @file
 * Closest points between primitives, for the narrow phase after a sphere-tree broad
 * phase: segment–segment (suture self-contact) and point–triangle (suture on the tissue
 * surface). Plain C++/Eigen.
 */

#include <Eigen/Core>

#include <utility>

namespace suturesim::collision
{
  /// Closest points of segments [p0, p1] and [q0, q1]: parameters (s, t) in [0, 1] with
  /// p = p0 + s (p1 − p0), q = q0 + t (q1 − q0) (a clamped two-step minimisation).
  std::pair<double, double>
  segment_closest_parameters(const Eigen::Vector3d &p0, const Eigen::Vector3d &p1,
                             const Eigen::Vector3d &q0, const Eigen::Vector3d &q1);

  /// The point of triangle (a, b, c) closest to @p p, with its barycentric coordinates
  /// (weights of a, b, c) in @p bary (Ericson, Real-Time Collision Detection, 2005,
  /// §5.1.5: Voronoi regions of vertices, edges and face).
  Eigen::Vector3d
  closest_point_on_triangle(const Eigen::Vector3d &p, const Eigen::Vector3d &a,
                            const Eigen::Vector3d &b, const Eigen::Vector3d &c,
                            Eigen::Vector3d &bary);
} // namespace suturesim::collision
