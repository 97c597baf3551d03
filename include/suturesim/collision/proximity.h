#pragma once
/**
 * @file
 * Closest points between primitives, for the narrow phase after a sphere-tree broad
 * phase: segment–segment (suture self-contact) and point–triangle (suture on the tissue
 * surface), and where a segment crosses a triangle (a needle tip's path through the
 * surface within one step). Plain C++/Eigen.
 */

#include <Eigen/Core>

#include <cstdint>
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

  /// The nearest of several triangles to a point p, offered one at a time (after a
  /// broad phase): the closest point q, its barycentric weights, the triangle's outward
  /// normal n and the signed distance d = (p − q)·n. Equally near triangles (q on a
  /// shared edge or vertex) go to the one whose normal points most nearly away from the
  /// surface at p (the larger d), so that a point resting on a face next to an edge is
  /// not taken to be behind the side face beyond the edge.
  struct NearestTriangle
  {
    std::uint32_t   triangle        = 0;
    double          distance        = -1; ///< |p − q|; negative while nothing is offered
    double          signed_distance = 0;
    Eigen::Vector3d weights         = Eigen::Vector3d::Zero();
    Eigen::Vector3d normal          = Eigen::Vector3d::Zero();

    bool
    found() const
    {
      return distance >= 0;
    }
    /// Offers triangle @p t with corners (a, b, c) (counter-clockwise seen from outside);
    /// @p scale (m) sets the tolerance of a tie, 1e-9 (|p − q| + scale).
    void
    offer(const Eigen::Vector3d &p, std::uint32_t t, const Eigen::Vector3d &a, const Eigen::Vector3d &b,
          const Eigen::Vector3d &c, double scale);
  };

  /// Where segment [p0, p1] crosses triangle (a, b, c): true with the segment's
  /// parameter @p s in [0, 1] and the crossing's barycentric coordinates @p bary
  /// (Möller & Trumbore 1997, J. Graphics Tools 2:21–28). A segment in the triangle's
  /// plane does not cross it.
  bool
  segment_crosses_triangle(const Eigen::Vector3d &p0, const Eigen::Vector3d &p1, const Eigen::Vector3d &a,
                           const Eigen::Vector3d &b, const Eigen::Vector3d &c, double &s, Eigen::Vector3d &bary);
} // namespace suturesim::collision
