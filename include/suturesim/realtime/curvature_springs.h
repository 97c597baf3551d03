#pragma once
/**
 * @file
 * Bending of a chain of nodes (the XPBD rod's bending constraint, and its force form for
 * the force-based integrators): at interior node i the discrete curvature vector
 * b = x_{i−1} − 2x_i + x_{i+1}, energy ½ c |b|², c = EI/l³ for a straight rest shape of
 * segment length l. Why: a turning angle φ at a node over a segment length l is a
 * curvature φ/l, so the bending energy is ½ EI (φ/l)² l = ½ EI φ²/l, and |b| = 2l sin(φ/2)
 * ≈ lφ. The constraint is linear in the positions (gradients I, −2I, I), so XPBD's
 * projection is exact in one sweep per node and well conditioned at φ = 0, where an angle
 * constraint has no gradient. Compliance α = 1/c = l³/EI per component.
 */

#include <suturesim/realtime/system.h>

#include <vector>

namespace suturesim::realtime
{
  class CurvatureSprings : public Interaction
  {
  public:
    std::string
    name() const override
    {
      return "rod bending";
    }
    std::size_t
    size() const override
    {
      return centre.size();
    }

    /// Bending at node @p i between @p i − 1 and @p i + 1 (given explicitly: chains need
    /// not be contiguous), stiffness @p c = EI/l³ (N/m).
    void
    add(std::uint32_t previous, std::uint32_t i, std::uint32_t next, double c);

    double
    energy(const Matrix3Xd &x) const override;
    void
    add_forces(const Matrix3Xd &x, Matrix3Xd &f) const override;
    void
    add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, double dt) const override;
    void
    reset_multipliers() override;
    void
    project(Matrix3Xd &x, const VectorXd &w, double dt) override;
    /// max |b| / |x_{i+1} − x_{i−1}|: the sine-like deviation from straight
    double
    max_violation(const Matrix3Xd &x) const override;

  private:
    std::vector<std::uint32_t> before, centre, after;
    std::vector<double>        stiffness;
    Matrix3Xd                  lambda;
  };
} // namespace suturesim::realtime
