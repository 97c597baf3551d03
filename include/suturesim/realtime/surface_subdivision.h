#pragma once
/**
 * @file
 * Seed 002 §4.A (Marshall, Payandeh & Dill 2005, "Suturing for surface meshes"): where
 * the needle touches a surface mass-spring mesh, the touched triangle is subdivided so
 * that the pierce point is a vertex of its own, and the pierced vertex is then what
 * slides on the needle and the suture.
 *
 *  1. the triangle (a, b, c) is split into three about the new vertex P at the touched
 *     point (P = Σ wᵢ xᵢ, its rest position Σ wᵢ Xᵢ);
 *  2. each of the triangle's original edges is split by Loop's edge mask (Loop 1987,
 *     "Smooth subdivision surfaces based on triangles", MSc thesis, Univ. of Utah; seed
 *     002 Fig. 3): E_ab = 3/8 (a + b) + 1/8 (P + d), d the vertex opposite ab in the
 *     neighbouring triangle, which is split in two along E_ab d. The mask moves E_ab off
 *     the edge, away from P, so that a point pierced near an edge does not leave slivers
 *     (seed 002 Fig. 4). The pierced triangle becomes a fan of six around P, each
 *     neighbour two: four new nodes, eight more triangles, twelve more springs (the three
 *     split edges' first halves reuse their springs' slots);
 *  3. every spring of the patch gets seed 002's rule, eq. (1): rest length 0.9 l (l its
 *     length at creation: "to place the mesh under tension") and stiffness
 *     k = (l_max/l) k_mesh clamped to [k_mesh, 4 k_mesh] "for stability", l_max the
 *     longest surface edge at set-up. The seed's mesh has one k_mesh; this model's
 *     membrane springs follow Delingette's rule edge by edge, so k_mesh here is the mean
 *     stiffness of the pierced triangle's three edges. The rest-length factor is a
 *     parameter (1 makes the patch stress-free at creation).
 *  4. Masses and home springs follow the surface model's own rules (a node's share of the
 *     surface area, surface_tissue.cc) on the patch, scaled so that the patch keeps its
 *     total mass and its total home-spring stiffness (the seed gives every vertex unit
 *     mass, which this model does not).
 *
 * New nodes come from a pool of spare ("dormant", held) tissue nodes set aside when the
 * model is built, so that node indices, the tissue's node range and the suture's after
 * it never move. A subdivision changes the surface's triangles: its caller must rebuild
 * the bounding trees built on them.
 */

#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/realtime/home_springs.h>
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/system.h>

#include <cstdint>
#include <vector>

namespace suturesim::realtime
{
  struct SubdivisionParameters
  {
    double   rest_length_factor = 0.9; ///< rest length / length at creation (seed 002: 0.9)
    unsigned capacity           = 16;  ///< subdivisions the spare nodes allow (four nodes each)
  };

  /// How the surface model lumps mass and home-spring stiffness on a node: per unit of its
  /// share of the reference surface area (Winkler), or a constant per node.
  struct SurfaceLumping
  {
    double mass_per_area = 0; ///< kg/m²
    double home_per_area = 0; ///< N/m³ (Winkler rule); 0: constant per node
    double home_constant = 0; ///< N/m per node (constant rule)
  };

  class SurfaceSubdivision
  {
  public:
    /// The spare nodes are [@p first_spare, @p first_spare + 4 capacity) of @p system
    /// (held as dormant, with home springs of their own in @p home); @p longest_edge is
    /// l_max, m.
    SurfaceSubdivision(const SubdivisionParameters &parameters, SpringSet &springs, HomeSprings &home,
                       std::uint32_t first_spare, const SurfaceLumping &lumping, double longest_edge);

    /// Subdivides triangle @p triangle of @p triangles (outward oriented, closed surface,
    /// node indices; @p tags alongside) at the point of barycentric weights @p weights.
    /// Returns the new vertex's node, −1 when no spare nodes are left. Triangle
    /// @p triangle becomes (P, a, E_ab): the touched point is its first vertex.
    std::int64_t
    subdivide(System &system, std::vector<mesh::Triangle> &triangles, std::vector<int> &tags,
              std::uint32_t triangle, const Eigen::Vector3d &weights);

    /// Subdivisions made so far.
    unsigned
    count() const
    {
      return used;
    }
    const SubdivisionParameters &
    parameters() const
    {
      return prm;
    }

  private:
    /// Stiffness of a new spring of length @p l from seed 002's eq. (1), N/m.
    double
    stiffness(double l, double k_mesh) const;
    /// Masses and home springs of the nodes of the patch whose triangles @p old_patch
    /// became @p new_patch (new nodes P … P + 3): each node's share of the surface
    /// changes by a third of the area of its triangles, rescaled so that the patch keeps
    /// its totals.
    void
    relump(Nodes &nodes, const std::vector<mesh::Triangle> &old_patch,
           const std::vector<mesh::Triangle> &new_patch, std::uint32_t P);

    SubdivisionParameters prm;
    SpringSet            &springs;
    HomeSprings          &home;
    std::uint32_t         first_spare;
    SurfaceLumping        lumping;
    double                longest_edge;
    unsigned              used = 0;
  };
} // namespace suturesim::realtime
