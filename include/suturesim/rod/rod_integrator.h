#pragma once
/**
 * @file
 * Time integrators of the accurate suture, registered by name (the Time/Integrator of a
 * scene whose Bodies = suture):
 *  - "quasi-static": load steps t = Δt, 2Δt, … T, Newton per step, Δt halved on failure
 *    and grown back after success;
 *  - "generalized-alpha": implicit dynamics (generalized_alpha.h), fixed Δt with the same
 *    cut-back on failure.
 * RodProblem holds what both share: the rod, its loads and end motion in time, and the
 * recording of each accepted state (forces.csv, suture.pvd, summary.json).
 */

#include <suturesim/core/registry.h>
#include <suturesim/io/polyline_writer.h>
#include <suturesim/io/recorder.h>
#include <suturesim/rod/rod_parameters.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/tissue/time_integrator.h>

#include <chrono>

namespace suturesim::rod
{
  /// The rod as a polyline for suture_*.vtu: nodes with radius and contact force, per
  /// segment the axial and shear force, bending and twisting moment, twist, curvature.
  io::PolylineData
  polyline_data(const RodModel &model, double radius);

  class RodProblem
  {
  public:
    RodProblem(const RodParameters &parameters, const tissue::TimeParameters &time,
               io::Recorder &recorder);

    /// Loads and end motion of time t.
    void
    set_time(double t);

    /// Records the current state at time t: a forces.csv row (end reactions, tip),
    /// summary metrics, @p statistics into summary.json "steps", a .vtu when due. The
    /// reactions are the constrained components of @p residual (default: the static
    /// residual; dynamics passes the one with inertia).
    void
    record(double t, nlohmann::json statistics, const Eigen::VectorXd *residual = nullptr);

    /// Indices of the nodes whose motion is prescribed.
    std::vector<std::size_t>
    prescribed_nodes() const;

    RodModel                     model;
    const RodModel               initial;
    const RodParameters         &parameters;
    const tissue::TimeParameters &time;
    io::Recorder                &recorder;
    unsigned                     newton_iterations = 0;

  private:
    double   last_output_time = -1;
    unsigned output_index     = 0;
    std::chrono::steady_clock::time_point start = std::chrono::steady_clock::now();
  };

  class RodIntegrator
  {
  public:
    using Registry = suturesim::Registry<RodIntegrator, const dealii::ParameterHandler &,
                                         const ParameterScope &>;
    virtual ~RodIntegrator() = default;

    /// Runs from t = 0 to the end time; throws SolverError (the last converged state
    /// recorded) when a step fails after every cut-back.
    virtual void
    run(RodProblem &problem) = 0;
  };
} // namespace suturesim::rod
