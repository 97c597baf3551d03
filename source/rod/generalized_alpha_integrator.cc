#include <suturesim/core/cutback_stepper.h>
#include <suturesim/core/error.h>
#include <suturesim/rod/generalized_alpha.h>
#include <suturesim/rod/rod_integrator.h>

namespace suturesim::rod
{
  namespace
  {
    /// Fixed-step generalized-α with the bounded cut-back of core/cutback_stepper.h (a
    /// step that fails leaves the integrator's state as it was).
    class GeneralizedAlphaIntegrator : public RodIntegrator
    {
    public:
      explicit GeneralizedAlphaIntegrator(const double rho)
        : rho(rho)
      {}

      void
      run(RodProblem &p, StateObserver &observer) override
      {
        p.set_time(0);
        GeneralizedAlpha ga(p.model, rho, p.parameters.damping);
        ga.initialize(std::vector<Vec3>(p.model.n_nodes(), Vec3::Zero()),
                      std::vector<Vec3>(p.model.n_nodes(), Vec3::Zero()));
        observer.accepted(0, {{"time", 0.0}, {"newton_iterations", 0}}, nullptr);
        p.model.commit_contact();
        double       t          = 0;
        const auto   prescribed = p.prescribed_nodes();
        NewtonResult result;
        StepHooks    hooks;
        hooks.attempt = [&](const double t_new, const double dt) {
          p.set_time(t_new);
          result = ga.step(dt, p.parameters.newton, prescribed);
          p.newton_iterations += result.iterations;
          return result.converged ? StepAttempt{} : StepAttempt{StepAttempt::Outcome::failed, result.reason};
        };
        hooks.undo   = [&](const StepAttempt &, double, double) { p.set_time(t); };
        hooks.accept = [&](const double t_new, const double dt, unsigned) {
          t = t_new;
          observer.accepted(t,
                            {{"time", t},
                             {"newton_iterations", result.iterations},
                             {"residual", result.residual},
                             {"step_size", dt},
                             {"kinetic_energy", p.model.kinetic_energy(ga.velocities(), ga.angular_velocities())}},
                            &ga.last_residual());
          p.model.commit_contact();
        };
        hooks.fail = [&](const double t_new, const unsigned cutbacks, const std::string &reason) {
          throw SolverError("suture dynamics step from t = " + std::to_string(t) + " s to " + std::to_string(t_new) +
                            " s failed after " + std::to_string(cutbacks) + " step halvings: " + reason +
                            "; the last converged state is kept");
        };
        hooks.keep = [&](const double t_now) { return observer.keep(t_now); };
        run_with_cutbacks({p.time.end_time, p.time.step_size, p.time.max_cutbacks, 0, 0, 4, p.time.maximum_steps}, hooks);
      }

    private:
      double rho;
    };

    const bool registered = RodIntegrator::Registry::instance().add(
      {"generalized-alpha",
       "implicit suture dynamics, Lie-group generalized-alpha (Bruls & Cardona 2010) with "
       "Chung-Hulbert parameters of spectral radius rho_inf; translational and rotational "
       "inertia, gravity, mass-proportional damping (suture only).",
       [](dealii::ParameterHandler &prm) {
         prm.enter_subsection("Generalized-alpha");
         prm.declare_entry("Spectral radius", "0.8", dealii::Patterns::Double(0, 1),
                           "rho_inf: 1 = no numerical dissipation (trapezoidal rule), smaller "
                           "values damp the highest frequencies more. Unit: 1. Range: [0, 1].");
         prm.leave_subsection();
       },
       [](const dealii::ParameterHandler &prm, const ParameterScope &) {
         auto &p = const_cast<dealii::ParameterHandler &>(prm);
         p.enter_subsection("Generalized-alpha");
         const double rho = p.get_double("Spectral radius");
         p.leave_subsection();
         return std::unique_ptr<RodIntegrator>(std::make_unique<GeneralizedAlphaIntegrator>(rho));
       }});
  } // namespace
} // namespace suturesim::rod
