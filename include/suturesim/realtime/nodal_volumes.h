#pragma once
/**
 * @file
 * The volumetric energy of linear tetrahedra averaged over each node's patch, Bonet &
 * Burton's average nodal pressure tetrahedron (J. Bonet, A. J. Burton 1998, "A simple
 * average nodal pressure tetrahedral element for incompressible and nearly incompressible
 * dynamic explicit applications", Commun. Numer. Meth. Engng 14:437–449), in the energy
 * form that makes its forces a gradient (Bonet, Marriott & Hassan 2001, Int. J. Numer.
 * Meth. Engng 50:119–133, §3): with each tetrahedron's volume v_e = V_e det F_e shared
 * equally by its four nodes,
 *
 *   v_a = Σ_{e∋a} v_e/4,  V_a = Σ_{e∋a} V_e/4,  J_a = v_a/V_a,
 *   E = Σ_a V_a λ_a/2 (J_a − 1)²,  λ_a = Σ_{e∋a} λ_e V_e/4 / V_a,
 *
 * and forces fᵢ = −Σ_{e∋i} p̄_e V_e cof(F_e) bᵢ, where p̄_e = ¼ Σ_{a∈e} λ_a (J_a − 1) is
 * the element's average of its nodes' pressures. A linear tetrahedron whose own J carries
 * the bulk term has one volume constraint per element, about five per node on a
 * tetrahedral mesh against three degrees of freedom, and locks as ν → ½; one constraint
 * per node does not. The deviatoric and shear response stays with the elements
 * (neo_hookean_tetrahedra.h with λ = 0), so no displacement mode is free of energy.
 *
 * Vertex block descent: fᵢ as above and Hᵢ = Σ_a (λ_a/V_a) g_a g_aᵀ with
 * g_a = ∂v_a/∂xᵢ = ¼ Σ_{e∋i,a} V_e cof(F_e) bᵢ, exact (each v_e is linear in each vertex)
 * and positive semi-definite. A node's block reads the pressures of every node of its
 * elements, and so the volumes of their patches: the family keeps the current element
 * and nodal volumes, renewed before each sweep and after each move (Interaction::
 * begin_sweep, vertex_moved), so that a block costs its own elements only.
 */

#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/realtime/tetrahedron_nodes.h>

#include <array>
#include <vector>

namespace suturesim::realtime
{
  class NodalVolumes : public TetrahedralElements
  {
  public:
    std::string
    name() const override
    {
      return "averaged nodal volumes";
    }

    /// One element per tetrahedron of @p mesh (@p node maps mesh vertices to system
    /// nodes) with Lamé's λ (Pa) @p lambda, one value per tetrahedron; once per family.
    /// Throws for a degenerate tetrahedron or λ < 0.
    void
    add_mesh(const mesh::SimplexMesh &mesh, const std::vector<std::uint32_t> &node, const std::vector<double> &lambda);

    double
    energy(const Matrix3Xd &x) const override;
    void
    add_forces(const Matrix3Xd &x, Matrix3Xd &f) const override;
    /// The elements with a node in @p touched, so that a boundary's reaction evaluates
    /// those only (World::reaction).
    bool
    elements_touching(const std::vector<char> &touched, std::vector<std::uint32_t> &tetrahedra) const override
    {
      return tetrahedra_touching(tets, touched, tetrahedra);
    }
    /// add_forces() of the listed elements, in their order (every node's pressure still
    /// needs every element's volume: one pass without the forces).
    void
    add_forces_of(const Matrix3Xd &x, Matrix3Xd &f, const std::vector<std::uint32_t> &tetrahedra) const override;
    /// Reads the volumes of the last begin_sweep() and vertex_moved(), which must be
    /// those of @p x.
    void
    add_vertex_block(const Matrix3Xd &x, std::uint32_t i, const std::uint32_t *tetrahedra, std::size_t n, Vector3d &f,
                     Eigen::Matrix3d &H) const override;
    void
    begin_sweep(const Matrix3Xd &x) override;
    void
    vertex_moved(const Matrix3Xd &x, std::uint32_t i, const std::uint32_t *tetrahedra, std::size_t n) override;
    /// False: a block reads the pressures of its elements' nodes, and so the volumes of
    /// their patches, which a move of a node two elements away changes.
    bool
    vertex_blocks_local() const override
    {
      return false;
    }
    /// max |J_a − 1| over the nodes
    double
    max_violation(const Matrix3Xd &x) const override;

  private:
    struct Element
    {
      double                       orientation; ///< ±1, the rest volume's sign
      std::array<std::uint32_t, 4> local;       ///< the nodes' indices into the per-node arrays
    };
    /// v_e = V_e J_e of tetrahedron @p t at @p x: its signed volume times its rest
    /// volume's sign, so that the gradients V_e cof(F_e) bᵢ are volume_gradients()'s
    /// times the orientation, and no element needs F
    double
    current_volume(const Matrix3Xd &x, std::size_t t) const;
    /// The nodes' volumes v_a at @p x into @p v (and the elements' v_e into
    /// @p element_volumes)
    void
    nodal_volumes(const Matrix3Xd &x, std::vector<double> &v, std::vector<double> *element_volumes = nullptr) const;
    /// work ← the nodes' pressures λ_a (J_a − 1) at @p x
    void
    nodal_pressures(const Matrix3Xd &x) const;
    /// f −= p̄_e ∂v_e/∂xᵢ at the four nodes of element @p t, from the pressures in work
    void
    add_element_forces(const Matrix3Xd &x, Matrix3Xd &f, std::size_t t) const;

    std::vector<Element> elements;
    std::vector<double>  rest_volume;         ///< V_a
    std::vector<double>  inverse_rest_volume; ///< 1/V_a, for the blocks' pressures
    std::vector<double>  modulus;             ///< λ_a
    std::vector<double>  volume_now;          ///< v_e of the current sweep
    std::vector<double>  nodal_now;           ///< v_a of the current sweep
    /// the per-node index of system node @p i, a node of element @p t
    std::uint32_t
    node_of(const std::uint32_t t, const std::uint32_t i) const
    {
      return elements[t].local[local_index(tets[t], i)];
    }

    // scratch of the const evaluations: v_a in energy() and add_forces() (on the stepping
    // thread), and for the blocks, which may run on several threads at once for nodes
    // that share no element's node (Interaction::vertex_blocks_local), what each block
    // writes only of its node, its elements and their nodes: the g_a being summed, and
    // ∂v_e/∂xᵢ of each element and vertex with the vertex's position at its block, from
    // which vertex_moved() updates the volumes
    mutable std::vector<double>   work;
    mutable std::vector<Vector3d> gradient;       ///< per node
    mutable std::vector<char>     block_pending;  ///< per node: its block ran, vertex_moved() not yet
    mutable std::vector<Vector3d> block_position; ///< per node
    mutable std::vector<Vector3d> block_gradient; ///< per element and vertex, 4 t + k
  };
} // namespace suturesim::realtime
