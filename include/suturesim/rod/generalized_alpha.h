#pragma once
/**
 * @file
 * Implicit rod dynamics by the Lie-group generalized-α method (Brüls & Cardona 2010,
 * J. Comput. Nonlinear Dyn. 5:031002; Arnold & Brüls 2007, Multibody Syst. Dyn. 18:185)
 * with the Chung–Hulbert (1993) parameters of a chosen spectral radius ρ∞:
 *   α_m = (2ρ∞ − 1)/(ρ∞ + 1), α_f = ρ∞/(ρ∞ + 1), γ = ½ + α_f − α_m, β = ¼(γ + ½)².
 * Per node the unknowns are x and R; velocities are ẋ (spatial) and W (material angular
 * velocity). With Ψ the increment over the step (x − xₙ for translations,
 * log(Rₙᵀ R) for rotations):
 *   Ψ = h vₙ + h²(½ − β) aₙ + h²β aₙ₊₁,   vₙ₊₁ = vₙ + h(1 − γ) aₙ + hγ aₙ₊₁,
 *   (1 − α_m) aₙ₊₁ + α_m aₙ = (1 − α_f) v̇ₙ₊₁ + α_f v̇ₙ,
 * and the equations of motion hold at tₙ₊₁:
 *   m ẍ + c m ẋ + r_x = 0,   R (J Ẇ + W × J W + c J W) + r_θ = 0,
 * with r the rod's elastic-minus-external residual (rod_model.h), m and J the lumped
 * nodal mass and material rotational inertia, c mass-proportional damping. The Newton
 * Jacobian of the inertia terms is exact, including the derivative of log through
 * J_r(Ψ)⁻¹. ρ∞ = 1 gives the trapezoidal rule (no numerical dissipation); ρ∞ < 1 damps
 * the highest frequencies (the stiff shear and torsion modes a suture does not need
 * resolved) while staying second-order accurate.
 */

#include <suturesim/rod/rod_model.h>

#include <vector>

namespace suturesim::rod
{
  class GeneralizedAlpha
  {
  public:
    GeneralizedAlpha(RodModel &model, double spectral_radius, double damping);

    /// Sets nodal velocities (spatial) and material angular velocities at the current
    /// state and computes the consistent initial accelerations (constrained components
    /// get zero).
    void
    initialize(const std::vector<Vec3> &velocity, const std::vector<Vec3> &omega);

    /// Advances by @p h. The caller sets loads and prescribed motion of tₙ₊₁ on the
    /// model before (prescribed nodes are not predicted). On failure the model is
    /// restored to tₙ.
    NewtonResult
    step(double h, const NewtonParameters &newton, const std::vector<std::size_t> &prescribed = {});

    const std::vector<Vec3> &
    velocities() const
    {
      return v;
    }
    const std::vector<Vec3> &
    angular_velocities() const
    {
      return W;
    }

    /// The residual with inertia at the end of the last step (reactions of supports).
    const Eigen::VectorXd &
    last_residual() const
    {
      return residual;
    }

    /// The inertia terms of a step of size h from the stored state tₙ.
    NodalTerms
    inertia_terms(double h);

  private:
    /// Pseudo-acceleration, velocity and acceleration of node i at the end of a step of
    /// size h that ends in (x, q): the generalized-α relations above, for translations
    /// (spatial) and rotations (material, Ψ = log(qₙ* q)).
    struct NodeKinematics
    {
      Vec3 a_x, v, acc_x, psi, a_w, W, acc_w;
    };
    NodeKinematics
    kinematics(std::size_t i, const Vec3 &x, const Quat &q, double h) const;

    RodModel &model;
    double    alpha_m, alpha_f, gamma, beta, c;
    // state at tₙ: configuration, velocities, pseudo-accelerations a, accelerations v̇
    std::vector<Vec3> x0;
    std::vector<Quat> q0;
    std::vector<Vec3> v, W, a_x, a_w, acc_x, acc_w;
    Eigen::VectorXd   residual;
  };
} // namespace suturesim::rod
