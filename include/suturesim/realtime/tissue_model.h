#pragma once
/**
 * @file
 * Realtime tissue models, registered by name (Realtime/Tissue model), built from the
 * same gmsh mesh as the accurate path:
 *  - "surface": the boundary triangles of the tetrahedral mesh as a mass-spring membrane
 *    with home springs (seeds 001, 002, 003): nodes only on the surface;
 *  - "volume": every tetrahedron edge a spring, plus volume constraints for XPBD
 *    (seed 004);
 *  - "fe": linear tetrahedral finite elements of the stable neo-Hookean energy
 *    (neo_hookean_tetrahedra.h), which converge to the continuum under refinement.
 * Both may carry angular bending springs at chosen vertices (seed 003). Masses are
 * lumped from the density: a quarter of each tetrahedron's mass to its vertices
 * (volume), or the body's mass shared by the surface nodes in proportion to their
 * surface area (surface).
 */

#include <suturesim/core/registry.h>
#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/core/model_parameters.h>
#include <suturesim/realtime/system.h>

#include <map>
#include <vector>

namespace suturesim::realtime
{
  /// Isotropic elastic constants of the tissue (from the scene's Tissue/Material and
  /// Tissue/Region moduli).
  struct TissueMaterial
  {
    double youngs_modulus = 0; ///< E, Pa
    double poisson_ratio  = 0; ///< ν
    double density        = 0; ///< ρ, kg/m³
    /// Tetrahedra tagged with these gmsh physical volumes take their own (E, ν); the
    /// others take the values above (a layered tissue: dermis over hypodermis).
    std::map<int, std::pair<double, double>> regions;

    double
    bulk_modulus() const
    {
      return youngs_modulus / (3 * (1 - 2 * poisson_ratio));
    }
    /// E (Pa) and K (Pa) of a tetrahedron tagged @p tag.
    double
    youngs_modulus_of(int tag) const;
    double
    bulk_modulus_of(int tag) const;
    /// μ = 3KE/(9K − E) (Pa) of a tetrahedron tagged @p tag.
    double
    shear_modulus_of(int tag) const;
  };

  class TissueModel
  {
  public:
    using Registry = BasicRegistry<TissueModel, ParameterDeclarations, const ParameterValues &>;
    virtual ~TissueModel() = default;

    /// Adds the tissue's nodes and interactions to @p system (which must hold no nodes
    /// yet). @p position_based: the integrator is XPBD (volume constraints are then
    /// added where the model has them).
    void
    build(System &system, const mesh::SimplexMesh &mesh, const mesh::BoundarySurface &surface,
          const TissueMaterial &material, bool position_based);

    /// System node of mesh vertex @p v, −1 if the model does not simulate it.
    std::int64_t
    node(std::uint32_t v) const
    {
      return node_of_vertex[v];
    }

    /// The surface triangles (outward oriented) in system node indices, with their
    /// boundary tags: what the suture touches and what is written to tissue.vtu.
    const std::vector<mesh::Triangle> &
    surface() const
    {
      return surface_nodes;
    }
    const std::vector<int> &
    surface_tags() const
    {
      return tags;
    }

    /// The simulated elements for output: tetrahedra (volume) in node indices, empty
    /// for the surface model.
    const std::vector<mesh::Tetrahedron> &
    volume_cells() const
    {
      return cells;
    }

    /// Adds seed 003's angular springs at @p node: one per pair of surface edges of a
    /// surface triangle at the node. Returns how many were added.
    std::size_t
    add_bending(System &system, std::uint32_t node);

    /// Seed 002 §4.A: makes the surface point of triangle @p triangle with barycentric
    /// weights @p weights a vertex of its own by subdividing the surface there
    /// (realtime/surface_subdivision.h). Returns its node, whose triangle is then
    /// @p triangle with the node first; −1 when the model does not subdivide (the volume
    /// model, or subdivision off) or has no spare node left. The surface's triangles
    /// change: bounding trees built on them must be rebuilt.
    virtual std::int64_t
    subdivide(System &, std::uint32_t /*triangle*/, const Vector3d & /*weights*/)
    {
      return -1;
    }

  protected:
    /// The surface as the model may change it (subdivision).
    std::vector<mesh::Triangle> &
    mutable_surface()
    {
      return surface_nodes;
    }
    std::vector<int> &
    mutable_surface_tags()
    {
      return tags;
    }

    /// Adds the model's nodes (setting node_of_vertex) and interactions.
    virtual void
    add_body(System &system, const mesh::SimplexMesh &mesh, const mesh::BoundarySurface &surface,
             const TissueMaterial &material, bool position_based) = 0;

    /// The nodes of a tetrahedral body: every vertex of a tetrahedron, its mass lumped
    /// as a quarter of each of its tetrahedra's ρV (vertices of no tetrahedron, stray
    /// gmsh points, are left out); sets node_of_vertex and the output cells. Returns
    /// node_of_vertex as indices (those of left-out vertices meaningless).
    std::vector<std::uint32_t>
    add_tetrahedral_nodes(System &system, const mesh::SimplexMesh &mesh, double density);

    std::vector<std::int64_t>      node_of_vertex;
    std::vector<mesh::Tetrahedron> cells;
    double                         bending_factor = 1;
    std::string                    bending_points;

  private:
    std::vector<mesh::Triangle> surface_nodes;
    std::vector<int>            tags;
  };

  /// Declares what every tissue model offers: bending springs at chosen points.
  void
  declare_bending_parameters(ParameterDeclarations &d);
} // namespace suturesim::realtime
