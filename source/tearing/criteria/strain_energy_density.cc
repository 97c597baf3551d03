/**
 * Strain-energy density: m = Ψ, the strain energy per reference volume; the tear opens
 * against the largest principal Cauchy stress's eigenvector. Default m_c = 3.6 MJ/m³: the
 * mean strain energy to failure of excised human back skin, 3.6 ± 1.6 MJ/m³ (Ní Annaidh
 * et al., J Mech Behav Biomed Mater 5:139, 2012).
 */
#include <suturesim/tearing/threshold_criterion.h>

#include <deal.II/base/parameter_handler.h>

namespace suturesim::tearing
{
  namespace
  {
    class StrainEnergyDensity : public ThresholdCriterion
    {
    public:
      explicit StrainEnergyDensity(const double critical_energy)
        : ThresholdCriterion(critical_energy, "J/m^3")
      {}

      Measure
      measure(const MaterialPointState &state) const override
      {
        return {state.energy, largest_principal(state.cauchy_stress).second};
      }
    };

    const bool registered = TearCriterion::Registry::instance().add(
        {"strain-energy-density",
         "m = Psi, the strain energy per reference volume; onset when its process-zone mean reaches the critical "
         "energy density.",
         [](dealii::ParameterHandler &prm) {
           prm.enter_subsection("strain-energy-density");
           prm.declare_entry(
               "Critical energy density", "3.6e6", dealii::Patterns::Double(0),
               "Critical strain energy per reference volume; default the mean strain energy to failure "
               "of human back skin (Ni Annaidh et al. 2012, 3.6 +- 1.6 MJ/m^3). Unit: J/m^3. Range: > 0.");
           prm.leave_subsection();
         },
         [](const dealii::ParameterHandler &prm, const ParameterScope &scope) {
           const double energy = prm.get_double("Critical energy density");
           scope.require(energy > 0, "Critical energy density", "must be > 0 J/m^3");
           return std::unique_ptr<TearCriterion>(new StrainEnergyDensity(energy));
         }});
  } // namespace
} // namespace suturesim::tearing
