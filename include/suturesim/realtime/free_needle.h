#pragma once
/**
 * @file
 * The needle let go (seed 001 §5–6: "the needle can be released and regrasped"): a rigid
 * body moved by what the bodies exert on it — the pierce points and the touch on its arc,
 * the suture's pull at the swage — and by its weight m g at its centroid.
 *
 * It moves by the quasi-static integrator's law (seed 001 §2.2, V = F/B: no inertia,
 * velocity from the forces of the instant), as a body: the centroid c with drag B,
 * the rotation about c with drag B R² (R the arc radius). Each step is a backward-Euler
 * step with the Gauss–Newton stiffness K of the springs that hold it (each a point
 * spring k at r from c: K += k Jᵀ J, J = [I, −[r]×], the motion of its point):
 *   (D/dt + K) (Δc, Δθ) = (F, M_c),   D = diag(B I, B R² I),   Q ← exp(Δθ) Q,
 * with F the force and M_c the moment about c. Its rest state is the body's
 * equilibrium F = 0, M_c = 0, whatever B and K; only the way there depends on them.
 * A K at least the springs' true stiffness keeps it stable at any dt.
 *
 * Mass m = ρ π d²/4 R Φ and centroid X_c = R (sin Φ, 1 − cos Φ, 0)/Φ in the body frame
 * of tools/curved_needle.h (the arc's mean point).
 */

#include <suturesim/tools/curved_needle.h>

namespace suturesim::realtime
{
  using Matrix6d = Eigen::Matrix<double, 6, 6>;

  /// K += k Jᵀ J for a point spring of stiffness @p k (N/m) at @p r (m) from the centre
  /// of the rigid motion (δc, δθ): its point moves by J (δc, δθ), J = [I, −[r]×].
  void
  add_point_stiffness(Matrix6d &K, const Eigen::Vector3d &r, double k);

  class FreeNeedle
  {
  public:
    /// @p density ρ (kg/m³, > 0) of the wire, @p drag B (N s/m, > 0);
    /// std::invalid_argument otherwise.
    FreeNeedle(const tools::CurvedNeedle &needle, double density, double drag);

    /// The needle is let go at @p pose.
    void
    release(const tools::Pose &pose);
    const tools::Pose &
    pose() const
    {
      return current;
    }
    double
    mass() const
    {
      return m;
    }
    /// The centroid in world coordinates, m.
    Eigen::Vector3d
    centroid() const
    {
      return current.apply(body_centroid);
    }

    /// One step of length @p dt under force @p force and moment @p moment (about the
    /// pose's position, the arc centre) that the bodies exert, gravity @p gravity
    /// (m/s²) and the stiffness @p K of the holding springs about the centroid
    /// (add_point_stiffness).
    void
    step(const Eigen::Vector3d &force, const Eigen::Vector3d &moment, const Eigen::Vector3d &gravity,
         const Matrix6d &K, double dt);

    /// The resultant force of the last step's load and weight (N); it vanishes at rest.
    const Eigen::Vector3d &
    resultant_force() const
    {
      return last_force;
    }

  private:
    double   R, B, m;
    Eigen::Vector3d body_centroid;
    tools::Pose current;
    Eigen::Vector3d last_force = Eigen::Vector3d::Zero();
  };
} // namespace suturesim::realtime
