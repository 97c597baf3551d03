#pragma once
/**
 * @file
 * A decoupled hyperelastic material Ψ(C) = Ψ_iso(C̄) + Ψ_vol(J) evaluated in the
 * reference configuration (Total Lagrangian): second Piola–Kirchhoff stress S = 2∂Ψ/∂C
 * and the material tangent ℂ = 4∂²Ψ/∂C∂C.
 *
 * Isochoric part (Holzapfel 2000, eqs. 6.90, 6.168, 6.193–6.196):
 *   S̄ = 2(ψ₁ + Ī₁ψ₂) I − 2ψ₂ C̄,       S_iso = J^(-2/3) Dev S̄,  Dev(·) = (·) − ⅓[(·):C] C⁻¹,
 *   ℂ̄ = δ₁ I⊗I + δ₂(I⊗C̄ + C̄⊗I) + δ₃ C̄⊗C̄ + δ₄ 𝕀,
 *     δ₁ = 4(ψ₁₁ + 2Ī₁ψ₁₂ + ψ₂ + Ī₁²ψ₂₂), δ₂ = −4(ψ₁₂ + Ī₁ψ₂₂), δ₃ = 4ψ₂₂, δ₄ = −4ψ₂,
 *   ℂ_iso = ℙ:(J^(-4/3) ℂ̄):ℙᵀ + ⅔(S̄:C̄) ℙ̃ − ⅔(C⁻¹⊗S_iso + S_iso⊗C⁻¹),
 *     ℙ = 𝕀 − ⅓ C⁻¹⊗C,  ℙ̃ = C⁻¹⊙C⁻¹ − ⅓ C⁻¹⊗C⁻¹.
 * Volumetric part at a given pressure p (the mixed formulation passes its own p̃):
 *   S_p = pJ C⁻¹,   ℂ_p = pJ (C⁻¹⊗C⁻¹ − 2 C⁻¹⊙C⁻¹),
 * and for the pure displacement form p = Ψ'_vol(J) adds J²Ψ''_vol C⁻¹⊗C⁻¹ (eq. 6.166).
 *
 * Tested against closed forms (uniaxial stress, simple shear) and central finite
 * differences in tests/unit/material_test.cc.
 */

#include <suturesim/tissue/isochoric_energy.h>
#include <suturesim/tissue/volumetric_energy.h>

#include <deal.II/base/symmetric_tensor.h>
#include <deal.II/base/tensor.h>

#include <memory>
#include <string>

namespace suturesim::tissue
{
  using SymTensor2 = dealii::SymmetricTensor<2, 3>;
  using SymTensor4 = dealii::SymmetricTensor<4, 3>;
  using Tensor2    = dealii::Tensor<2, 3>;

  class Material
  {
  public:
    /// Declares "Model", "Volumetric energy", "Poisson ratio", "Bulk modulus", "Density"
    /// and every registered model's subsection into the current subsection.
    static void
    declare_parameters(dealii::ParameterHandler &prm);

    /// Builds the material from the current subsection (the one declared into).
    static Material
    parse_parameters(const dealii::ParameterHandler &prm, const ParameterScope &scope);

    /// @p kappa the bulk modulus (Pa), @p density in kg/m³.
    Material(std::shared_ptr<const IsochoricEnergy> isochoric,
             const std::string                     &volumetric_name,
             double                                 kappa,
             double                                 density);

    /// Strain energy per reference volume Ψ(C) (Pa).
    double
    energy(const SymTensor2 &C) const;

    /// Isochoric energy Ψ_iso(C̄) (Pa).
    double
    isochoric_energy(const SymTensor2 &C) const;

    /// S_iso and ℂ_iso for right Cauchy–Green tensor C.
    void
    isochoric_response(const SymTensor2 &C, SymTensor2 &S_iso, SymTensor4 &CC_iso) const;

    /// Full compressible response (pure displacement form): S and ℂ.
    void
    response(const SymTensor2 &C, SymTensor2 &S, SymTensor4 &CC) const;

    /// Cauchy stress σ = J⁻¹ F S Fᵀ with S = S_iso + pJ C⁻¹ at the given pressure p.
    SymTensor2
    cauchy_stress(const Tensor2 &F, double pressure) const;

    const VolumetricEnergy &
    volumetric() const
    {
      return *volumetric_energy;
    }

    double
    shear_modulus() const
    {
      return isochoric->shear_modulus();
    }

    double
    bulk_modulus() const
    {
      return kappa;
    }

    double
    density() const
    {
      return rho;
    }

  private:
    std::shared_ptr<const IsochoricEnergy>  isochoric;
    std::shared_ptr<const VolumetricEnergy> volumetric_energy;
    double                                  kappa;
    double                                  rho;
  };

  /// C⁻¹⊙C⁻¹ with (A⊙A)_ABCD = ½(A_AC A_BD + A_AD A_BC).
  SymTensor4
  symmetric_product(const SymTensor2 &A);
} // namespace suturesim::tissue
