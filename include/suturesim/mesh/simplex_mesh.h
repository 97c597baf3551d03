#pragma once
/**
 * @file
 * A tetrahedral mesh as the realtime path needs it: vertex coordinates as the columns of
 * one matrix, tetrahedra and tagged boundary triangles as index arrays, gmsh's physical
 * names for the tags. The gmsh reader lives with the scene layer (mesh/gmsh_reader.h);
 * this header and its source are plain C++/Eigen and belong to the realtime library.
 */

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace suturesim::mesh
{
  using Tetrahedron = std::array<std::uint32_t, 4>;
  using Triangle    = std::array<std::uint32_t, 3>;

  struct SimplexMesh
  {
    Eigen::Matrix3Xd         vertices;      ///< m, one column per vertex
    std::vector<Tetrahedron> tetrahedra;
    std::vector<int>         tetrahedron_tags; ///< gmsh physical volume (material id), 0 if none
    std::vector<Triangle>    triangles;     ///< gmsh's triangles of physical surfaces
    std::vector<int>         triangle_tags; ///< their physical surface (boundary id)
    std::map<int, std::string> boundary_names; ///< boundary id → physical name
    std::map<int, std::string> material_names;
    std::string              description;

    /// Signed volume of tetrahedron @p t (m³), positive for gmsh's orientation.
    double
    volume(std::size_t t) const;

    /// The mesh's volume, the sum of its tetrahedra's (m³).
    double
    total_volume() const;

    /// The boundary id of a boundary given by name or number; -1 if there is none.
    int
    boundary_id(const std::string &name_or_id) const;
  };

  /// The closed surface of a tetrahedral mesh: the faces that belong to one tetrahedron
  /// only, oriented with outward normals, each with the tag of the gmsh triangle on it
  /// (0 where gmsh wrote none).
  struct BoundarySurface
  {
    std::vector<Triangle>      triangles;
    std::vector<int>           tags;
    std::vector<std::uint32_t> vertices; ///< the mesh vertices on the surface, ascending
  };

  /// Extracts the boundary surface. Throws std::invalid_argument naming the tetrahedron
  /// when one is inverted or degenerate (volume ≤ 1e-12 of the mean), or when a face is
  /// shared by more than two tetrahedra (not a manifold mesh).
  BoundarySurface
  extract_boundary(const SimplexMesh &mesh);

  /// A point of a triangle rule: barycentric coordinates (λ₀, λ₁, λ₂) and the weight as
  /// a fraction of the triangle's area.
  struct TrianglePoint
  {
    std::array<double, 3> barycentric;
    double                weight;
  };

  /// The composite centroid rule: the triangle split into @p n² congruent sub-triangles
  /// (n ≥ 1), a point at each one's centroid with weight 1/n². ∫ f dA ≈ A Σ w f(x_q);
  /// exact for linear f, error O(n⁻²) for smooth f, and for a jump along a curve the
  /// points sample the two sides in proportion to the areas as n grows. With linear
  /// shape functions Nᵢ = λᵢ it gives the consistent nodal loads fᵢ = ∫ t Nᵢ dA
  /// (realtime tractions, scene/realtime_world.h).
  std::vector<TrianglePoint>
  subtriangle_centroids(unsigned n);

  /// Vertices (ascending) of the boundary triangles tagged @p tag.
  std::vector<std::uint32_t>
  vertices_with_tag(const BoundarySurface &surface, int tag);
} // namespace suturesim::mesh
