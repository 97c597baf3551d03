#include <suturesim/core/cutback_stepper.h>
#include <suturesim/core/error.h>

#include <algorithm>
#include <cmath>

namespace suturesim
{
  unsigned
  run_with_cutbacks(const StepControl &control, const StepHooks &hooks, const double t_start)
  {
    const double T = control.end_time, h = control.step_size;
    const double h_max = std::max(h, control.max_step_size), h_min = std::ldexp(h, -int(control.max_cutbacks));
    double       t = t_start, dt = h;
    unsigned     cutbacks = 0, steps = 0;
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
                throw SolverError("the step to t = " + std::to_string(t_new) + " s failed after " +
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
      }
    return steps;
  }
} // namespace suturesim
