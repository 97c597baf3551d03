#pragma once
/**
 * @file
 * Time integrators of the accurate tissue model, registered by name:
 *  - "quasi-static": load stepping t = Δt, 2Δt, … T with Newton per step, halving Δt on
 *    failure (bounded), growing it back after success;
 *  - "ida": implicit dynamics M v̇ + (a_M M + a_K K_t) v + R(u, t) = 0, u̇ = v, by
 *    SUNDIALS IDA (variable-order BDF, adaptive error-controlled steps).
 * Both record each accepted state the same way (reactions, probes, VTU, progress).
 */

#include <suturesim/core/registry.h>
#include <suturesim/io/recorder.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/base/conditional_ostream.h>

#include <chrono>
#include <map>

namespace suturesim::tissue
{
  struct TimeParameters
  {
    std::string integrator      = "quasi-static";
    double      end_time        = 1.0;
    double      step_size       = 0.1;
    unsigned    max_cutbacks    = 6;
    double      output_interval = 0.0;

    /// Declares into the current subsection ("Time") and lets each tissue integrator
    /// declare its own subsection. @p other_integrators (name → description) are
    /// integrators of other bodies (the suture's) offered under the same key.
    static void
    declare(dealii::ParameterHandler &prm,
            const std::map<std::string, std::string> &other_integrators = {});
    void
    parse(const dealii::ParameterHandler &prm, const ParameterScope &scope);
  };

  class TimeIntegrator
  {
  public:
    using Registry = suturesim::Registry<TimeIntegrator,
                                         const dealii::ParameterHandler &,
                                         const ParameterScope &>;

    virtual ~TimeIntegrator() = default;

    /// Runs from t = 0 to the end time; throws SolverError (after recording the last
    /// converged state) when a step cannot be completed.
    virtual void
    run(TissueModel &model, const TimeParameters &time, io::Recorder &recorder) = 0;

  protected:
    /// Records the current state at time t: a forces.csv row, the per-step statistics,
    /// and (when due) a VTU file. @p statistics goes into summary.json "steps".
    void
    record(TissueModel                &model,
           io::Recorder               &recorder,
           const TimeParameters       &time,
           double                      t,
           nlohmann::json              statistics,
           const TissueModel::Vector *velocity     = nullptr,
           const TissueModel::Vector *acceleration = nullptr);

    /// One progress line: step, simulated time, Newton iterations, ETA.
    void
    progress(unsigned step, unsigned expected_steps, double t, double end_time,
             const std::string &solver_info);

    std::string last_output_file;
    double      last_output_time = -1;
    double      last_converged_time = 0;
    unsigned    output_index = 0;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  };
} // namespace suturesim::tissue
