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

  /// The winding number of the closed, outward-oriented triangle surface @p surface
  /// (vertex columns of @p x) about @p p: Σ Ω/(4π) over its triangles, Ω the signed
  /// solid angle (Van Oosterom & Strackee 1983, IEEE Trans. Biomed. Eng. 30:125). 1
  /// inside, 0 outside (on the surface itself it is not defined); for a surface that is not quite closed, still
  /// near 1 or 0 away from the holes (Jacobson et al. 2013, "Robust inside-outside
  /// segmentation using generalized winding numbers").
  double
  winding_number(const Eigen::Vector3d &p, const Eigen::Matrix3Xd &x,
                 const std::vector<std::array<std::uint32_t, 3>> &surface);

  /// As volume_penetration() for a body known only by its closed boundary @p surface
  /// (the accurate path's tissue: its FE mesh's boundary faces, bilinear patches split
  /// into triangles): inside where the winding number exceeds ½.
  /// The deep points split into those a stitch carries inside on purpose (@p in_tract,
  /// per point column: between an exit pierce point and the next entry along the thread)
  /// and the others, which have passed through the surface.
  struct TractSplit
  {
    std::size_t outside_tracts = 0, in_tracts = 0;
    double      depth          = 0; ///< deepest of the others, m
  };
  TractSplit
  split_by_tracts(const VolumePenetration &penetration, const std::vector<char> &in_tract);

  VolumePenetration
  surface_penetration(const Eigen::Matrix3Xd &x, const std::vector<std::array<std::uint32_t, 3>> &surface,
                      const Eigen::Matrix3Xd &points, double tolerance);
} // namespace suturesim::collision
