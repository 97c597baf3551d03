#pragma once
/**
 * @file
 * The one step-size control of the implicit solvers (tissue, suture, and the two solved
 * together): steps t = Δt, 2Δt, … up to the end time, each a nonlinear solve; a step
 * that fails is undone and halved, up to "Max cutbacks" times in a row, after which
 * the run fails; after an accepted step the step doubles back towards the nominal Δt
 * (the usual bounded cut-back of load stepping, e.g. FEBio's auto time stepper or
 * ASPECT's nonlinear-solver failure strategy, in its simplest form).
 *
 * A step may also converge and still be too long for an accuracy target of the caller
 * (e.g. an event that must land within a tolerance of its threshold): it is then undone
 * and halved as well, at most Max cutbacks + @ref StepControl::refinements halvings in a
 * row, and accepted once none is left.
 *
 * Adaptive steps (@ref StepControl::max_step_size above the nominal Δt): a step that
 * needed n Newton iterations, against a target N (Target iterations), is followed by
 *
 *     Δt_next = clamp(Δt · min(2, max(1/2, √(N / n))), Δt_nom 2^(−Max cutbacks), Δt_max)
 *
 * (n = 0 counts as doubling): steps grow while the solves are easy and shrink as they
 * get hard, before any fails — the iteration-count rule of the implicit codes' automatic
 * steppers (FEBio's time stepper with its dtmax and opt_iter; ABAQUS *STATIC's automatic
 * increments). No step crosses an event of the caller (@ref StepHooks::next_event: a
 * kink of a prescribed motion, a grasp): it ends on it, and the step after an event
 * starts again from the nominal Δt. With Δt_max = Δt_nom (the default) the steps are
 * those of the fixed stepper above.
 *
 * Plain C++: the solvers of both paths may include it.
 */

#include <functional>
#include <string>
#include <vector>

namespace suturesim
{
  struct StepControl
  {
    double   end_time     = 1;   ///< s
    double   step_size    = 0.1; ///< nominal Δt, s
    unsigned max_cutbacks = 6;   ///< halvings of a failing step in a row
    unsigned refinements  = 0;   ///< further halvings of a step that is too long
    double   max_step_size = 0;  ///< s; ≤ step_size: no growth beyond the nominal Δt
    unsigned target_iterations = 4; ///< Newton iterations a step aims at when adaptive
    /// the most accepted steps (0: no bound); see run_with_cutbacks()
    double max_steps = 0;
  };

  struct StepAttempt
  {
    enum class Outcome
    {
      converged,
      failed,  ///< the solve failed: undo, halve, or fail the run
      too_long ///< converged, but the caller wants a shorter step
    };
    Outcome     outcome = Outcome::converged;
    std::string reason;         ///< why it failed
    unsigned    iterations = 0; ///< the solve's Newton iterations (adaptive steps)
  };

  /// Where a run of run_with_cutbacks() stands after an accepted step, the next step's
  /// size chosen: enough to go on from there as if it had never stopped (a checkpoint's,
  /// io/checkpoint.h).
  struct StepperState
  {
    double              t  = 0; ///< s
    double              dt = 0; ///< the next step's size, s
    unsigned            steps = 0;
    std::vector<double> recent; ///< the last accepted steps (the pace's ring), s
    double              recent_sum = 0;
  };

  struct StepHooks
  {
    /// Solves from the current state (the last accepted one) to @p t_new = t + @p dt.
    std::function<StepAttempt(double t_new, double dt)> attempt;
    /// Returns to the last accepted state after @p attempt was rejected.
    std::function<void(const StepAttempt &attempt, double t_new, double dt)> undo;
    /// The attempt to @p t_new is accepted; @p cutbacks halvings led to it.
    std::function<void(double t_new, double dt, unsigned cutbacks)> accept;
    /// No halving is left for the failed step to @p t_new (the state is the last
    /// accepted one again): throw the run's SolverError.
    std::function<void(double t_new, unsigned cutbacks, const std::string &reason)> fail;
    /// Optional: the first event after time @p t that a step must end on (∞: none);
    /// read with adaptive steps only, so that fixed steps stay on their grid.
    std::function<double(double t)> next_event;
    /// Optional: the run stops after the step to @p t was accepted (a stop signal,
    /// core/interruption.h, or steps that collapsed): write the state and return where it
    /// is ("": nowhere new).
    std::function<std::string(double t)> keep;
    /// Optional: after each accepted step, before a stop signal is heeded, the state the
    /// run would go on from (for checkpoints).
    std::function<void(const StepperState &state)> accepted;
  };

  /// Runs from @p t_start to the end time; returns the number of accepted steps. When
  /// @p hooks.fail returns, a SolverError with the reason is thrown; after a step
  /// accepted once a stop signal has arrived, an Interrupted (core/interruption.h).
  ///
  /// Collapsed steps: a solution that diverges (or a load far too fast for the step)
  /// does not always fail a step; its steps shrink to the floor Δt 2^(−Max cutbacks) and
  /// it creeps on, millions of steps that look like progress. With
  /// @ref StepControl::max_steps = N, once the steps taken plus those still to go at the
  /// mean step of the last 200 exceed N the run stops (keep, then a SolverError naming
  /// the pace): a bounded number of steps, relative to the run's own step budget.
  ///
  /// @p resume: go on from that state (a restart) instead of from @p t_start.
  unsigned
  run_with_cutbacks(const StepControl &control, const StepHooks &hooks, double t_start = 0,
                    const StepperState *resume = nullptr);
} // namespace suturesim
