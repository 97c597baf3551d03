#pragma once
/**
 * @file
 * Angular ("bending", "torsional") springs on pairs of edges that meet at a vertex: seed
 * 003 adds them at pierced vertices so that "the adjacent edges in small triangles" no
 * longer "bend to any angle if their common node is dragged by needle or suture"; the
 * spring is "configured on two connected springs as a pair". For edges (v, a) and (v, b)
 * with angle θ = ∠(a − v, b − v) and rest angle θ₀: energy ½ k (θ − θ₀)², k in N m/rad²;
 * under XPBD the constraint C = θ − θ₀ with compliance 1/k. With e₁ = a − v, e₂ = b − v,
 * ∂θ/∂a = −(ê₂ − cos θ ê₁)/(|e₁| sin θ), ∂θ/∂b likewise, ∂θ/∂v = −(∂θ/∂a + ∂θ/∂b);
 * straight (θ = 0 or π) angles have no unique gradient and are skipped.
 */

#include <suturesim/realtime/system.h>

#include <array>
#include <vector>

namespace suturesim::realtime
{
  class AngleSprings : public Interaction
  {
  public:
    std::string
    name() const override
    {
      return "bending springs";
    }
    std::size_t
    size() const override
    {
      return vertex.size();
    }

    /// An angular spring at vertex @p v between edges to @p a and @p b, rest angle from
    /// @p x, stiffness @p k (N m/rad²).
    void
    add(std::uint32_t v, std::uint32_t a, std::uint32_t b, const Matrix3Xd &x, double k);

    double
    energy(const Matrix3Xd &x) const override;
    void
    add_forces(const Matrix3Xd &x, Matrix3Xd &f) const override;
    void
    add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, double dt) const override;
    void
    reset_multipliers() override;
    void
    warm_multipliers(const VectorXd &w, double scale) override;
    void
    project(Matrix3Xd &x, const VectorXd &w, double dt) override;
    /// max |θ − θ₀| (rad)
    double
    max_violation(const Matrix3Xd &x) const override;

  private:
    /// θ and its gradients with respect to a, b (that of v is minus their sum); false
    /// where the angle is straight or an edge has zero length.
    bool
    angle(const Matrix3Xd &x, std::size_t s, double &theta, Vector3d &ga, Vector3d &gb) const;

    std::vector<std::uint32_t> vertex, end_a, end_b;
    std::vector<double>        rest, stiffness, lambda;
  };
} // namespace suturesim::realtime
