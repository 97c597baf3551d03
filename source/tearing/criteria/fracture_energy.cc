/**
 * Energy criterion with a fracture toughness G_c: m = Ψ, and a tear starts when the
 * process-zone mean of Ψ reaches the elastic limit of the AT1 gradient-damage model whose
 * internal length is the zone's radius ℓ,
 *   Ψ_c = 3 G_c / (16 ℓ)
 * (the homogeneous state stops being elastic at σ_c = √(3 G_c E / (8 ℓ)), Ψ_c = σ_c²/(2E);
 * Pham, Amor, Marigo & Maurini, Int J Damage Mech 20:618, 2011; Tanné, Li, Bourdin,
 * Marigo & Maurini, J Mech Phys Solids 110:80, 2018). So one length sets both the zone and
 * the strength it implies. Default G_c = 1.1 kJ/m²: porcine skin cut by a needle (the
 * insertion-test value of the review data in references.md; tear tests give 17–30 kJ/m²).
 * The tear opens against the largest principal Cauchy stress's eigenvector.
 */
#include <suturesim/tearing/tear_criterion.h>

#include <deal.II/base/parameter_handler.h>

namespace suturesim::tearing
{
  namespace
  {
    class FractureEnergy : public TearCriterion
    {
    public:
      explicit FractureEnergy(const double toughness) : toughness(toughness)
      {
      }

      Measure
      measure(const MaterialPointState &state) const override
      {
        return {state.energy, largest_principal(state.cauchy_stress).second};
      }

      double
      critical_value(const double process_zone_radius) const override
      {
        return 3.0 * toughness / (16.0 * process_zone_radius);
      }

      std::string
      unit() const override
      {
        return "J/m^3";
      }

    private:
      double toughness;
    };

    const bool registered = TearCriterion::Registry::instance().add(
        {"fracture-energy",
         "m = Psi; onset when its process-zone mean reaches the AT1 elastic limit 3 G_c / (16 l) of a damage model "
         "with internal length l = the process-zone radius (Pham et al. 2011).",
         [](dealii::ParameterHandler &prm) {
           prm.enter_subsection("fracture-energy");
           prm.declare_entry("Fracture toughness", default_toughness, dealii::Patterns::Double(0), toughness_help);
           prm.leave_subsection();
         },
         [](const dealii::ParameterHandler &prm, const ParameterScope &scope) {
           const double toughness = prm.get_double("Fracture toughness");
           scope.require(toughness > 0, "Fracture toughness", "must be > 0 J/m^2");
           return std::unique_ptr<TearCriterion>(new FractureEnergy(toughness));
         }});
  } // namespace
} // namespace suturesim::tearing
