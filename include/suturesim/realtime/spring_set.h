#pragma once
/**
 * @file
 * Edge springs (seed 001 §2): F = k (L − L₀) (P_a − P)/|P_a − P| on each end, energy
 * ½ k (L − L₀)²; under XPBD the distance constraint C = L − L₀ with compliance 1/k.
 * Stored as a structure of arrays (end indices, rest lengths, stiffnesses, multipliers),
 * contiguous and ordered so that consecutive springs share no node (independent_order.h).
 *
 * Stiffness from the material (rules with no fitted constant; spring_identification.h
 * identifies them from the linear FE element instead, and docs/calibration.md fits
 * scales of them to the FE model):
 *  - volume (tetrahedron edges): k_e = c Σ_{T∋e} V_T / L_e², Van Gelder (1998),
 *    "Approximate simulation of elastic membranes by triangulated spring meshes",
 *    J. Graphics Tools 3(2):21–42, §5 (three dimensions), with c = E. Under a uniform
 *    dilatation ε = e I every edge stretches by e L_e, so the network stores
 *    Σ ½ k_e L_e² e² = ½ E e² · 6V = 3E e² V, which equals the continuum ½·9K e² V for
 *    K = 2E/3, i.e. ν = 1/4 — the Cauchy relation of central-force networks: a spring
 *    network cannot represent another ν. The XPBD volume constraints (volume_constraints.h)
 *    add the missing bulk stiffness K − 2E/3.
 *  - surface (triangle edges, a membrane of thickness t): the tensile part of
 *    Delingette's triangular biquadratic springs, linearised at rest,
 *    k_e = Σ_{T∋e} E t L_e² (2 cot²θ_e + 1 − ν) / (8 (1 − ν²) A_T), θ_e the angle of T
 *    opposite e (Delingette 2008, "Triangular springs for modeling nonlinear membranes",
 *    IEEE TVCG 14(2):329–341: k_T = E t (2cot²θ + 1 − ν)/(16(1 − ν²)A_T) for the
 *    biquadratic energy k_T/4 (L² − L₀²)², whose second derivative at rest is
 *    2 k_T L₀²). The angular springs of that model are left out; they vanish for
 *    equilateral triangles at ν = 1/3, where the rule reproduces the plane-stress
 *    energy of the triangle exactly (tested), and otherwise make the network softer in
 *    shear than the membrane.
 */

#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/realtime/system.h>

#include <array>
#include <functional>
#include <vector>

namespace suturesim::realtime
{
  class SpringSet : public Interaction
  {
  public:
    explicit SpringSet(std::string name)
      : label(std::move(name))
    {}

    std::string
    name() const override
    {
      return label;
    }
    std::size_t
    size() const override
    {
      return first.size();
    }

    /// Adds a spring between nodes @p i and @p j with rest length @p rest (m) and
    /// stiffness @p k (N/m).
    void
    add(std::uint32_t i, std::uint32_t j, double rest, double k);

    /// Spring @p s becomes one between nodes @p i and @p j with rest length @p rest (m) and
    /// stiffness @p k (N/m): a topology change (seed 002's edge split) reuses its slot.
    void
    set(std::size_t s, std::uint32_t i, std::uint32_t j, double rest, double k);

    /// Spring @p s's stiffness becomes @p k (N/m, >= 0; ∞: rigid). k = 0 leaves the spring out
    /// without a topology change: it exerts no force, stores no energy and, under XPBD,
    /// corrects nothing (α̃ is then the largest double and its multiplier stays 0). A
    /// constraint that stands in for the spring for a while (realtime/node_access.h)
    /// leaves it out and gives it back.
    void
    set_stiffness(std::size_t s, double k);

    /// Removes the springs between nodes i, j (i < j) for which @p cut(i, j) holds (a
    /// tear, tearing/ligament_tear.h): a topology change; the rest are ordered again as
    /// sort() does. Returns how many went.
    std::size_t
    remove_if(const std::function<bool(std::uint32_t, std::uint32_t)> &cut);

    /// Index of the spring between nodes @p i and @p j, or size() if there is none.
    std::size_t
    find(std::uint32_t i, std::uint32_t j) const;

    /// Orders the springs so that consecutive ones share no node (independent_order.h);
    /// call once after adding.
    void
    sort();

    double
    energy(const Matrix3Xd &x) const override;
    void
    add_forces(const Matrix3Xd &x, Matrix3Xd &f) const override;
    void
    add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, double dt) const override;
    bool
    elements_touching(const std::vector<char> &touched, std::vector<std::uint32_t> &springs) const override;
    std::size_t
    revision() const override
    {
      return changes;
    }
    void
    add_forces_of(const Matrix3Xd &x, Matrix3Xd &f, const std::vector<std::uint32_t> &springs) const override;
    void
    add_constraint_forces_of(const Matrix3Xd &x, Matrix3Xd &f, double dt,
                             const std::vector<std::uint32_t> &springs) const override;
    bool
    add_forces_on(const Matrix3Xd &x, const std::vector<std::uint32_t> &springs, const std::vector<char> &touched,
                  Vector3d &sum) const override;
    bool
    add_constraint_forces_on(const Matrix3Xd &x, double dt, const std::vector<std::uint32_t> &springs,
                             const std::vector<char> &touched, Vector3d &sum) const override;
    bool
    element_nodes(std::vector<std::uint32_t> &nodes, unsigned &per_element) const override;
    /// f = ±k (L − L₀) n, H = k [n nᵀ + max(0, 1 − L₀/L)(I − n nᵀ)] (the exact Hessian
    /// with its transverse part clipped at zero under compression: Chen et al. 2024, §3.4)
    void
    add_vertex_block(const Matrix3Xd &x, std::uint32_t i, const std::uint32_t *springs, std::size_t n, Vector3d &f,
                     Eigen::Matrix3d &H) const override;
    void
    reset_multipliers() override;
    void
    warm_multipliers(const VectorXd &w, double scale) override;
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
    /// max |L − L₀| / L₀
    double
    max_violation(const Matrix3Xd &x) const override;

    /// Post-step strain limiting (seed 003; Provot 1995, "Deformation constraints in a
    /// mass-spring model to describe rigid cloth behavior", Graphics Interface): every
    /// spring stretched or compressed beyond a relative strain @p limit is moved back to
    /// the limit, the correction shared by inverse mass; @p sweeps Gauss–Seidel sweeps.
    /// Returns the number of corrections of the last sweep.
    std::size_t
    limit_strain(Matrix3Xd &x, const VectorXd &w, double limit, unsigned sweeps) const;

    const std::vector<std::uint32_t> &
    first_ends() const
    {
      return first;
    }
    const std::vector<std::uint32_t> &
    second_ends() const
    {
      return second;
    }
    const std::vector<double> &
    rest_lengths() const
    {
      return rest;
    }
    const std::vector<double> &
    stiffnesses() const
    {
      return stiffness;
    }

  private:
    /// The springs' end pairs, for the orderings of independent_order.h.
    std::vector<std::array<std::uint32_t, 2>>
    ends() const;
    /// Permutes every per-spring array: position s gets spring order[s].
    void
    reorder(const std::vector<std::size_t> &order);

    /// f += t(s, L) (x_b − x_a)/L on a = I[s], the opposite on b = J[s], for the springs
    /// s = spring(k), k < n: the one kernel of elastic and constraint forces, of all
    /// springs, a list or a block (its local node indices).
    template <typename Tension, typename Spring>
    void
    add_tension_forces(const Matrix3Xd &x, Matrix3Xd &f, const Tension &tension, const Spring &spring, std::size_t n,
                       const std::uint32_t *I, const std::uint32_t *J) const;
    /// Σ over the flagged nodes of add_tension_forces()' forces from the listed springs;
    /// a spring with both ends flagged or neither adds nothing to it and is skipped.
    template <typename Tension>
    Vector3d
    tension_force_on(const Matrix3Xd &x, const Tension &tension, const std::vector<std::uint32_t> &springs,
                     const std::vector<char> &touched) const;

    std::string                label;
    std::vector<std::uint32_t> first, second;
    std::vector<double>        rest, stiffness, lambda;
    /// blocks() of the last partition(); emptied by add(), set() and sort()
    std::vector<std::size_t> parallel;
    /// the ends of the springs of blocks below the interface, as indices into their part
    std::vector<std::uint32_t> local_first, local_second;
    std::size_t                changes = 0; ///< revision()
    /// α̃ = 1/(k dt²) for the step prepared_dt (prepare_projection)
    std::vector<double> alpha_tilde;
    double              prepared_dt = 0;
  };

  /// One spring per tetrahedron edge (a, b) of @p mesh: k_e = stiffness(Σ_{T∋e} share(T,
  /// a, b), L_e), a and b the edge's local vertex indices in T (a < b), no spring where
  /// that is 0; the rules below and spring_identification.h are its uses. @p node maps
  /// mesh vertices to nodes.
  void
  add_tetrahedron_edge_springs(SpringSet &springs, const mesh::SimplexMesh &mesh,
                               const std::vector<std::uint32_t>                         &node,
                               const std::function<double(std::size_t, unsigned, unsigned)> &share,
                               const std::function<double(double, double)>                &stiffness);

  /// One spring per tetrahedron edge, k from Van Gelder's rule (above) with c = E:
  /// k_e = Σ_{T∋e} E_T V_T / L_e², so a tetrahedron contributes its own modulus to each
  /// of its edges (layers of different tissue share the edges on their interface).
  /// @p node maps mesh vertices to system nodes; @p youngs_modulus has one E (Pa) per
  /// tetrahedron.
  void
  add_volume_springs(SpringSet &springs, const mesh::SimplexMesh &mesh,
                     const std::vector<std::uint32_t> &node, const std::vector<double> &youngs_modulus);
  /// The same with one E for every tetrahedron.
  void
  add_volume_springs(SpringSet &springs, const mesh::SimplexMesh &mesh,
                     const std::vector<std::uint32_t> &node, double youngs_modulus);

  /// One spring per triangle edge of @p triangles (vertex indices of @p vertices), k
  /// from the linearised Delingette rule (above).
  void
  add_membrane_springs(SpringSet &springs, const Matrix3Xd &vertices,
                       const std::vector<mesh::Triangle> &triangles,
                       const std::vector<std::uint32_t> &node, double youngs_modulus,
                       double poisson_ratio, double thickness);
} // namespace suturesim::realtime
