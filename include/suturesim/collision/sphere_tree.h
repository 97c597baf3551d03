#pragma once
/**
 * @file
 * Bounding-sphere hierarchy of a chain of segments (a suture centreline), after seed 000
 * §IV.B: every segment is enclosed by a leaf sphere, each pair of successive spheres by a
 * parent, up to one root; the hierarchy is a balanced binary tree whose topology never
 * changes while the chain keeps its segments. When segments move, only their spheres are
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

#include <Eigen/Core>

#include <cstdint>
#include <utility>
#include <vector>

namespace suturesim::collision
{
  struct Sphere
  {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double          radius = 0;

    /// True when @p other lies inside this sphere up to a relative slack of 1e-12.
    bool
    contains(const Sphere &other) const;
  };

  /// The smallest sphere enclosing two spheres.
  Sphere
  enclosing_sphere(const Sphere &a, const Sphere &b);

  class SphereTree
  {
  public:
    /// Builds the hierarchy over the segments (points[i], points[i+1]) for i in
    /// [0, points.size() - 1), each thickened by @p tube_radius (m).
    void
    build(const std::vector<Eigen::Vector3d> &points, double tube_radius);

    /// Bottom-up refit (seed 000, Algorithm 1) after the points moved: a leaf is dirty
    /// when one of its end points moved; ancestors are updated once each, children
    /// before parents. Returns the number of tree nodes recomputed. The number of
    /// points must not change (that would change the topology: build again).
    std::size_t
    refit(const std::vector<Eigen::Vector3d> &points);

    /// Refit after the caller marked moved points itself (no comparison of positions);
    /// @p moved lists point indices.
    std::size_t
    refit(const std::vector<Eigen::Vector3d> &points, const std::vector<std::size_t> &moved);

    /// All pairs of segments (i < j) whose leaf spheres, grown by @p margin (m), overlap,
    /// found by a simultaneous descent of the tree against itself.
    void
    self_overlaps(double margin, std::vector<std::pair<std::uint32_t, std::uint32_t>> &pairs) const;

    std::size_t
    n_segments() const
    {
      return n_leaves;
    }

    /// Spheres of the tree, stored level by level from the leaves up: the first
    /// n_segments entries are the leaves in segment order, the last one is the root, and
    /// every parent comes after its children (so the index orders the refit queue).
    const std::vector<Sphere> &
    spheres() const
    {
      return nodes;
    }

    std::size_t
    root() const
    {
      return nodes.size() - 1;
    }

    /// Children of a tree node (-1 for none).
    int
    left_child(std::size_t node) const
    {
      return children[node].first;
    }
    int
    right_child(std::size_t node) const
    {
      return children[node].second;
    }

  private:
    Sphere
    leaf_sphere(const std::vector<Eigen::Vector3d> &points, std::size_t segment) const;
    void
    update_node(std::size_t node);
    void
    descend(int a, int b, double margin,
            std::vector<std::pair<std::uint32_t, std::uint32_t>> &pairs) const;

    double                           tube = 0;
    std::size_t                      n_leaves = 0;
    std::vector<Sphere>              nodes;
    std::vector<std::pair<int, int>> children;
    std::vector<int>                 parent;
    std::vector<Eigen::Vector3d>     last_points;
    // work space of refit(), kept to avoid allocation per call
    std::vector<char>                dirty;
    std::vector<std::size_t>         moved_work;
  };
} // namespace suturesim::collision
