#pragma once
/**
 * @file
 * Time integrators of the accurate suture, registered by name (the Time/Integrator of a
 * scene whose Bodies = suture):
 *  - "quasi-static": load steps t = Δt, 2Δt, … T, Newton per step, with the bounded
 *    cut-back of core/cutback_stepper.h;
 *  - "generalized-alpha": implicit dynamics (generalized_alpha.h), fixed Δt with the same
 *    cut-back on failure.
 * RodProblem holds what both share: the rod, its loads and end motion in time. Each
 * accepted state is handed to a StateObserver (the driver's recorder); the integrators
 * write no output.
 */

#include <suturesim/core/parameter_file.h>
#include <suturesim/core/registry.h>
#include <suturesim/core/time_parameters.h>
#include <suturesim/rod/rod_parameters.h>

#include <nlohmann/json.hpp>

#include <vector>

namespace suturesim::rod
{
  class RodProblem
  {
  public:
    RodProblem(const RodParameters &parameters, const TimeParameters &time);

    /// Loads and end motion of time t.
    void
    set_time(double t);

    /// Indices of the nodes whose motion is prescribed.
    std::vector<std::size_t>
    prescribed_nodes() const;

    RodModel              model;
    const RodModel        initial;
    const RodParameters  &parameters;
    const TimeParameters &time;
    unsigned              newton_iterations = 0;
  };

  /// What is told of the states a rod integrator accepts.
  class StateObserver
  {
  public:
    virtual ~StateObserver() = default;
    /// The problem's model holds the accepted state at time @p t. The supports'
    /// reactions are the constrained components of @p residual (nullptr: the static
    /// residual; dynamics passes the one with inertia). @p statistics: the solver's
    /// account of the step (summary.json "steps").
    virtual void
    accepted(double t, const nlohmann::json &statistics, const Eigen::VectorXd *residual) = 0;

    /// The model holds the state accepted at @p t and the run stops there (a stop
    /// signal, core/interruption.h): make sure that state is on disk; returns where it
    /// is ("" if nowhere).
    virtual std::string
    keep(double t)
    {
      (void)t;
      return "";
    }
  };

  class RodIntegrator
  {
  public:
    using Registry = suturesim::Registry<RodIntegrator, const dealii::ParameterHandler &, const ParameterScope &>;
    virtual ~RodIntegrator() = default;

    /// Runs from t = 0 to the end time; throws SolverError (the model back at the last
    /// accepted state) when a step fails after every cut-back.
    virtual void
    run(RodProblem &problem, StateObserver &observer) = 0;
  };
} // namespace suturesim::rod
