#pragma once
/**
 * @file
 * The two-node Simo–Reissner (geometrically exact) rod element with one-point (reduced)
 * integration and the Crisfield–Jelenić interpolation of rotations.
 *
 * Nodes carry positions x₁, x₂ and rotations R₁, R₂ (unit quaternions; the first
 * director d₁ = R E₁ is the rod axis). Crisfield & Jelenić (1999, Proc. R. Soc. A
 * 455:1125) interpolate the rotation relative to a reference rotation R_r; for two nodes
 * and one integration point at the element centre this reduces to
 *   R_m = R₁ exp(ψ/2),   ψ = log(R₁ᵀR₂)   (the geodesic midpoint of R₁ and R₂),
 * and the material strain measures of Simo (1985) and Simo & Vu-Quoc (1986) at the centre
 * are
 *   Γ = R_mᵀ(x₂ − x₁)/L₀ − Γ₀   (extension and shear),
 *   K = ψ/L₀ − K₀               (twist and bending),
 * with Γ₀, K₀ the values of the stress-free initial configuration. Both depend only on
 * the current nodal rotations (path independence) and are unchanged by a superposed
 * rigid motion (objectivity), which is why this interpolation is used and not an
 * interpolation of incremental rotation vectors. One-point integration removes shear and
 * membrane locking of slender rods. The stored energy is
 *   W = L₀/2 (Γᵀ C_N Γ + Kᵀ C_M K),  C_N = diag(EA, GA₂, GA₃),  C_M = diag(GJ, EI₂, EI₃).
 *
 * Gradient and tangent are those of W at the current configuration with respect to
 * (Δx₁, θ₁, Δx₂, θ₂), where a node moves as x ← x + Δx, R ← exp(θ̂)R (spatial rotation
 * increments, the multiplicative update). The tangent is the exact Hessian of this
 * pull-back, so Newton converges quadratically; it is derived with the quaternion
 * midpoint q_m = (q₁ + q₂)/|q₁ + q₂| and ψ = F(|p|²)p (rotation.h), whose second-order
 * expansions are polynomial (derivation in rod_element.cc), and it is checked against
 * central finite differences in tests/unit/rod_element_test.cc.
 */

#include <suturesim/rod/rotation.h>

#include <Eigen/Core>

namespace suturesim::rod
{
  using Vec6  = Eigen::Matrix<double, 6, 1>;
  using Vec12 = Eigen::Matrix<double, 12, 1>;
  using Mat12 = Eigen::Matrix<double, 12, 12>;

  /// Diagonal section stiffnesses in the material frame (d₁ axial).
  struct SectionStiffness
  {
    Vec3 force  = Vec3::Ones();  ///< (EA, GA₂, GA₃), N
    Vec3 moment = Vec3::Ones();  ///< (GJ, EI₂, EI₃), N m²
  };

  /// What an element remembers of the stress-free configuration.
  struct ElementReference
  {
    double length = 1;              ///< L₀, m
    Vec3   gamma0 = Vec3::UnitX();  ///< R_mᵀ(x₂ − x₁)/L₀ at rest (E₁ for a straight rod)
    Vec3   kappa0 = Vec3::Zero();   ///< ψ/L₀ at rest, 1/m
  };

  /// Strains and stress resultants at the element centre (material frame) and the
  /// midpoint rotation.
  struct ElementState
  {
    Vec3 Gamma, K; ///< strains Γ (1) and K (1/m)
    Vec3 N, M;     ///< N = C_N Γ (N), M = C_M K (N m)
    Mat3 Rm;       ///< R_m
    double energy; ///< W, J
  };

  /// Strains, resultants and energy. Throws std::domain_error when the relative
  /// rotation of the two nodes reaches π (the element is too long for its curvature).
  ElementState
  element_state(const Vec3 &x1, const Quat &q1, const Vec3 &x2, const Quat &q2,
                const ElementReference &reference, const SectionStiffness &section);

  /// Energy gradient and consistent tangent (exact Hessian of the pull-back) with respect
  /// to (Δx₁, θ₁, Δx₂, θ₂); returns the state as element_state() does. With @p hessian
  /// null only the gradient is computed (residual evaluations).
  ElementState
  element_tangent(const Vec3 &x1, const Quat &q1, const Vec3 &x2, const Quat &q2,
                  const ElementReference &reference, const SectionStiffness &section,
                  Vec12 &gradient, Mat12 *hessian);

  /// The reference of a stress-free element in the configuration given.
  ElementReference
  make_reference(const Vec3 &x1, const Quat &q1, const Vec3 &x2, const Quat &q2);
} // namespace suturesim::rod
