#include <suturesim/tissue/volumetric_energy.h>

#include <cmath>

namespace suturesim::tissue
{
  namespace
  {
    /// Ψ = κ/4 (J² − 1 − 2 ln J)  (Simo & Taylor 1991).
    class SimoTaylor : public VolumetricEnergy
    {
    public:
      explicit SimoTaylor(const double kappa)
        : kappa(kappa)
      {}
      double
      energy(const double J) const override
      {
        return 0.25 * kappa * (J * J - 1.0 - 2.0 * std::log(J));
      }
      double
      pressure(const double J) const override
      {
        return 0.5 * kappa * (J - 1.0 / J);
      }
      double
      pressure_derivative(const double J) const override
      {
        return 0.5 * kappa * (1.0 + 1.0 / (J * J));
      }

    private:
      double kappa;
    };

    /// Ψ = κ/2 (J − 1)².
    class Quadratic : public VolumetricEnergy
    {
    public:
      explicit Quadratic(const double kappa)
        : kappa(kappa)
      {}
      double
      energy(const double J) const override
      {
        return 0.5 * kappa * (J - 1.0) * (J - 1.0);
      }
      double
      pressure(const double J) const override
      {
        return kappa * (J - 1.0);
      }
      double
      pressure_derivative(const double) const override
      {
        return kappa;
      }

    private:
      double kappa;
    };

    /// Ψ = κ/2 (ln J)².
    class Logarithmic : public VolumetricEnergy
    {
    public:
      explicit Logarithmic(const double kappa)
        : kappa(kappa)
      {}
      double
      energy(const double J) const override
      {
        return 0.5 * kappa * std::log(J) * std::log(J);
      }
      double
      pressure(const double J) const override
      {
        return kappa * std::log(J) / J;
      }
      double
      pressure_derivative(const double J) const override
      {
        return kappa * (1.0 - std::log(J)) / (J * J);
      }

    private:
      double kappa;
    };

    template <typename Model>
    VolumetricEnergy::Registry::Entry
    entry(const char *name, const char *description)
    {
      return {name, description, nullptr, [](const double kappa) {
                return std::unique_ptr<VolumetricEnergy>(new Model(kappa));
              }};
    }

    const bool registered =
      VolumetricEnergy::Registry::instance().add(entry<SimoTaylor>(
        "simo-taylor-1991",
        "Psi_vol = kappa/4 (J^2 - 1 - 2 ln J) (Simo & Taylor 1991; Cook's membrane "
        "benchmark of Pelteret & McBride 2016).")) &&
      VolumetricEnergy::Registry::instance().add(
        entry<Quadratic>("quadratic", "Psi_vol = kappa/2 (J - 1)^2.")) &&
      VolumetricEnergy::Registry::instance().add(
        entry<Logarithmic>("logarithmic", "Psi_vol = kappa/2 (ln J)^2."));
  } // namespace
} // namespace suturesim::tissue
