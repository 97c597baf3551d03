/**
 * Quasi-static load stepping with bounded cutback: a step whose Newton solve fails is
 * halved (up to "Max cutbacks" times in a row), and after a success the step grows back
 * toward the nominal size. When it still fails the run stops with the reason, keeping
 * the last converged state on disk.
 */
#include <suturesim/core/error.h>
#include <suturesim/tissue/time_integrator.h>

#include <cmath>
#include <sstream>

namespace suturesim::tissue
{
  namespace
  {
    nlohmann::json
    to_json(const NewtonReport &r, const double dt, const unsigned cutbacks)
    {
      return {{"dt", dt},
              {"newton_iterations", r.iterations},
              {"residual_norms", r.residual_norms},
              {"increment_norms", r.increment_norms},
              {"line_search_backtracks", r.backtracks},
              {"linear_iterations", r.linear_iterations},
              {"assembly_seconds", r.assembly_seconds},
              {"solve_seconds", r.solve_seconds},
              {"cutbacks", cutbacks}};
    }

    class QuasiStatic : public TimeIntegrator
    {
    public:
      void
      run(TissueModel &model, const TimeParameters &time, io::Recorder &recorder) override
      {
        const double   T        = time.end_time;
        const unsigned expected = static_cast<unsigned>(std::ceil(T / time.step_size - 1e-9));
        double         t        = 0;
        double         dt       = time.step_size;
        unsigned       step     = 0;
        unsigned       total_iterations = 0;

        // Equilibrium at t = 0 (gravity or loads that start non-zero).
        model.save_state();
        const NewtonReport initial = model.solve_static(0.0);
        if (!initial.converged)
          fail(model, recorder, 0.0, 0, 0, initial.failure, "the initial state");
        record(model, recorder, time, 0.0, to_json(initial, 0.0, 0));

        unsigned cutbacks = 0;
        while (t < T * (1 - 1e-12))
          {
            const double step_dt = std::min(dt, T - t);
            model.save_state();
            const NewtonReport report = model.solve_static(t + step_dt);
            if (!report.converged)
              {
                model.restore_state();
                if (cutbacks == time.max_cutbacks)
                  fail(model, recorder, t + step_dt, step + 1, cutbacks, report.failure, "");
                ++cutbacks;
                dt = 0.5 * step_dt;
                continue;
              }
            t += step_dt;
            ++step;
            total_iterations += report.iterations;
            record(model, recorder, time, t, to_json(report, step_dt, cutbacks));
            std::ostringstream info;
            info << "Newton " << report.iterations << " it"
                 << (cutbacks ? "  (dt halved " + std::to_string(cutbacks) + "x)" : "");
            progress(step, std::max(expected, step), t, T, info.str());
            cutbacks = 0;
            dt       = std::min(2 * dt, time.step_size);
          }
        auto &stats                      = recorder.summary()["solver"];
        stats["integrator"]              = "quasi-static";
        stats["steps"]                   = step;
        stats["newton_iterations_total"] = total_iterations;
      }

    private:
      [[noreturn]] void
      fail(TissueModel       &model,
           io::Recorder      &recorder,
           const double       t,
           const unsigned     step,
           const unsigned     cutbacks,
           const std::string &reason,
           const std::string &what)
      {
        // The state was restored to the last converged one: make sure it is on disk.
        if (step > 0 && last_output_time < last_converged_time)
          {
            last_output_file = model.write_vtu(recorder.directory(), output_index++,
                                               last_converged_time);
            recorder.add_vtu("tissue", last_converged_time, last_output_file);
          }
        std::ostringstream s;
        s << "Newton failed at " << (what.empty() ? "step " + std::to_string(step) : what)
          << " (t = " << t << " s) after " << cutbacks << " step halvings: " << reason
          << "; last converged state t = " << last_converged_time << " s"
          << (last_output_file.empty() ? "" : " in " + recorder.directory() + "/" +
                                                last_output_file);
        throw SolverError(s.str());
      }
    };

    const bool registered = TimeIntegrator::Registry::instance().add(
      {"quasi-static",
       "Quasi-static load stepping, Newton per step with bounded halving of failing steps.",
       nullptr,
       [](const dealii::ParameterHandler &, const ParameterScope &) {
         return std::unique_ptr<TimeIntegrator>(new QuasiStatic());
       }});
  } // namespace
} // namespace suturesim::tissue
