#pragma once
/**
 * @file
 * Bounding-sphere hierarchy of a triangle surface (the tissue surface the suture lies
 * on): seed 000 §IV.A says a deformable object is handled like the thread. Each triangle
 * gets a leaf sphere (centred at its centroid, through its farthest vertex, grown by a
 * thickness); the leaves are put in Morton (Z-curve) order of their rest centroids, so
 * that successive leaves are neighbours and pairing them level by level (sphere_hierarchy.h)
 * gives a tree of compact spheres. The order is fixed at build(); deformation only refits
 * (seed 000, Algorithm 1).
 */

#include <suturesim/collision/sphere_hierarchy.h>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace suturesim::collision
{
  class TriangleSphereTree : public SphereHierarchy
  {
  public:
    using Points    = Eigen::Ref<const Eigen::Matrix3Xd>;
    using Triangles = std::vector<std::array<std::uint32_t, 3>>;

    /// Builds the tree over @p triangles (vertex indices into the columns of
    /// @p vertices), each leaf sphere grown by @p thickness (m).
    void
    build(const Points &vertices, const Triangles &triangles, double thickness);

    /// Refit after every vertex moved: all leaves, then all inner nodes.
    void
    refit(const Points &vertices);

    /// Refit after the vertices listed in @p moved moved (bottom-up, each marked node
    /// once); returns the number of nodes recomputed.
    std::size_t
    refit(const Points &vertices, const std::vector<std::uint32_t> &moved);

    /// Lazy refit with slack s (the "fat" bounds of Box2D's and Bullet's dynamic trees):
    /// a leaf fitted when its vertices were at x₀ and grown by s still bounds its
    /// triangle while every vertex stays within s of x₀ (|x − c| ≤ |x₀ − c| + s). Only
    /// leaves with a vertex that moved farther are refitted (and their ancestors, once,
    /// bottom-up); a slowly deforming surface costs one distance test per vertex.
    /// @p slack (m) is fixed by the first call; returns the number of nodes recomputed.
    std::size_t
    update(const Points &vertices, double slack);

    /// The triangle bounded by leaf @p leaf.
    std::uint32_t
    triangle(const std::size_t leaf) const
    {
      return order[leaf];
    }

    double
    thickness() const
    {
      return margin;
    }

  private:
    Sphere
    triangle_sphere(const Points &vertices, std::uint32_t triangle, double grow) const;

    const Triangles           *tris = nullptr;
    double                     margin = 0;
    std::vector<std::uint32_t> order;          ///< leaf → triangle
    std::vector<std::uint32_t> vertex_offsets; ///< CSR: vertex → leaves touching it
    std::vector<std::uint32_t> vertex_leaves;
    // update(): vertex positions at the last fit of their leaves, and the slack
    Eigen::Matrix3Xd           fitted;
    std::vector<std::uint32_t> escaped;
    double                     slack = -1;
  };
} // namespace suturesim::collision
