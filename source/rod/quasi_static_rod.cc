#include <suturesim/core/cutback_stepper.h>
#include <suturesim/core/error.h>
#include <suturesim/rod/rod_integrator.h>

namespace suturesim::rod
{
  namespace
  {
    /// Load stepping with Newton per step and the bounded cut-back of
    /// core/cutback_stepper.h (a failed step restores the last converged state).
    class QuasiStaticRod : public RodIntegrator
    {
    public:
      void
      run(RodProblem &p, StateObserver &observer) override
      {
        p.set_time(0);
        observer.accepted(0, {{"time", 0.0}, {"newton_iterations", 0}}, nullptr);
        p.model.commit_contact();
        double                 t = 0;
        std::vector<Vec3>      x;
        std::vector<Quat>      q;
        NewtonResult           result;
        StepHooks              hooks;
        hooks.attempt = [&](const double t_new, double) {
          x = p.model.positions();
          q = p.model.rotations();
          p.set_time(t_new);
          result = p.model.solve(p.parameters.newton);
          p.newton_iterations += result.iterations;
          return result.converged ? StepAttempt{} : StepAttempt{StepAttempt::Outcome::failed, result.reason};
        };
        hooks.undo = [&](const StepAttempt &, double, double) {
          for (std::size_t i = 0; i < x.size(); ++i)
            p.model.set_node(i, x[i], q[i]);
          p.set_time(t);
        };
        hooks.accept = [&](const double t_new, const double dt, unsigned) {
          t = t_new;
          observer.accepted(t, {{"time", t}, {"newton_iterations", result.iterations}, {"residual", result.residual},
                                {"step_size", dt}},
                            nullptr);
          p.model.commit_contact();
        };
        hooks.fail = [&](const double t_new, const unsigned cutbacks, const std::string &reason) {
          throw SolverError("suture load step from t = " + std::to_string(t) + " s to " + std::to_string(t_new) +
                            " s failed after " + std::to_string(cutbacks) + " step halvings: " + reason +
                            "; the last converged state is kept");
        };
        hooks.keep = [&](const double t_now) { return observer.keep(t_now); };
        run_with_cutbacks({p.time.end_time, p.time.step_size, p.time.max_cutbacks, 0, 0, 4, p.time.maximum_steps}, hooks);
      }
    };

    const bool registered = RodIntegrator::Registry::instance().add(
      {"quasi-static",
       "load stepping t = dt, 2 dt, ... T with Newton's method per step and halving of a "
       "failing step.",
       nullptr,
       [](const dealii::ParameterHandler &, const ParameterScope &) {
         return std::unique_ptr<RodIntegrator>(std::make_unique<QuasiStaticRod>());
       }});
  } // namespace
} // namespace suturesim::rod
