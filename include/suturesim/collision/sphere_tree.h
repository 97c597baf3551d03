#pragma once
/**
 * @file
 * Bounding-sphere hierarchy of a chain of segments (a suture centreline), after seed 000
 * §IV.B: every segment is enclosed by a leaf sphere, each pair of successive spheres by a
 * parent, up to one root (sphere_hierarchy.h). When segments move, only their spheres are
 * refitted, bottom-up (seed 000, Algorithm 1): moved leaves are marked dirty, so are
 * their ancestors, and each marked node is recomputed once, after its children.
 *
 * Deviation from the seed, on purpose: a leaf sphere is centred at the segment midpoint
 * with radius half the segment length plus the tube radius (the seed uses the whole
 * segment length as radius); it is the smallest sphere that bounds the tube, so the
 * broad phase reports fewer false pairs.
 *
 * Plain C++/Eigen, no deal.II: the realtime path and rod–tissue contact use it too.
 */

#include <suturesim/collision/sphere_hierarchy.h>

#include <Eigen/Core>

#include <cstdint>
#include <utility>
#include <vector>

namespace suturesim::collision
{
  class SphereTree : public SphereHierarchy
  {
  public:
    /// Points as columns (the realtime path's layout).
    using Points = Eigen::Ref<const Eigen::Matrix3Xd>;

    /// Builds the hierarchy over the segments (points[i], points[i+1]) for i in
    /// [0, points.size() - 1), each thickened by @p tube_radius (m).
    void
    build(const std::vector<Eigen::Vector3d> &points, double tube_radius);
    void
    build(const Points &points, double tube_radius);

    /// Bottom-up refit (seed 000, Algorithm 1) after the points moved: a leaf is dirty
    /// when one of its end points moved; ancestors are updated once each, children
    /// before parents. Returns the number of tree nodes recomputed. The number of
    /// points must not change (that would change the topology: build again).
    std::size_t
    refit(const std::vector<Eigen::Vector3d> &points);
    std::size_t
    refit(const Points &points);

    /// Refit after the caller marked moved points itself (no comparison of positions);
    /// @p moved lists point indices.
    std::size_t
    refit(const std::vector<Eigen::Vector3d> &points, const std::vector<std::size_t> &moved);
    std::size_t
    refit(const Points &points, const std::vector<std::size_t> &moved);

    /// Refit after every point moved: all leaves, then all inner nodes, no comparison
    /// of positions (the realtime path, where the whole thread moves every step).
    void
    refit_all(const Points &points);

    /// All pairs of segments (i < j) whose leaf spheres, grown by @p margin (m), overlap.
    using SphereHierarchy::self_overlaps;

    std::size_t
    n_segments() const
    {
      return n_leaves();
    }

    double
    tube_radius() const
    {
      return tube;
    }

  private:
    Sphere
    segment_sphere(const Points &points, std::size_t segment) const;

    double                       tube = 0;
    Eigen::Matrix3Xd             last_points;
    std::vector<std::size_t>     moved_work; // work space of refit(), no allocation per call
  };
} // namespace suturesim::collision
