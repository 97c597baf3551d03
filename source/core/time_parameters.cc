#include <suturesim/core/model_parameters.h>
#include <suturesim/core/time_parameters.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace suturesim
{
  void
  TimeParameters::declare(dealii::ParameterHandler &prm, const std::map<std::string, std::string> &integrators)
  {
    const TimeParameters d;
    std::string          pattern, doc = "Time integration. ";
    for (const auto &[name, description] : integrators)
      {
        pattern += (pattern.empty() ? "" : "|") + name;
        doc += "'" + name + "': " + description + " ";
      }
    prm.declare_entry("Integrator", d.integrator, dealii::Patterns::Selection(pattern), doc + "Unit: none.");
    prm.declare_entry("End time", default_text(d.end_time), dealii::Patterns::Double(0),
                      "Simulated time at the end of the run (for quasi-static runs the "
                      "load parameter of the boundary-condition functions). Unit: s. "
                      "Range: > 0.");
    prm.declare_entry("Step size", default_text(d.step_size), dealii::Patterns::Double(0),
                      "Load step (quasi-static) or initial step (IDA). Unit: s. Range: > 0.");
    prm.declare_entry("Max cutbacks", default_text(d.max_cutbacks), dealii::Patterns::Integer(0, 30),
                      "Consecutive halvings of a failing step before the run stops. Unit: 1. "
                      "Range: 0-30.");
    prm.declare_entry("Max step size", default_text(d.max_step_size), dealii::Patterns::Double(0),
                      "Adaptive steps (the accurate path's quasi-static steps: tissue, needle "
                      "pass, stitch): above 'Step size', each step is followed by one scaled by "
                      "sqrt(Target iterations / its Newton iterations), within [1/2, 2] times it, "
                      "up to this size; steps end on the motions' kinks and the grasp, and start "
                      "again from 'Step size' there. 0 (or <= Step size): fixed steps. Unit: s. "
                      "Range: >= 0.");
    prm.declare_entry("Target iterations", default_text(d.target_iterations), dealii::Patterns::Integer(1, 100),
                      "Newton iterations per step that adaptive steps aim at (see Max step size). "
                      "Unit: 1. Range: 1-100.");
    prm.declare_entry("Maximum steps", "1e6", dealii::Patterns::Double(1),
                      "A guard against a run that would never end: a scene whose End time / Step "
                      "size (realtime: End time x Realtime/Rate) is above this many steps is "
                      "refused before it starts, and an implicit run whose steps shrink so far "
                      "that the steps taken plus those still to go at the pace of its last 200 "
                      "exceed it stops with status failed (a diverging solution). Raise it for "
                      "a longer run. Unit: 1. Range: >= 1.");
    prm.declare_entry("Maximum outputs", "1e4", dealii::Patterns::Double(1),
                      "A guard against a run that would fill the disk or the folder: a scene "
                      "whose output states (VTU files per body: End time / Output interval, or "
                      "one per step when it is 0) are more than this is refused before it "
                      "starts. Raise it (or Output interval) for more states. Unit: 1. "
                      "Range: >= 1.");
    prm.declare_entry("Checkpoint steps", "0", dealii::Patterns::Integer(0),
                      "Checkpoints of the accurate needle pass and stitch (the run's folder, "
                      "checkpoint/; suturesim --restart DIR goes on from the last): every this many "
                      "accepted steps; 0: not by steps. A run stopped by SIGINT or SIGTERM writes one "
                      "anyway. Unit: 1. Range: >= 0.");
    prm.declare_entry("Checkpoint minutes", "0", dealii::Patterns::Double(0),
                      "Checkpoints (see Checkpoint steps) every this many minutes of wall time; 0: "
                      "not by time. Unit: min. Range: >= 0.");
    prm.declare_entry("Output interval", default_text(d.output_interval), dealii::Patterns::Double(0),
                      "Simulated time between VTU outputs; 0 writes every step (quasi-"
                      "static) or every 'Step size' (IDA); the realtime path writes the first and "
                      "last states alone. Unit: s. Range: >= 0.");
  }

  void
  TimeParameters::parse(const dealii::ParameterHandler &prm, const ParameterScope &scope)
  {
    integrator      = prm.get("Integrator");
    end_time        = prm.get_double("End time");
    step_size       = prm.get_double("Step size");
    max_cutbacks    = prm.get_integer("Max cutbacks");
    output_interval = prm.get_double("Output interval");
    max_step_size     = prm.get_double("Max step size");
    target_iterations = prm.get_integer("Target iterations");
    scope.require(end_time > 0, "End time", "must be > 0 s");
    scope.require(step_size > 0, "Step size", "must be > 0 s");
    scope.require(step_size <= end_time, "Step size", "must not exceed the end time");
    maximum_steps      = prm.get_double("Maximum steps");
    maximum_outputs    = prm.get_double("Maximum outputs");
    checkpoint_steps   = prm.get_integer("Checkpoint steps");
    checkpoint_minutes = prm.get_double("Checkpoint minutes");
    check_counts(end_time / step_size, scope, "Step size");
  }

  double
  TimeParameters::output_states(const double steps, const bool every_step_when_zero) const
  {
    if (output_interval <= 0)
      return every_step_when_zero ? 1 + steps : 2;
    return 1 + std::min(steps, std::ceil(end_time / output_interval));
  }

  void
  TimeParameters::check_counts(const double steps, const ParameterScope &scope, const std::string &steps_key,
                               const std::string &what, const bool every_step_when_zero) const
  {
    std::ostringstream why;
    why << "gives " << steps << " " << what << " to End time, above Time/Maximum steps = " << maximum_steps
        << " (raise it to run this)";
    scope.require(steps <= maximum_steps, steps_key, why.str());
    const double states = output_states(steps, every_step_when_zero);
    why.str("");
    why << "gives " << states << " output states (VTU files per body) to End time, above Time/Maximum outputs = "
        << maximum_outputs << " (raise it, or Output interval, to write them)";
    scope.require(states <= maximum_outputs, "Output interval", why.str());
  }

  bool
  TimeParameters::output_due(const double t, const double last_output) const
  {
    return output_interval <= 0 || last_output < 0 || t >= last_output + output_interval * (1 - 1e-9) ||
           t >= end_time * (1 - 1e-12);
  }
} // namespace suturesim
