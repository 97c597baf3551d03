#pragma once
/**
 * @file
 * Stick–slip friction between a pierce point and the thread it sits on (needle, then
 * suture), shared by both model paths: Coulomb's law f = μ N (seed 000 eq. 2), made
 * well-posed by an elastic stick with stiffness k_t and a slip rule by return mapping
 * (the penalty regularisation of Coulomb friction used in FE contact: Wriggers 2006,
 * "Computational Contact Mechanics", §5.2; Laursen 2002, §4).
 *
 * One dimension, along the thread: ζ is where the tissue point now projects on the
 * thread (thread coordinate, m: tools/curved_needle.h), ζ_a the anchor where it sticks.
 * The tangential force on the tissue point, along the thread tangent, is
 *   trial  f = −k_t (ζ − ζ_a);
 *   stick  |f| ≤ μ N: f as tried, anchor kept;
 *   slip   |f| > μ N: f = −μ N sign(ζ − ζ_a), anchor moved to ζ − sign(ζ − ζ_a) μ N / k_t,
 * so that k_t |ζ − ζ_a| = μ N after the step. μ = 0 slides freely (f = 0); k_t → ∞ is
 * rigid-plastic Coulomb. The anchor is history: it is updated only when a step is
 * accepted (commit()), so Newton iterations and cut-backs of a step see the anchor of
 * the last converged state.
 *
 * Normal force: the pressure of the hole on the thread. At a pierce point the thread
 * pulls with tensions T₁, T₂ on either side; the tissue balances their transverse
 * resultant, which for a wrap angle θ (the angle between the two directions) is
 * 2 T sin(θ/2) at T₁ = T₂ = T (the discrete capstan relation; Euler–Eytelwein), and
 * that is what the transverse coupling force carries. The hole also grips a straight
 * thread: N = N₀ + |f_⊥|, with the grip N₀ a parameter (N).
 */

#include <suturesim/core/model_parameters.h>

#include <algorithm>
#include <cmath>

namespace suturesim::coupling
{
  /// The law's parameters, declared and parsed by the law (the scene's "Pierce points"
  /// subsection, both model paths). Defaults: μ = 0.2 within the 0.1–0.3 measured for
  /// monofilament sutures in soft tissue (references.md); k_t = 500 N/m, N₀ = 0.05 N.
  struct FrictionParameters
  {
    double mu        = 0.2;  ///< Coulomb coefficient, 1
    double stiffness = 500;  ///< k_t of the elastic stick, N/m
    double grip      = 0.05; ///< N₀, normal force of the hole on a straight thread, N

    /// "Friction coefficient", "Stick stiffness", "Grip", with these defaults.
    static void
    declare(ParameterDeclarations &declarations);
    /// The values of declare()'s entries; ParameterError for a bad one.
    static FrictionParameters
    parse(const ParameterValues &values);
  };

  /// Coulomb's limit μ N of the tangential force for a normal force @p normal (N; a
  /// negative one, a hole that does not press, carries none): the one place the limit
  /// is computed, in both paths and every pierce model.
  inline double
  friction_limit(const FrictionParameters &p, const double normal)
  {
    return p.mu * std::max(normal, 0.0);
  }

  struct FrictionResult
  {
    double force      = 0;     ///< f along the tangent on the tissue point, N
    double derivative = 0;     ///< ∂f/∂ζ at fixed N (−k_t in stick, 0 in slip), N/m
    double anchor     = 0;     ///< ζ_a after this evaluation, m
    double capacity   = 0;     ///< μ N, N
    bool   slipping   = false;
  };

  /// One branch of the law: stick, or slip in the direction sign(ζ − ζ_a) = @p sign.
  struct FrictionBranch
  {
    bool   slipping = false;
    double sign     = 1;

    /// Relative distance below the capacity μ N within which a stick counts as slip
    /// (of()): well above the round-off (≈ 1e-16 relative) that picks a branch on the
    /// kink, well below any stick force a Newton step resolves.
    static constexpr double at_capacity_within = 1e-9;

    /// The branch of @p r at gap ζ − ζ_a = @p gap for a Newton tangent: the return
    /// mapping's, except that a stick within at_capacity_within of the capacity counts as
    /// slip. A slipping step returns the anchor to exactly k_t |ζ − ζ_a| = μ N, so the
    /// next step starts on the kink, where round-off would pick the branch: a restart,
    /// whose rotations were then normalised again in their last bit, took another Newton
    /// path from the same state (Restart.AnAccurateNeedlePassStoppedMidRun…, 5 against
    /// 7 suture iterations in one step). Both branches carry μ N there.
    static FrictionBranch
    of(const FrictionResult &r, const double gap)
    {
      const bool at_capacity =
        r.capacity > 0 && std::abs(r.force) >= (1 - at_capacity_within) * r.capacity;
      return {r.slipping || at_capacity, gap >= 0 ? 1.0 : -1.0};
    }
  };

  /// The return mapping at thread coordinate @p zeta, anchor @p anchor (last converged)
  /// and normal force @p normal (N ≥ 0).
  ///
  /// With @p branch, the law is evaluated on that branch whatever |trial| is: stick
  /// f = −k_t (ζ − ζ_a), or slip f = −sign μ N. Finite-difference tangents take it from
  /// their base state. Differences across the kink |trial| = μ N would average the
  /// slopes of both branches (−k_t and 0), and that average is not a derivative of the
  /// law on either side. A one-sided difference on the base state's branch is an element
  /// of the law's generalised (Clarke) Jacobian, the tangent of a semismooth Newton
  /// method (Qi & Sun 1993; for frictional contact: Alart & Curnier 1991).
  FrictionResult
  coulomb_friction(const FrictionParameters &p, double zeta, double anchor, double normal,
                   const FrictionBranch *branch = nullptr);

  struct NormalForce
  {
    double value = 0; ///< N, N
    double rate  = 0; ///< ∂N/∂|f⊥|, 1
  };

  /// N = N₀ + s(|f⊥|) for a transverse tie force of magnitude @p tie (N). With
  /// @p smoothing ε = 0, s(f) = f. With ε > 0, s(f) = f²/√(f² + ε²). This is smooth at
  /// f = 0, where |f⊥| has a kink. A Newton iteration on a thread that runs straight
  /// through the hole (f⊥ → 0, its direction flipping between iterations) otherwise
  /// cycles. s(f) = f − ε²/(2f) + … for f ≫ ε, and 0 ≤ f − s(f) ≤ 0.3003 ε (at f = 0.786 ε).
  NormalForce
  normal_force(double grip, double tie, double smoothing);
} // namespace suturesim::coupling
