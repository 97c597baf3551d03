/**
 * Compressible (decoupled) neo-Hookean: Ψ_iso = μ/2 (Ī₁ − 3) (Holzapfel 2000, eq. 6.148;
 * the isochoric part of the Cook's membrane benchmark, Pelteret & McBride 2016).
 */
#include <suturesim/tissue/isochoric_energy.h>

#include <deal.II/base/parameter_handler.h>

namespace suturesim::tissue
{
  namespace
  {
    class NeoHookean : public IsochoricEnergy
    {
    public:
      explicit NeoHookean(const double mu)
        : mu(mu)
      {}

      double
      shear_modulus() const override
      {
        return mu;
      }

      Derivatives
      derivatives(const double I1bar, const double) const override
      {
        Derivatives d;
        d.psi = 0.5 * mu * (I1bar - 3.0);
        d.d1  = 0.5 * mu;
        return d;
      }

    private:
      double mu;
    };

    const bool registered = IsochoricEnergy::Registry::instance().add(
      {"neo-Hookean",
       "Psi_iso = mu/2 (I1bar - 3), mu the shear modulus (Holzapfel 2000, eq. 6.148).",
       [](dealii::ParameterHandler &prm) {
         prm.enter_subsection("neo-Hookean");
         // Dermis, Tran et al. 2007: C10 = 1.11 MPa, mu = 2 C10 (references.md).
         prm.declare_entry("Shear modulus",
                           "2.22e6",
                           dealii::Patterns::Double(0),
                           "Shear modulus mu = 2 C10. Unit: Pa. Range: > 0.");
         prm.leave_subsection();
       },
       [](const dealii::ParameterHandler &prm, const ParameterScope &scope) {
         const double mu = prm.get_double("Shear modulus");
         scope.require(mu > 0, "Shear modulus", "must be > 0 Pa");
         return std::unique_ptr<IsochoricEnergy>(new NeoHookean(mu));
       }});
  } // namespace
} // namespace suturesim::tissue
