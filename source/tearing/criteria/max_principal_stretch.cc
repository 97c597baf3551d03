/**
 * Maximum principal stretch: m = λ₁ = √(largest eigenvalue of b = F Fᵀ); the tear opens
 * against its eigenvector (current configuration). Default m_c = 1.54: the mean failure
 * strain of excised human back skin, 54 ± 17 % (Ní Annaidh et al., J Mech Behav Biomed
 * Mater 5:139, 2012).
 */
#include <suturesim/tearing/threshold_criterion.h>

#include <deal.II/base/parameter_handler.h>

#include <cmath>

namespace suturesim::tearing
{
  namespace
  {
    class MaxPrincipalStretch : public ThresholdCriterion
    {
    public:
      explicit MaxPrincipalStretch(const double critical_stretch)
        : ThresholdCriterion(critical_stretch, "1")
      {}

      Measure
      measure(const MaterialPointState &state) const override
      {
        const auto [b_1, n] = largest_principal(dealii::symmetrize(state.F * dealii::transpose(state.F)));
        return {std::sqrt(b_1), n};
      }
    };

    const bool registered = TearCriterion::Registry::instance().add(
        {"max-principal-stretch",
         "m = lambda_1, the largest principal stretch (sqrt of the largest eigenvalue of b = F F^T); onset when its "
         "process-zone mean reaches the critical stretch.",
         [](dealii::ParameterHandler &prm) {
           prm.enter_subsection("max-principal-stretch");
           prm.declare_entry("Critical stretch", "1.54", dealii::Patterns::Double(1),
                             "Critical principal stretch; default 1 + the mean failure strain of human back skin (Ni "
                             "Annaidh et al. 2012, 54 +- 17 %). Unit: 1. Range: > 1.");
           prm.leave_subsection();
         },
         [](const dealii::ParameterHandler &prm, const ParameterScope &scope) {
           const double stretch = prm.get_double("Critical stretch");
           scope.require(stretch > 1, "Critical stretch", "must be > 1");
           return std::unique_ptr<TearCriterion>(new MaxPrincipalStretch(stretch));
         }});
  } // namespace
} // namespace suturesim::tearing
