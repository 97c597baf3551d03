#pragma once
/**
 * @file
 * Isochoric strain energies Ψ_iso(Ī₁, Ī₂) of decoupled hyperelastic materials
 * (Holzapfel, Nonlinear Solid Mechanics, 2000, §6.4): Ψ = Ψ_iso(C̄) + Ψ_vol(J) with
 * C̄ = J^(-2/3) C, Ī₁ = tr C̄, Ī₂ = ½[(tr C̄)² − tr C̄²].
 *
 * A model supplies Ψ_iso and its first and second derivatives with respect to the two
 * invariants; Material turns them into stress and the consistent tangent. Models
 * register themselves (one source file each) through IsochoricEnergy::Registry.
 */

#include <suturesim/core/registry.h>
#include <suturesim/core/parameter_file.h>

#include <memory>

namespace suturesim::tissue
{
  class IsochoricEnergy
  {
  public:
    /// Ψ and ∂Ψ/∂Ī₁, ∂Ψ/∂Ī₂, ∂²Ψ/∂Ī₁², ∂²Ψ/∂Ī₁∂Ī₂, ∂²Ψ/∂Ī₂² (Pa).
    struct Derivatives
    {
      double psi = 0, d1 = 0, d2 = 0, d11 = 0, d12 = 0, d22 = 0;
    };

    /// Created from the model's own subsection; checks fail through the scope.
    using Registry = suturesim::Registry<IsochoricEnergy,
                                         const dealii::ParameterHandler &,
                                         const ParameterScope &>;

    virtual ~IsochoricEnergy() = default;

    /// Shear modulus of the linearised model, μ₀ (Pa).
    virtual double
    shear_modulus() const = 0;

    virtual Derivatives
    derivatives(double I1bar, double I2bar) const = 0;
  };
} // namespace suturesim::tissue
