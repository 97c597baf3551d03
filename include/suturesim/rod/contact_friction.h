#pragma once
/**
 * @file
 * Friction of the rod against itself: Coulomb's law with an elastic stick and history
 * (core/coulomb_law.h, the law of the pierce points), isotropic in the tangent plane of
 * each self-contact (self_contact.h), acting where the strands touch: at their surfaces,
 * a radius r from each centreline, so that it loads the cross-sections' rotations as well
 * as the centrelines (contact of beam surfaces: Durville 2012, Comput. Mech. 49:687–707).
 *
 * A contact between segments a and b has its closest points p, q, the normal n = (p −
 * q)/|p − q| and the touching surface points p − r n of a and q + r n of b. When a state
 * is accepted (commit()) each contact is anchored to those material surface points: its
 * segment, the weight s or t along it, and the surface direction in the material frame of
 * each of the segment's nodes, ν = Rᵀ(∓n). In a later configuration the anchored points
 * are
 *   P_a = Σ_k w_k (x_k + r R_k ν_k)   over a's two nodes (weights 1 − s, s),
 * and P_b likewise, and the elastic slip is
 *   d = (I − n_c n_cᵀ)(P_a − P_b) + g,
 * with n_c the normal and g the elastic slip (tangential) at the anchoring. The normal
 * part of P_a − P_b, a change of the penetration, is the penalty's and left out. With
 * N = −φ'(g) the current normal force and c = μ N:
 *   stick  k_t |d| ≤ c:  f = k_t d,      stored energy ½ k_t |d|²;
 *   slip   k_t |d| > c:  f = c d/|d|,    c |d| − c²/(2 k_t);
 * f acts on a at P_a and −f on b at P_b: the residual is J_dᵀ f, J_d = ∂d/∂(x, θ) of the
 * anchored elements' nodes (a force and the moment r R ν × f at each node). Its Jacobian
 * is exact: the turn of R ν under a rotation increment θ (δ(Rν) = θ × Rν), in slip the
 * turn of d/|d| and μ d/|d| ⊗ ∂N/∂x (∂N/∂x through the closest points and their
 * sensitivity du/dx, from ∂(BᵀΔ)/∂x + BᵀB du/dx = 0, B = ∂Δ/∂u).
 *
 * Why the surfaces, not the centrelines: centreline points cannot tell a strand sliding
 * round another from the two turning together about it (a strand's turn about its own
 * axis moves no centreline point); the surface points can. And the lever matters when
 * strands wrap each other: round a strand of the thread's own radius, friction at the
 * surface (lever r about the strand's axis) against tension at the centreline (lever
 * 2r) gives T₂/T₁ = e^{μθ/2} for a thread of negligible bending stiffness (the thick
 * belt's capstan, dT (R + r) = μ T dθ R with R = r), where a thin thread on a thick
 * cylinder gives Euler–Eytelwein's e^{μθ}
 * (RodFriction.AThreadSlippingRoundAStrandHoldsTheThickCapstanRatio).
 *
 * History: re-anchored at every commit, so Newton iterations and cut-backs see the
 * anchors of the last converged state, and the anchors stay where the contact is. A
 * contact takes the committed anchor nearest to it in rest arc length (σ_a, σ_b) within
 * R = 2 h_max + 4 r (h_max the longest element); without one it carries no friction
 * until the next commit anchors it. A slipping contact's g after the commit is the
 * return-mapped c/k_t d/|d|. The normal n_c is frozen within a step, so a pair turning
 * by φ within one step reads a slip of order |g| φ: negligible against the slip of a
 * sliding step (|g| ≤ c/k_t).
 */

#include <suturesim/rod/self_contact.h>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <vector>

namespace suturesim::rod
{
  /// The friction of one contact: its elastic slip, force and, when asked for, the
  /// residual and Jacobian on its eight node slots (6 components each: the anchors'
  /// nodes on a, 2, and on b, 2; then the contact's segments a and b, 4, whose positions
  /// set the normal force; a node may fill several slots).
  struct FrictionTerm
  {
    bool                          anchored = false; ///< a committed anchor matched
    bool                          slipping = false;
    Vec3                          slip     = Vec3::Zero(); ///< d, m
    double                        force    = 0;            ///< |f|, N
    double                        capacity = 0;            ///< μ N, N
    double                        energy   = 0;            ///< J
    double                        sigma_a = 0, sigma_b = 0; ///< the contact's σ, m
    std::array<std::uint32_t, 8>  node{};
    Eigen::Matrix<double, 48, 1>  residual = Eigen::Matrix<double, 48, 1>::Zero();
    Eigen::Matrix<double, 48, 48> jacobian = Eigen::Matrix<double, 48, 48>::Zero();
  };

  /// A contact's anchor: on each strand the segment, the weight of its second node, the
  /// surface direction in each node's material frame; the normal and elastic slip then.
  struct FrictionAnchor
  {
    std::uint32_t       a = 0, b = 0;
    double              s = 0, t = 0;
    double              sigma_a = 0, sigma_b = 0; ///< rest arc length, m (for matching)
    std::array<Vec3, 2> nu_a, nu_b;               ///< material unit vectors
    Vec3                normal = Vec3::UnitZ();   ///< n_c
    Vec3                slip   = Vec3::Zero();    ///< g, m

    /// 20 numbers (a checkpoint's record) and back; InputError-free: the caller checks
    /// the count.
    void
    write(std::vector<double> &out) const;
    static FrictionAnchor
    read(const double *in);
    static constexpr std::size_t size = 20;
  };

  class ContactFriction
  {
  public:
    /// μ and k_t from @p parameters, rest arc length at the nodes @p arc (m).
    void
    setup(const ContactParameters &parameters, const std::vector<double> &arc);

    /// true when μ > 0 (otherwise the contacts are frictionless and nothing is computed).
    bool
    active() const
    {
      return mu > 0;
    }

    /// The friction of contact @p c in configuration (@p x, @p q) (the Jacobian only
    /// when @p with_jacobian), with the committed anchors.
    FrictionTerm
    evaluate(const ContactPair &c, const std::vector<Vec3> &x, const std::vector<Quat> &q,
             bool with_jacobian) const;

    /// Accepts the state (@p x, @p q) with the contacts @p pairs found in it: each
    /// contact is anchored where it is, with its return-mapped elastic slip.
    void
    commit(const std::vector<ContactPair> &pairs, const std::vector<Vec3> &x, const std::vector<Quat> &q);

    /// The committed anchors.
    const std::vector<FrictionAnchor> &
    anchors() const
    {
      return history;
    }

    /// Replaces the history (a checkpoint's, or a test's).
    void
    set_anchors(std::vector<FrictionAnchor> a)
    {
      history = std::move(a);
    }

  private:
    double                      mu = 0, stiffness = 0, radius = 0, match = 0;
    std::vector<double>         arc;
    std::vector<FrictionAnchor> history;
  };
} // namespace suturesim::rod
