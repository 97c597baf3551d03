#include <suturesim/core/cutback_stepper.h>
#include <suturesim/core/error.h>

#include <algorithm>

namespace suturesim
{
  unsigned
  run_with_cutbacks(const StepControl &control, const StepHooks &hooks, const double t_start)
  {
    const double T = control.end_time, h = control.step_size;
    double       t = t_start, dt = h;
    unsigned     cutbacks = 0, steps = 0;
    while (t < T * (1 - 1e-12))
      {
        const double      step_dt = std::min(dt, T - t), t_new = t + step_dt;
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
        cutbacks = 0;
        dt       = std::min(2 * dt, h);
      }
    return steps;
  }
} // namespace suturesim
