/**
 * Compressible (decoupled) Mooney–Rivlin: Ψ_iso = C₁₀(Ī₁ − 3) + C₀₁(Ī₂ − 3), shear
 * modulus μ = 2(C₁₀ + C₀₁) (Holzapfel 2000, eq. 6.147).
 */
#include <suturesim/tissue/isochoric_energy.h>

#include <deal.II/base/parameter_handler.h>

namespace suturesim::tissue
{
  namespace
  {
    class MooneyRivlin : public IsochoricEnergy
    {
    public:
      MooneyRivlin(const double c10, const double c01)
        : c10(c10)
        , c01(c01)
      {}

      double
      shear_modulus() const override
      {
        return 2.0 * (c10 + c01);
      }

      Derivatives
      derivatives(const double I1bar, const double I2bar) const override
      {
        Derivatives d;
        d.psi = c10 * (I1bar - 3.0) + c01 * (I2bar - 3.0);
        d.d1  = c10;
        d.d2  = c01;
        return d;
      }

    private:
      double c10, c01;
    };

    const bool registered = IsochoricEnergy::Registry::instance().add(
      {"Mooney-Rivlin",
       "Psi_iso = C10 (I1bar - 3) + C01 (I2bar - 3), mu = 2 (C10 + C01) (Holzapfel 2000, "
       "eq. 6.147).",
       [](dealii::ParameterHandler &prm) {
         prm.enter_subsection("Mooney-Rivlin");
         prm.declare_entry("C10",
                           "1.0e6",
                           dealii::Patterns::Double(0),
                           "First Mooney-Rivlin constant C10. Unit: Pa. Range: >= 0.");
         prm.declare_entry("C01",
                           "0.11e6",
                           dealii::Patterns::Double(0),
                           "Second Mooney-Rivlin constant C01. Unit: Pa. Range: >= 0; "
                           "C10 + C01 > 0.");
         prm.leave_subsection();
       },
       [](const dealii::ParameterHandler &prm, const ParameterScope &scope) {
         const double c10 = prm.get_double("C10");
         const double c01 = prm.get_double("C01");
         scope.require(c10 + c01 > 0, "C10", "C10 + C01 must be > 0 Pa");
         return std::unique_ptr<IsochoricEnergy>(new MooneyRivlin(c10, c01));
       }});
  } // namespace
} // namespace suturesim::tissue
