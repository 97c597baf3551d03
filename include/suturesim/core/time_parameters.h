#pragma once
/**
 * @file
 * The "Time" subsection every model path reads: which integrator, the end time, the
 * (nominal) step, how many halvings of a failing step in a row, the output interval,
 * and the bounds of adaptive steps where an integrator takes them.
 * The integrators themselves are registered by the bodies they integrate (tissue/,
 * rod/); the scene offers all of them under one key (Simulation::declare_parameters).
 */

#include <suturesim/core/parameter_file.h>

#include <deal.II/base/parameter_handler.h>

#include <map>
#include <string>

namespace suturesim
{
  struct TimeParameters
  {
    std::string integrator      = "quasi-static";
    double      end_time        = 1.0; ///< s
    double      step_size       = 0.1; ///< s
    unsigned    max_cutbacks    = 6;
    double      output_interval = 0.0; ///< s; 0: every step
    /// adaptive steps (core/cutback_stepper.h): the largest step, s (≤ step_size: fixed
    /// steps), and the Newton iterations a step aims at
    double   max_step_size     = 0;
    unsigned target_iterations = 4;
    /// the most steps a run may take (Time/Maximum steps): refused before the run when
    /// the nominal steps exceed it, stopped during it when the steps taken and those
    /// still to go at the recent pace do (core/cutback_stepper.h)
    double maximum_steps = 1e6;
    /// the most output states (VTU files per body) a run may write (Time/Maximum
    /// outputs): refused before the run when End time / Output interval, or the steps
    /// when it is 0, exceed it
    double maximum_outputs = 1e4;
    /// checkpoints of the runs that write them (the accurate needle pass and stitch,
    /// io/checkpoint.h): every this many accepted steps and minutes of wall time (0: not
    /// by that count)
    unsigned checkpoint_steps   = 0;
    double   checkpoint_minutes = 0;

    /// Declares into the current subsection ("Time"); @p integrators (name →
    /// description) are the choices of "Integrator", of every body.
    static void
    declare(dealii::ParameterHandler &prm, const std::map<std::string, std::string> &integrators);
    void
    parse(const dealii::ParameterHandler &prm, const ParameterScope &scope);

    /// The resource guard of a run of @p steps nominal steps (End time / Step size, or
    /// End time x Realtime/Rate): refuses them above Time/Maximum steps, naming
    /// @p steps_key and saying they are @p what, and the output states they give
    /// (output_states()) above Time/Maximum outputs, naming Output interval.
    void
    check_counts(double steps, const ParameterScope &scope, const std::string &steps_key,
                 const std::string &what = "steps", bool every_step_when_zero = true) const;

    /// The output states a run of @p steps nominal steps writes, the initial state and
    /// the last included: End time / Output interval, at most one per step; when the
    /// interval is 0, one per step if @p every_step_when_zero (the accurate path), else
    /// the first and last alone (the realtime path).
    double
    output_states(double steps, bool every_step_when_zero = true) const;

    /// Whether a state at @p t is due for output after the last one at @p last_output
    /// (< 0: none yet): every state when the interval is 0, then one per interval, and
    /// the end time's.
    bool
    output_due(double t, double last_output) const;
  };
} // namespace suturesim
