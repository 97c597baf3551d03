#pragma once
/**
 * @file
 * Linear tetrahedral finite elements with the stable neo-Hookean energy, the realtime
 * tissue whose response converges to the continuum's under refinement (tissue model
 * "fe"), where a spring network's does not (docs/calibration.md).
 *
 * Per tetrahedron of rest volume V₀ and rest edge matrix D_m = [X₁ − X₀, X₂ − X₀,
 * X₃ − X₀], the deformation gradient F = Σᵢ xᵢ bᵢᵀ with b₁…b₃ the rows of D_m⁻¹ and
 * b₀ = −(b₁ + b₂ + b₃), and the energy
 *
 *   E = V₀ [ μ/2 (I_C − 3) + λ̂/2 (J − γ)² − λ̂/2 (1 − γ)² ],  I_C = tr FᵀF, J = det F,
 *   γ = 1 + μ/λ̂
 *
 * (Smith, de Goes & Kim 2018, "Stable neo-Hookean flesh simulation", ACM TOG 37:12,
 * without their log term, as Macklin & Müller 2021, "A constraint-based formulation of
 * stable neo-Hookean materials", MIG '21, use it): stress free at rest (γ balances the
 * μ I of the first term), finite and smooth through inversion (J ≤ 0). Linearised at
 * rest it is μ|ε|² + (λ̂ − μ)/2 (tr ε)², so λ̂ = λ + μ reproduces linear elasticity's
 * Lamé constants (μ, λ) exactly; the small-strain response is then that of the accurate
 * path's material of the same μ and K = λ + 2μ/3.
 *
 * Forces fᵢ = −V₀ P bᵢ with P = μ F + λ̂ (J − γ) cof F, for the force-based integrators,
 * and exact vertex blocks for vertex block descent ("vbd", Chen et al. 2024, whose
 * elements these are). No XPBD projection: Macklin & Müller's two constraints per
 * tetrahedron (C_D = √I_C, C_H = J − γ) carry the rest state's prestress μ V₀ in their
 * multipliers, so a sweep's linearisation moves nodes by amounts that cancel only when
 * converged; measured on the sag of tests/realtime/vbd_test.cc, one warm-started sweep
 * diverged and forty cold ones settled 2.3 % short of VBD's equilibrium, and a static
 * fixed point of the sweeps left the free nodes' force residual at the held nodes' (an
 * experiment of 2026-11-30, docs/calibration.md). A TetrahedralElements family: the
 * World refuses XPBD with it.
 */

#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/realtime/tetrahedron_nodes.h>

#include <array>
#include <vector>

namespace suturesim::realtime
{
  class NeoHookeanTetrahedra : public TetrahedralElements
  {
  public:
    std::string
    name() const override
    {
      return "neo-Hookean tetrahedra";
    }

    /// One element per tetrahedron of @p mesh (@p node maps mesh vertices to system
    /// nodes), with its Lamé constants of linear elasticity @p mu and @p lambda (Pa),
    /// one value per tetrahedron. Throws for a degenerate tetrahedron or μ ≤ 0, λ < 0.
    /// λ = 0 leaves the elements the shear response only, μ|ε|² at small strain, for a
    /// volumetric energy carried elsewhere (nodal_volumes.h).
    void
    add_mesh(const mesh::SimplexMesh &mesh, const std::vector<std::uint32_t> &node, const std::vector<double> &mu,
             const std::vector<double> &lambda);

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
    /// add_forces() of the listed elements, in their order.
    void
    add_forces_of(const Matrix3Xd &x, Matrix3Xd &f, const std::vector<std::uint32_t> &tetrahedra) const override;
    /// f = −V₀ P bᵢ, H = V₀ (μ |bᵢ|² I + λ̂ gᵢ gᵢᵀ), gᵢ = cof(F) bᵢ: exact, since J is
    /// linear in each vertex, and positive definite. Evaluated without F: F bᵢ =
    /// Σⱼ xⱼ (bⱼ · bᵢ) from the element's Gram matrix, and J = V/V₀, gᵢ = ∇ᵢV/V₀ from the
    /// current signed volume V and its gradient at the vertex (one cross product;
    /// six_vertex_volume_gradient()): about 80 operations an element where F and its
    /// cofactor took about 200.
    void
    add_vertex_block(const Matrix3Xd &x, std::uint32_t i, const std::uint32_t *tetrahedra, std::size_t n, Vector3d &f,
                     Eigen::Matrix3d &H) const override;
    /// max |J − 1|, the largest volumetric strain
    double
    max_violation(const Matrix3Xd &x) const override;

    /// F of tetrahedron @p t at @p x (for tests and output).
    Eigen::Matrix3d
    deformation_gradient(const Matrix3Xd &x, std::size_t t) const;

  private:
    /// f −= V₀ P bᵢ at the four nodes of element @p t.
    void
    add_element_forces(const Matrix3Xd &x, Matrix3Xd &f, std::size_t t) const;

    /// add_vertex_block()'s loop, multi-versioned (hot_kernel.h), into @p f and the
    /// upper triangle @p H (xx, xy, xz, yy, yz, zz).
    void
    vertex_block(const Matrix3Xd &x, std::uint32_t i, const std::uint32_t *tetrahedra, std::size_t n, double (&f)[3],
                 double (&H)[6]) const;

    struct Element : TetrahedronShape // b and V₀
    {
      double mu, lambda; ///< μ and λ̂ = λ + μ
      double gamma;      ///< γ = 1 + μ/λ̂
    };
    std::vector<Element> elements;
    /// what a vertex block reads of an element, together
    struct BlockElement
    {
      double volume, mu, lambda, gamma; ///< V₀ = |V₀|, μ, λ̂, γ as in Element
      double inverse_six_volume;        ///< 1/(6 V₀), V₀ signed
      double gram[4][4];                ///< bᵢ · bⱼ
    };
    std::vector<BlockElement> block_elements;
  };
} // namespace suturesim::realtime
