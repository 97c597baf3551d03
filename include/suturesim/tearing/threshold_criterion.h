#pragma once
/**
 * @file
 * A tear criterion whose critical value is one material constant, independent of the
 * process zone (stress, stretch and energy-density thresholds): the constant and its unit
 * here, the measure in each criterion's own file.
 */

#include <suturesim/tearing/tear_criterion.h>

#include <string>
#include <utility>

namespace suturesim::tearing
{
  class ThresholdCriterion : public TearCriterion
  {
  public:
    ThresholdCriterion(const double critical, std::string unit)
      : critical(critical)
      , measure_unit(std::move(unit))
    {}

    double
    critical_value(const double) const override
    {
      return critical;
    }

    std::string
    unit() const override
    {
      return measure_unit;
    }

  private:
    double      critical;
    std::string measure_unit;
  };
} // namespace suturesim::tearing
