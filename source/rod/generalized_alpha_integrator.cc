#include <suturesim/core/error.h>
#include <suturesim/rod/generalized_alpha.h>
#include <suturesim/rod/rod_integrator.h>

namespace suturesim::rod
{
  namespace
  {
    class GeneralizedAlphaIntegrator : public RodIntegrator
    {
    public:
      explicit GeneralizedAlphaIntegrator(const double rho)
        : rho(rho)
      {}

      void
      run(RodProblem &p) override
      {
        p.set_time(0);
        GeneralizedAlpha ga(p.model, rho, p.parameters.damping);
        ga.initialize(std::vector<Vec3>(p.model.n_nodes(), Vec3::Zero()),
                      std::vector<Vec3>(p.model.n_nodes(), Vec3::Zero()));
        p.record(0, {{"time", 0.0}, {"newton_iterations", 0}});
        double   t = 0, dt = p.time.step_size;
        unsigned cutbacks = 0;
        const auto prescribed = p.prescribed_nodes();
        while (t < p.time.end_time * (1 - 1e-12))
          {
            const double t_new = std::min(t + dt, p.time.end_time);
            p.set_time(t_new);
            const NewtonResult result = ga.step(t_new - t, p.parameters.newton, prescribed);
            p.newton_iterations += result.iterations;
            if (!result.converged)
              {
                p.set_time(t);
                if (++cutbacks > p.time.max_cutbacks)
                  throw SolverError("suture dynamics step from t = " + std::to_string(t) +
                                    " s failed after " + std::to_string(p.time.max_cutbacks) +
                                    " cutbacks (last step " + std::to_string(dt) + " s): " + result.reason +
                                    "; the last converged state is kept");
                dt *= 0.5;
                continue;
              }
            t = t_new;
            p.record(t,
                     {{"time", t},
                      {"newton_iterations", result.iterations},
                      {"residual", result.residual},
                      {"step_size", dt},
                      {"kinetic_energy", p.model.kinetic_energy(ga.velocities(), ga.angular_velocities())}},
                     &ga.last_residual());
            if (cutbacks == 0)
              dt = std::min(2 * dt, p.time.step_size);
            cutbacks = 0;
          }
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
