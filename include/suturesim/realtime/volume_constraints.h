#pragma once
/**
 * @file
 * Volume preservation of tetrahedra (seed 004's tetrahedral tissue under position-based
 * dynamics): C = V − V₀ with V = (x₁ − x₀)·((x₂ − x₀) × (x₃ − x₀))/6, energy
 * ½ (K_v/V₀) C² (the volumetric energy ½ K (J − 1)² V₀ of a compressible solid), so the
 * XPBD compliance is α = V₀/K_v. Gradients ∇₁V = (x₂ − x₀)×(x₃ − x₀)/6 and cyclic,
 * ∇₀V = −(∇₁V + ∇₂V + ∇₃V) (Müller et al. 2007, "Position based dynamics", §4).
 * K_v is the bulk stiffness the edge springs lack: K − 2E/3 (spring_set.h).
 */

#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/realtime/system.h>

#include <array>
#include <vector>

namespace suturesim::realtime
{
  class VolumeConstraints : public Interaction
  {
  public:
    std::string
    name() const override
    {
      return "volume constraints";
    }
    std::size_t
    size() const override
    {
      return rest.size();
    }

    /// One constraint per tetrahedron (@p node maps mesh vertices to system nodes),
    /// bulk stiffness @p bulk_modulus (Pa): one value for all, or one per tetrahedron.
    void
    add_mesh(const mesh::SimplexMesh &mesh, const std::vector<std::uint32_t> &node,
             double bulk_modulus);
    void
    add_mesh(const mesh::SimplexMesh &mesh, const std::vector<std::uint32_t> &node,
             const std::vector<double> &bulk_modulus);

    double
    energy(const Matrix3Xd &x) const override;
    void
    add_forces(const Matrix3Xd &x, Matrix3Xd &f) const override;
    void
    add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, double dt) const override;
    bool
    elements_touching(const std::vector<char> &touched, std::vector<std::uint32_t> &tetrahedra) const override;
    void
    add_forces_of(const Matrix3Xd &x, Matrix3Xd &f, const std::vector<std::uint32_t> &tetrahedra) const override;
    void
    add_constraint_forces_of(const Matrix3Xd &x, Matrix3Xd &f, double dt,
                             const std::vector<std::uint32_t> &tetrahedra) const override;
    bool
    add_forces_on(const Matrix3Xd &x, const std::vector<std::uint32_t> &tetrahedra, const std::vector<char> &touched,
                  Vector3d &sum) const override;
    bool
    add_constraint_forces_on(const Matrix3Xd &x, double dt, const std::vector<std::uint32_t> &tetrahedra,
                             const std::vector<char> &touched, Vector3d &sum) const override;
    bool
    element_nodes(std::vector<std::uint32_t> &nodes, unsigned &per_element) const override;
    /// f = −(K_v/V₀) C ∇ᵢV, H = (K_v/V₀) ∇ᵢV ∇ᵢVᵀ: exact, since V is linear in each vertex
    void
    add_vertex_block(const Matrix3Xd &x, std::uint32_t i, const std::uint32_t *tetrahedra, std::size_t n, Vector3d &f,
                     Eigen::Matrix3d &H) const override;
    void
    reset_multipliers() override;
    void
    warm_multipliers(const VectorXd &w, double scale) override;
    std::size_t
    revision() const override
    {
      return changes;
    }
    bool
    partition(const std::vector<std::uint32_t> &node_part, const std::vector<std::uint32_t> &local,
              unsigned parts) override;
    const std::vector<std::size_t> *
    blocks() const override
    {
      return parallel.empty() ? nullptr : &parallel;
    }
    void
    project_block(unsigned p, Matrix3Xd &x, const VectorXd &w, double dt) override;
    void
    add_constraint_forces_block(unsigned p, const Matrix3Xd &x, Matrix3Xd &f, double dt) const override;
    void
    add_constraint_forces_range(const Matrix3Xd &x, Matrix3Xd &f, double dt, std::size_t begin,
                                std::size_t end) const override;
    void
    project_range(Matrix3Xd &x, const VectorXd &w, double dt, std::size_t begin, std::size_t end) override;
    void
    project(Matrix3Xd &x, const VectorXd &w, double dt) override;
    void
    prepare_projection(double dt) override;
    /// max |V − V₀| / V₀
    double
    max_violation(const Matrix3Xd &x) const override;

  private:
    /// Permutes every per-tetrahedron array: position k gets tetrahedron order[k].
    void
    reorder(const std::vector<std::size_t> &order);

    /// The volume of tetrahedron @p t at @p x.
    double
    volume(const Matrix3Xd &x, std::size_t t) const;
    /// f += p(t, V) ∇V for the tetrahedra t = tet(k), k < n, with vertices[t]: the one
    /// loop of elastic and constraint forces, of all tetrahedra, a list or a block (its
    /// local node indices).
    template <typename Pressure, typename Tet>
    void
    add_pressure_forces(const Matrix3Xd &x, Matrix3Xd &f, const Pressure &pressure, const Tet &tet, std::size_t n,
                        const mesh::Tetrahedron *vertices) const;
    /// Σ over the flagged nodes of add_pressure_forces()' forces from the listed
    /// tetrahedra: p Σ ∇ᵢV over their flagged vertices i.
    template <typename Pressure>
    Vector3d
    pressure_force_on(const Matrix3Xd &x, const Pressure &pressure, const std::vector<std::uint32_t> &tetrahedra,
                      const std::vector<char> &touched) const;

    std::vector<mesh::Tetrahedron> tets;
    std::vector<double>            rest, stiffness, lambda; ///< V₀, K_v/V₀, λ
    std::vector<std::size_t>       parallel; ///< blocks() of the last partition()
    /// the tetrahedra of blocks below the interface, as indices into their part
    std::vector<mesh::Tetrahedron> local_tets;
    std::size_t                    changes = 0; ///< revision(): add_mesh() and partition()
    std::vector<double>            alpha_tilde; ///< 1/(k dt²) for the step prepared_dt
    double                         prepared_dt = 0;
  };
} // namespace suturesim::realtime
