#include <suturesim/core/error.h>
#include <suturesim/rod/rod_integrator.h>

namespace suturesim::rod
{
  namespace
  {
    /// Load stepping with Newton per step; a failed step restores the last converged
    /// state and is halved, up to Time/Max cutbacks times in a row.
    class QuasiStaticRod : public RodIntegrator
    {
    public:
      void
      run(RodProblem &p) override
      {
        p.set_time(0);
        p.record(0, {{"time", 0.0}, {"newton_iterations", 0}});
        double   t = 0, dt = p.time.step_size;
        unsigned cutbacks = 0;
        while (t < p.time.end_time * (1 - 1e-12))
          {
            const double t_new = std::min(t + dt, p.time.end_time);
            const auto   x = p.model.positions();
            const auto   q = p.model.rotations();
            p.set_time(t_new);
            const NewtonResult result = p.model.solve(p.parameters.newton);
            p.newton_iterations += result.iterations;
            if (!result.converged)
              {
                for (std::size_t i = 0; i < x.size(); ++i)
                  p.model.set_node(i, x[i], q[i]);
                p.set_time(t);
                if (++cutbacks > p.time.max_cutbacks)
                  throw SolverError("suture load step from t = " + std::to_string(t) + " s failed after " +
                                    std::to_string(p.time.max_cutbacks) + " cutbacks (last step " +
                                    std::to_string(dt) + " s): " + result.reason +
                                    "; the last converged state is kept");
                dt *= 0.5;
                continue;
              }
            t = t_new;
            p.record(t, {{"time", t}, {"newton_iterations", result.iterations}, {"residual", result.residual},
                         {"step_size", dt}});
            if (cutbacks == 0)
              dt = std::min(2 * dt, p.time.step_size);
            cutbacks = 0;
          }
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
