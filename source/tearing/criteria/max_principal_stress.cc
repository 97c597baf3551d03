/**
 * Maximum principal Cauchy stress (Rankine): m = σ₁, the largest eigenvalue of σ; the tear
 * opens against its eigenvector. Default m_c: the mean ultimate tensile strength of
 * excised human back skin, 21.6 ± 8.4 MPa (Ní Annaidh et al., J Mech Behav Biomed Mater
 * 5:139, 2012; uniaxial, 0.012 1/s).
 */
#include <suturesim/tearing/threshold_criterion.h>

#include <deal.II/base/parameter_handler.h>

namespace suturesim::tearing
{
  namespace
  {
    class MaxPrincipalStress : public ThresholdCriterion
    {
    public:
      explicit MaxPrincipalStress(const double strength)
        : ThresholdCriterion(strength, "Pa")
      {}

      Measure
      measure(const MaterialPointState &state) const override
      {
        const auto [sigma_1, n] = largest_principal(state.cauchy_stress);
        return {sigma_1, n};
      }
    };

    const bool registered = TearCriterion::Registry::instance().add(
        {"max-principal-stress",
         "m = sigma_1, the largest principal Cauchy stress (Rankine); onset when its process-zone mean reaches the "
         "tensile strength.",
         [](dealii::ParameterHandler &prm) {
           prm.enter_subsection("max-principal-stress");
           prm.declare_entry("Tensile strength", "21.6e6", dealii::Patterns::Double(0),
                             "Critical principal Cauchy stress; default the mean UTS of human back skin (Ni Annaidh "
                             "et al. 2012, 21.6 +- 8.4 MPa). Unit: Pa. Range: > 0.");
           prm.leave_subsection();
         },
         [](const dealii::ParameterHandler &prm, const ParameterScope &scope) {
           const double strength = prm.get_double("Tensile strength");
           scope.require(strength > 0, "Tensile strength", "must be > 0 Pa");
           return std::unique_ptr<TearCriterion>(new MaxPrincipalStress(strength));
         }});
  } // namespace
} // namespace suturesim::tearing
