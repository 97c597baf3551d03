#include <suturesim/tissue/material.h>

#include <deal.II/base/parameter_handler.h>

#include <cmath>

namespace suturesim::tissue
{
  using dealii::outer_product;

  SymTensor4
  symmetric_product(const SymTensor2 &A)
  {
    SymTensor4 result;
    for (unsigned int a = 0; a < 3; ++a)
      for (unsigned int b = a; b < 3; ++b)
        for (unsigned int c = 0; c < 3; ++c)
          for (unsigned int d = c; d < 3; ++d)
            result[a][b][c][d] = 0.5 * (A[a][c] * A[b][d] + A[a][d] * A[b][c]);
    return result;
  }

  void
  Material::declare_parameters(dealii::ParameterHandler &prm)
  {
    const auto &models = IsochoricEnergy::Registry::instance();
    prm.declare_entry("Model",
                      "neo-Hookean",
                      dealii::Patterns::Selection(models.selection_pattern()),
                      "Isochoric strain energy. " + models.documentation());
    const auto &volumetric = VolumetricEnergy::Registry::instance();
    prm.declare_entry("Volumetric energy",
                      "simo-taylor-1991",
                      dealii::Patterns::Selection(volumetric.selection_pattern()),
                      "Volumetric strain energy Psi_vol(J) = kappa G(J). " +
                        volumetric.documentation());
    prm.declare_entry("Poisson ratio",
                      "0.45",
                      dealii::Patterns::Double(-1, 0.5),
                      "Poisson ratio nu of the linearised material; sets the bulk modulus "
                      "kappa = 2 mu (1 + nu) / (3 (1 - 2 nu)) unless 'Bulk modulus' is "
                      "given. Unit: 1. Range: (-1, 0.5).");
    prm.declare_entry("Bulk modulus",
                      "0",
                      dealii::Patterns::Double(0),
                      "Bulk modulus kappa; 0 derives it from the Poisson ratio. Unit: Pa. "
                      "Range: >= 0.");
    prm.declare_entry("Density",
                      "1100",
                      dealii::Patterns::Double(0),
                      "Mass density in the reference configuration (soft tissue about "
                      "1000-1200). Unit: kg/m^3. Range: >= 0.");
    for (const auto &[name, entry] : models.all())
      entry.declare_parameters(prm);
  }

  Material
  Material::parse_parameters(const dealii::ParameterHandler &prm,
                             const ParameterScope    &scope)
  {
    const std::string model = prm.get("Model");
    auto             &prm_mut = const_cast<dealii::ParameterHandler &>(prm);
    prm_mut.enter_subsection(model);
    std::shared_ptr<const IsochoricEnergy> isochoric;
    try
      {
        isochoric = IsochoricEnergy::Registry::instance().get(model).create(
          prm, scope.subsection(model));
      }
    catch (...)
      {
        prm_mut.leave_subsection();
        throw;
      }
    prm_mut.leave_subsection();

    const double nu = prm.get_double("Poisson ratio");
    scope.require(nu < 0.5,
                  "Poisson ratio",
                  "must be < 0.5 (nu = 0.5 is exactly incompressible; use e.g. 0.4999 with "
                  "the mixed formulation)");
    scope.require(nu > -1.0, "Poisson ratio", "must be > -1");
    double kappa = prm.get_double("Bulk modulus");
    if (kappa == 0.0)
      kappa = 2.0 * isochoric->shear_modulus() * (1.0 + nu) / (3.0 * (1.0 - 2.0 * nu));
    scope.require(kappa > 0, "Bulk modulus", "the bulk modulus must be > 0 Pa");
    return Material(isochoric, prm.get("Volumetric energy"), kappa, prm.get_double("Density"));
  }

  Material::Material(std::shared_ptr<const IsochoricEnergy> isochoric,
                     const std::string                     &volumetric_name,
                     const double                           kappa,
                     const double                           density)
    : isochoric(std::move(isochoric))
    , volumetric_energy(VolumetricEnergy::Registry::instance().get(volumetric_name).create(kappa))
    , kappa(kappa)
    , rho(density)
  {}

  namespace
  {
    /// Ī₁ and Ī₂ of C̄ = J^(-2/3) C.
    std::pair<double, double>
    invariants(const SymTensor2 &C_bar)
    {
      const double I1 = dealii::trace(C_bar);
      const double I2 = 0.5 * (I1 * I1 - dealii::scalar_product(C_bar, C_bar));
      return {I1, I2};
    }
  } // namespace

  double
  Material::isochoric_energy(const SymTensor2 &C) const
  {
    const double J       = std::sqrt(dealii::determinant(C));
    const auto [I1, I2] = invariants(std::pow(J, -2.0 / 3.0) * C);
    return isochoric->derivatives(I1, I2).psi;
  }

  double
  Material::energy(const SymTensor2 &C) const
  {
    return isochoric_energy(C) + volumetric_energy->energy(std::sqrt(dealii::determinant(C)));
  }

  void
  Material::isochoric_response(const SymTensor2 &C, SymTensor2 &S_iso, SymTensor4 &CC_iso) const
  {
    static const SymTensor2 I  = dealii::unit_symmetric_tensor<3>();
    static const SymTensor4 II = dealii::identity_tensor<3>();

    const double     J        = std::sqrt(dealii::determinant(C));
    const double     J_m23    = std::pow(J, -2.0 / 3.0);
    const SymTensor2 C_inv    = dealii::invert(C);
    const SymTensor2 C_bar    = J_m23 * C;
    const auto [I1, I2]      = invariants(C_bar);
    const auto       d        = isochoric->derivatives(I1, I2);

    const SymTensor2 S_bar = 2.0 * (d.d1 + I1 * d.d2) * I - 2.0 * d.d2 * C_bar;
    const double     S_bar_C_bar = S_bar * C_bar; // = J^(-2/3) S̄:C
    S_iso = J_m23 * (S_bar - (1.0 / 3.0) * (S_bar * C) * C_inv);

    const double d1 = 4.0 * (d.d11 + 2.0 * I1 * d.d12 + d.d2 + I1 * I1 * d.d22);
    const double d2 = -4.0 * (d.d12 + I1 * d.d22);
    const double d3 = 4.0 * d.d22;
    const double d4 = -4.0 * d.d2;

    const SymTensor4 P  = II - (1.0 / 3.0) * outer_product(C_inv, C);
    const SymTensor4 PT = II - (1.0 / 3.0) * outer_product(C, C_inv);
    const SymTensor4 P_tilde =
      symmetric_product(C_inv) - (1.0 / 3.0) * outer_product(C_inv, C_inv);

    CC_iso = (2.0 / 3.0) * S_bar_C_bar * P_tilde -
             (2.0 / 3.0) * (outer_product(C_inv, S_iso) + outer_product(S_iso, C_inv));
    // ℂ̄ vanishes for neo-Hookean and Mooney–Rivlin only in part (δ₄ ≠ 0 for C01 ≠ 0);
    // skip the two 6×6×6 products when it is exactly zero.
    if (d1 != 0 || d2 != 0 || d3 != 0 || d4 != 0)
      {
        const SymTensor4 CC_bar = d1 * outer_product(I, I) +
                                  d2 * (outer_product(I, C_bar) + outer_product(C_bar, I)) +
                                  d3 * outer_product(C_bar, C_bar) + d4 * II;
        CC_iso += (J_m23 * J_m23) * (P * CC_bar * PT);
      }
  }

  void
  Material::response(const SymTensor2 &C, SymTensor2 &S, SymTensor4 &CC) const
  {
    isochoric_response(C, S, CC);
    const double     J     = std::sqrt(dealii::determinant(C));
    const double     p     = volumetric_energy->pressure(J);
    const double     dp    = volumetric_energy->pressure_derivative(J);
    const SymTensor2 C_inv = dealii::invert(C);
    S += p * J * C_inv;
    CC += (p * J + J * J * dp) * outer_product(C_inv, C_inv) -
          2.0 * p * J * symmetric_product(C_inv);
  }

  SymTensor2
  Material::cauchy_stress(const Tensor2 &F, const double pressure) const
  {
    const SymTensor2 C = dealii::symmetrize(dealii::transpose(F) * F);
    SymTensor2       S;
    SymTensor4       CC;
    isochoric_response(C, S, CC);
    const double J = dealii::determinant(F);
    S += pressure * J * dealii::invert(C);
    return dealii::symmetrize(F * static_cast<Tensor2>(S) * dealii::transpose(F)) / J;
  }
} // namespace suturesim::tissue
