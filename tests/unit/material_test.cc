// Constitutive verification (conventions.md §6): stresses against closed forms for
// uniaxial stress and simple shear, and S, ℂ against central finite differences of Ψ.
#include <suturesim/core/error.h>
#include <suturesim/tissue/material.h>

#include <deal.II/base/parameter_handler.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

using namespace suturesim;
using namespace suturesim::tissue;

namespace
{
  struct Case
  {
    std::string model;
    double      c10, c01; // neo-Hookean: c10 = mu/2, c01 = 0
    std::string volumetric;
    double      nu;
  };

  Material
  make(const Case &c)
  {
    dealii::ParameterHandler prm;
    Material::declare_parameters(prm);
    std::string text = "set Model = " + c.model + "\nset Volumetric energy = " + c.volumetric +
                       "\nset Poisson ratio = " + std::to_string(c.nu) + "\n";
    if (c.model == "neo-Hookean")
      text += "subsection neo-Hookean\n set Shear modulus = " + std::to_string(2 * c.c10) +
              "\nend\n";
    else
      text += "subsection Mooney-Rivlin\n set C10 = " + std::to_string(c.c10) +
              "\n set C01 = " + std::to_string(c.c01) + "\nend\n";
    ParameterFile file(prm, text, "material_test.prm", ".");
    return Material::parse_parameters(prm, ParameterScope(file, ""));
  }

  const std::vector<Case> cases = {
    {"neo-Hookean", 211.25e3, 0.0, "simo-taylor-1991", 0.3},
    {"neo-Hookean", 1.11e6, 0.0, "quadratic", 0.45},
    {"Mooney-Rivlin", 0.8e6, 0.2e6, "simo-taylor-1991", 0.49},
    {"Mooney-Rivlin", 0.5e6, 0.3e6, "logarithmic", 0.3},
  };

  /// Closed-form Cauchy stress of Ψ_iso = C10(Ī1−3) + C01(Ī2−3) (Rivlin; Holzapfel 2000
  /// eq. 6.110 specialised): σ = (2/J) dev[(C10 + C01 Ī1) b̄ − C01 b̄²] + p I, for diagonal
  /// b = diag(λ1², λ2², λ3²). Returns σ_ii.
  std::array<double, 3>
  principal_cauchy(const Case &c, const Material &m, const std::array<double, 3> &lambda)
  {
    const double J = lambda[0] * lambda[1] * lambda[2];
    std::array<double, 3> bb, A;
    double I1 = 0;
    for (int i = 0; i < 3; ++i)
      {
        bb[i] = std::pow(J, -2.0 / 3.0) * lambda[i] * lambda[i];
        I1 += bb[i];
      }
    double trA = 0;
    for (int i = 0; i < 3; ++i)
      {
        A[i] = (c.c10 + c.c01 * I1) * bb[i] - c.c01 * bb[i] * bb[i];
        trA += A[i];
      }
    const double p = m.volumetric().pressure(J);
    return {{2 / J * (A[0] - trA / 3) + p, 2 / J * (A[1] - trA / 3) + p,
             2 / J * (A[2] - trA / 3) + p}};
  }
} // namespace

TEST(Material, UniaxialStressClosedForm)
{
  for (const auto &c : cases)
    {
      const Material m = make(c);
      for (const double lambda : {0.7, 1.05, 1.4})
        {
          // Lateral stretch β from σ22 = 0, by bisection on the closed form alone.
          double lo = 0.3, hi = 2.0;
          for (int it = 0; it < 200; ++it)
            {
              const double mid = 0.5 * (lo + hi);
              const double s22 = principal_cauchy(c, m, {{lambda, mid, mid}})[1];
              // σ22 grows with β: too large β means σ22 > 0.
              (s22 > 0 ? hi : lo) = mid;
            }
          const double beta     = 0.5 * (lo + hi);
          const auto   expected = principal_cauchy(c, m, {{lambda, beta, beta}});

          Tensor2 F;
          F[0][0] = lambda;
          F[1][1] = F[2][2] = beta;
          const SymTensor2 sigma = m.cauchy_stress(F, m.volumetric().pressure(lambda * beta * beta));
          const double scale = std::abs(expected[0]);
          EXPECT_NEAR(sigma[0][0], expected[0], 1e-10 * scale) << c.model << " λ=" << lambda;
          EXPECT_NEAR(sigma[1][1], 0.0, 1e-8 * scale) << c.model << " λ=" << lambda;
          EXPECT_NEAR(sigma[2][2], 0.0, 1e-8 * scale) << c.model << " λ=" << lambda;
          EXPECT_NEAR(sigma[0][1], 0.0, 1e-12 * scale);
        }
    }
}

TEST(Material, SimpleShearClosedForm)
{
  for (const auto &c : cases)
    {
      const Material m = make(c);
      for (const double gamma : {0.1, 0.5, 1.0})
        {
          Tensor2 F = dealii::unit_symmetric_tensor<3>();
          F[0][1]   = gamma;
          const SymTensor2 sigma = m.cauchy_stress(F, m.volumetric().pressure(1.0));
          const double     mu    = 2 * (c.c10 + c.c01);
          // Rivlin's universal results for J = 1: σ12 = μγ, N1 = σ11 − σ22 = μγ²,
          // N2 = σ22 − σ33 = −2 C01 γ².
          EXPECT_NEAR(sigma[0][1], mu * gamma, 1e-10 * mu);
          EXPECT_NEAR(sigma[0][0] - sigma[1][1], mu * gamma * gamma, 1e-10 * mu);
          EXPECT_NEAR(sigma[1][1] - sigma[2][2], -2 * c.c01 * gamma * gamma, 1e-10 * mu);
          EXPECT_NEAR(sigma[0][2], 0.0, 1e-12 * mu);
        }
    }
}

namespace
{
  /// A general (non-symmetric, finite-strain) deformation gradient.
  Tensor2
  sample_F(const double scale)
  {
    Tensor2 F;
    const double v[3][3] = {{1.12, 0.21, -0.07}, {-0.13, 0.91, 0.18}, {0.05, -0.24, 1.07}};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        F[i][j] = (i == j ? 1.0 : 0.0) + scale * (v[i][j] - (i == j ? 1.0 : 0.0));
    return F;
  }

  /// Central difference of f with respect to the symmetric tensor argument: returns
  /// 2 ∂f/∂C_AB (the factor 2 of S = 2∂Ψ/∂C and ℂ = 2∂S/∂C), perturbing C_AB and C_BA
  /// together.
  template <typename T>
  T
  fd_component(const std::function<T(const SymTensor2 &)> &f,
               const SymTensor2                         &C,
               const unsigned                            A,
               const unsigned                            B,
               const double                              h)
  {
    SymTensor2 Cp = C, Cm = C;
    Cp[A][B] += h; // a SymmetricTensor entry is C_AB and C_BA at once
    Cm[A][B] -= h;
    const double factor = (A == B) ? 2.0 : 1.0;
    return (factor / (2 * h)) * (f(Cp) - f(Cm));
  }
} // namespace

TEST(Material, StressIsDerivativeOfEnergy)
{
  for (const auto &c : cases)
    for (const double scale : {0.3, 1.0, 2.0})
      {
        const Material   m = make(c);
        const Tensor2    F = sample_F(scale);
        const SymTensor2 C = dealii::symmetrize(dealii::transpose(F) * F);
        SymTensor2       S;
        SymTensor4       CC;
        m.response(C, S, CC);
        const std::function<double(const SymTensor2 &)> psi = [&](const SymTensor2 &X) {
          return m.energy(X);
        };
        for (unsigned A = 0; A < 3; ++A)
          for (unsigned B = A; B < 3; ++B)
            {
              const double fd = fd_component(psi, C, A, B, 1e-6);
              EXPECT_LE(std::abs(fd - S[A][B]), 1e-6 * S.norm())
                << c.model << " S" << A << B << " fd=" << fd << " S=" << S[A][B];
            }
      }
}

TEST(Material, TangentIsDerivativeOfStress)
{
  for (const auto &c : cases)
    for (const double scale : {0.3, 1.0, 2.0})
      {
        const Material   m = make(c);
        const Tensor2    F = sample_F(scale);
        const SymTensor2 C = dealii::symmetrize(dealii::transpose(F) * F);
        SymTensor2       S;
        SymTensor4       CC;
        m.response(C, S, CC);
        const std::function<SymTensor2(const SymTensor2 &)> stress =
          [&](const SymTensor2 &X) {
            SymTensor2 Sx;
            SymTensor4 CCx;
            m.response(X, Sx, CCx);
            return Sx;
          };
        double max_error = 0;
        for (unsigned A = 0; A < 3; ++A)
          for (unsigned B = A; B < 3; ++B)
            {
              const SymTensor2 fd = fd_component(stress, C, A, B, 1e-6);
              for (unsigned I = 0; I < 3; ++I)
                for (unsigned K = I; K < 3; ++K)
                  max_error = std::max(max_error, std::abs(fd[I][K] - CC[I][K][A][B]));
            }
        EXPECT_LE(max_error, 1e-6 * CC.norm()) << c.model << " scale " << scale;
      }
}

TEST(Material, RejectsIncompressiblePoissonRatio)
{
  dealii::ParameterHandler prm;
  Material::declare_parameters(prm);
  // refused on reading (the range its help states, (-1, 0.5)) or by the material's check
  try
    {
      ParameterFile file(prm, "set Poisson ratio = 0.5\n", "nu.prm", ".");
      Material::parse_parameters(prm, ParameterScope(file, "Tissue/Material"));
      FAIL() << "nu = 0.5 accepted";
    }
  catch (const InputError &e)
    {
      EXPECT_NE(std::string(e.what()).find("nu.prm"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("Poisson ratio"), std::string::npos) << e.what();
    }
}

TEST(Material, VolumetricEnergiesMatchTheirClosedForms)
{
  // p = dΨ/dJ and dp/dJ of the registered energies against their formulas, and p(1) = 0.
  const double kappa = 3e6;
  const auto  &reg   = VolumetricEnergy::Registry::instance();
  for (const double J : {0.8, 1.0, 1.25})
    {
      const auto st = reg.get("simo-taylor-1991").create(kappa);
      EXPECT_NEAR(st->energy(J), kappa / 4 * (J * J - 1 - 2 * std::log(J)), 1e-9 * kappa);
      EXPECT_NEAR(st->pressure(J), kappa / 2 * (J - 1 / J), 1e-9 * kappa);
      EXPECT_NEAR(st->pressure_derivative(J), kappa / 2 * (1 + 1 / (J * J)), 1e-9 * kappa);
      const auto q = reg.get("quadratic").create(kappa);
      EXPECT_NEAR(q->energy(J), kappa / 2 * (J - 1) * (J - 1), 1e-9 * kappa);
      EXPECT_NEAR(q->pressure(J), kappa * (J - 1), 1e-9 * kappa);
      const auto l = reg.get("logarithmic").create(kappa);
      EXPECT_NEAR(l->energy(J), kappa / 2 * std::log(J) * std::log(J), 1e-9 * kappa);
      EXPECT_NEAR(l->pressure(J), kappa * std::log(J) / J, 1e-9 * kappa);
      for (const auto *e : {st.get(), q.get(), l.get()})
        {
          const double h = 1e-6;
          EXPECT_NEAR(e->pressure(J), (e->energy(J + h) - e->energy(J - h)) / (2 * h), 1e-6 * kappa);
          EXPECT_NEAR(e->pressure_derivative(J),
                      (e->pressure(J + h) - e->pressure(J - h)) / (2 * h), 1e-6 * kappa);
        }
    }
}
