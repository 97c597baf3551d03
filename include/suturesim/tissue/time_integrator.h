#pragma once
/**
 * @file
 * Time integrators of the accurate tissue model, registered by name:
 *  - "quasi-static": load stepping t = Δt, 2Δt, … T with Newton per step and the
 *    bounded cut-back of core/cutback_stepper.h;
 *  - "ida": implicit dynamics M v̇ + (a_M M + a_K K_t) v + R(u, t) = 0, u̇ = v, by
 *    SUNDIALS IDA (variable-order BDF, adaptive error-controlled steps).
 * An integrator leaves each accepted state in the model and hands it to a StateObserver
 * (the driver's recorder: reactions, probes, VTU); it writes no output itself.
 */

#include <suturesim/core/parameter_file.h>
#include <suturesim/core/registry.h>
#include <suturesim/core/time_parameters.h>
#include <suturesim/tissue/tissue_model.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <string>

namespace suturesim::tissue
{
  /// What is told of the states an integrator accepts.
  class StateObserver
  {
  public:
    virtual ~StateObserver() = default;

    /// The model holds the accepted state at time @p t; in dynamics @p velocity and
    /// @p acceleration are v and v̇ (the supports then carry M v̇ + C v too).
    /// @p statistics: the solver's account of the step (summary.json "steps").
    virtual void
    accepted(double t, const nlohmann::json &statistics, const TissueModel::Vector *velocity,
             const TissueModel::Vector *acceleration) = 0;

    /// After a failure the model holds the last accepted state again: keep it (on
    /// disk); returns where it is, for the message ("" if nowhere).
    virtual std::string
    keep_last_accepted() = 0;

    /// The time of the last accepted state, s (0 before the first).
    virtual double
    last_accepted_time() const = 0;

    /// The integrator's totals at the end of the run (summary.json "solver").
    virtual void
    totals(const nlohmann::json &solver) = 0;
  };

  class TimeIntegrator
  {
  public:
    using Registry =
      suturesim::Registry<TimeIntegrator, const dealii::ParameterHandler &, const ParameterScope &>;

    virtual ~TimeIntegrator() = default;

    /// Runs from t = 0 to the end time; throws SolverError (after the observer has kept
    /// the last accepted state) when a step cannot be completed.
    virtual void
    run(TissueModel &model, const TimeParameters &time, StateObserver &observer) = 0;

  protected:
    /// One progress line: step, simulated time, solver account, ETA.
    void
    progress(unsigned step, unsigned expected_steps, double t, double end_time, const std::string &solver_info) const;

    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  };
} // namespace suturesim::tissue
