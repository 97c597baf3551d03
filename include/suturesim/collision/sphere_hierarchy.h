#pragma once
/**
 * @file
 * The bounding-sphere hierarchy of seed 000 §IV, independent of what the leaves bound:
 * leaves in a given order, each pair of successive nodes of one level enclosed by a
 * parent on the next, up to one root, so the tree is balanced and its topology never
 * changes while the primitives keep their number. Moved primitives update their leaf and
 * mark it dirty; refit() then recomputes every marked ancestor once, after its children
 * (seed 000, Algorithm 1). Nodes are stored level by level from the leaves up, so every
 * parent comes after its children and one sweep in index order is that bottom-up order
 * (the seed keeps a priority queue by level; the storage order makes it unnecessary).
 *
 * The leaf order decides the quality of the tree: a chain (suture) is already ordered
 * along its length; a triangle surface is put in Morton (Z-curve) order of its centroids
 * first, so that successive leaves are neighbours in space.
 *
 * Plain C++/Eigen, no deal.II: the realtime path uses it.
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

  /// Pairs of leaves (i of the first hierarchy, j of the second) whose spheres overlap.
  using LeafPairs = std::vector<std::pair<std::uint32_t, std::uint32_t>>;

  class SphereHierarchy
  {
  public:
    /// Builds the balanced tree over @p leaves, in their order.
    void
    build_from_leaves(const std::vector<Sphere> &leaves);

    /// Replaces leaf @p leaf and marks it and its ancestors for the next refit_marked().
    /// Returns false when the leaf was marked already.
    bool
    set_leaf(std::size_t leaf, const Sphere &sphere);

    /// Recomputes every marked inner node once, children before parents; returns how
    /// many inner nodes were recomputed.
    std::size_t
    refit_marked();

    /// Recomputes every inner node from the leaves (after all leaves changed).
    void
    refit_all_inner();

    /// All pairs of distinct leaves (i < j) whose spheres, grown by @p margin (m),
    /// overlap: a simultaneous descent of the tree against itself.
    void
    self_overlaps(double margin, LeafPairs &pairs) const;

    /// All pairs (leaf of this, leaf of @p other) whose spheres, grown by @p margin (m),
    /// overlap.
    void
    overlaps(const SphereHierarchy &other, double margin, LeafPairs &pairs) const;

    /// The leaves whose spheres overlap the sphere (@p centre, @p radius) into @p leaves
    /// (cleared first): a point query, e.g. a needle tip against a surface.
    void
    leaves_near(const Eigen::Vector3d &centre, double radius, std::vector<std::uint32_t> &leaves) const;

    std::size_t
    n_leaves() const
    {
      return leaves;
    }

    /// Spheres of the tree, leaves first (in leaf order), the root last; every parent
    /// after its children.
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

  protected:
    Sphere &
    leaf_sphere(std::size_t leaf)
    {
      return nodes[leaf];
    }

  private:
    void
    update_node(std::size_t node);
    void
    descend_self(int a, int b, double margin, LeafPairs &pairs) const;
    void
    descend_other(const SphereHierarchy &other, int a, int b, double margin,
                  LeafPairs &pairs) const;

    std::size_t                      leaves = 0;
    std::vector<Sphere>              nodes;
    std::vector<std::pair<int, int>> children;
    std::vector<int>                 parent;
    std::vector<char>                dirty;
  };
} // namespace suturesim::collision
