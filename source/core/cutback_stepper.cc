#include <suturesim/core/cutback_stepper.h>
#include <suturesim/core/error.h>
#include <suturesim/core/interruption.h>

#include <algorithm>
#include <cmath>
#include <sstream>
#include <vector>

namespace suturesim
{
  namespace
  {
    /// The accepted steps over which the pace of a run is judged (see the header): long
    /// enough that a burst of short steps through an event (a contact, a puncture:
    /// halvings that double back within Max cutbacks steps) does not count, short enough
    /// that a collapsed run stops within seconds.
    constexpr std::size_t pace_window = 200;

    std::string
    text(const double value)
    {
      std::ostringstream s;
      s << value;
      return s.str();
    }
  } // namespace

  unsigned
  run_with_cutbacks(const StepControl &control, const StepHooks &hooks, const double t_start,
                    const StepperState *resume)
  {
    const double T = control.end_time, h = control.step_size;
    const double h_max = std::max(h, control.max_step_size), h_min = std::ldexp(h, -int(control.max_cutbacks));
    double       t = t_start, dt = h;
    unsigned     cutbacks = 0, steps = 0;
    std::vector<double> recent(pace_window, 0.0); // the last accepted steps, a ring
    double              recent_sum = 0;
    if (resume)
      {
        if (resume->recent.size() != pace_window)
          throw InputError("a checkpoint's step history holds " + std::to_string(resume->recent.size()) +
                           " steps, not the " + std::to_string(pace_window) + " this version keeps");
        t          = resume->t;
        dt         = resume->dt;
        steps      = resume->steps;
        recent     = resume->recent;
        recent_sum = resume->recent_sum;
      }
    while (t < T * (1 - 1e-12))
      {
        // a step ends on the next event (adaptive steps) or the end time when it would
        // reach it
        const double event   = hooks.next_event && h_max > h ? std::min(hooks.next_event(t), T) : T;
        const double step_dt = std::min(dt, event - t);
        const bool   ends_on = step_dt == event - t;
        const double t_new   = ends_on ? event : t + step_dt;
        const StepAttempt attempt = hooks.attempt(t_new, step_dt);
        const bool        failed  = attempt.outcome == StepAttempt::Outcome::failed;
        const bool        refine  = attempt.outcome == StepAttempt::Outcome::too_long &&
                            cutbacks < control.max_cutbacks + control.refinements;
        if (failed || refine)
          {
            hooks.undo(attempt, t_new, step_dt);
            if (failed && cutbacks == control.max_cutbacks)
              {
                hooks.fail(t_new, cutbacks, attempt.reason);
                throw SolverError("the step to t = " + text(t_new) + " s failed after " +
                                  std::to_string(cutbacks) + " step halvings: " + attempt.reason);
              }
            ++cutbacks;
            dt = 0.5 * step_dt;
            continue;
          }
        hooks.accept(t_new, step_dt, cutbacks);
        t = t_new;
        ++steps;
        if (ends_on && event < T)
          dt = h; // past an event: from the nominal step again
        else if (cutbacks > 0 || h_max <= h)
          dt = std::min(2 * dt, h); // back towards the nominal step
        else
          {
            const unsigned n      = attempt.iterations;
            const double   factor = n == 0 ? 2 : std::clamp(std::sqrt(double(control.target_iterations) / n), 0.5, 2.0);
            dt                    = std::clamp(dt * factor, h_min, h_max);
          }
        cutbacks = 0;
        recent_sum += step_dt - recent[steps % pace_window];
        recent[steps % pace_window] = step_dt;
        if (hooks.accepted)
          hooks.accepted({t, dt, steps, recent, recent_sum});
        // the last step ends the run as it would without the signal or the pace
        const bool before_end = t < T * (1 - 1e-12);
        if (const int signal = before_end ? stop_requested() : 0)
          {
            throw Interrupted(signal, t, hooks.keep ? hooks.keep(t) : "");
          }
        if (control.max_steps > 0 && steps >= pace_window && before_end)
          {
            const double pace = recent_sum / pace_window;
            if (steps + (T - t) / pace > control.max_steps)
              {
                const std::string where = hooks.keep ? hooks.keep(t) : "";
                throw SolverError("the steps collapsed at t = " + text(t) + " s: the last " + std::to_string(pace_window) +
                                  " averaged " + text(pace) + " s (nominal " + text(h) + " s), so End time = " + text(T) +
                                  " s is " + text((T - t) / pace) + " steps away, above Time/Maximum steps = " +
                                  text(control.max_steps) + " (" + std::to_string(steps) +
                                  " taken): the solution is likely diverging, or the loads too fast for the step" +
                                  (where.empty() ? "" : "; the state is in " + where));
              }
          }
      }
    return steps;
  }
} // namespace suturesim
