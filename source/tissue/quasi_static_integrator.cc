/**
 * Quasi-static load stepping: Newton per load level, with the bounded cut-back of
 * core/cutback_stepper.h. When a step still fails the run stops with the reason, the
 * last converged state kept by the observer.
 */
#include <suturesim/core/cutback_stepper.h>
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

    /// @p next's solve after @p first's in one report: its state, both costs.
    NewtonReport
    merged(const NewtonReport &first, NewtonReport next)
    {
      next.iterations += first.iterations;
      next.backtracks += first.backtracks;
      next.linear_iterations += first.linear_iterations;
      next.assembly_seconds += first.assembly_seconds;
      next.solve_seconds += first.solve_seconds;
      next.residual_norms.insert(next.residual_norms.begin(), first.residual_norms.begin(), first.residual_norms.end());
      next.increment_norms.insert(next.increment_norms.begin(), first.increment_norms.begin(),
                                  first.increment_norms.end());
      return next;
    }

    /// Equilibrium at @p t and, with the phase field, the step's alternate minimisation
    /// (TissueModel::minimise_alternately()); a step that does not settle fails (and is
    /// halved). @p changes receives each damage solve's change of d.
    NewtonReport
    solve_step(TissueModel &model, const double t, std::vector<double> &changes)
    {
      NewtonReport report = model.solve_static(t);
      changes.clear();
      if (!report.converged)
        return report;
      const std::string failure = model.minimise_alternately(
        [&] {
          report = merged(report, model.solve_static(t));
          return report.converged ? std::string() : report.failure;
        },
        changes);
      if (!failure.empty())
        {
          report.converged = false;
          report.failure   = failure;
        }
      return report;
    }

    /// The step's record with the damage's, when there is a phase field.
    nlohmann::json
    with_damage(const TissueModel &model, nlohmann::json record, const std::vector<double> &changes)
    {
      if (model.damage_field())
        record["damage"] = model.damage_record(changes);
      return record;
    }

    class QuasiStatic : public TimeIntegrator
    {
    public:
      void
      run(TissueModel &model, const TimeParameters &time, StateObserver &observer) override
      {
        const double   T        = time.end_time;
        const unsigned expected = static_cast<unsigned>(std::ceil(T / time.step_size - 1e-9));
        unsigned       step = 0, total_iterations = 0;

        // Equilibrium at t = 0 (gravity or loads that start non-zero).
        model.save_state();
        std::vector<double> changes;
        const NewtonReport  initial = solve_step(model, 0.0, changes);
        if (!initial.converged)
          fail(observer, "the initial state", 0.0, 0, initial.failure);
        observer.accepted(0.0, with_damage(model, to_json(initial, 0.0, 0), changes), nullptr, nullptr);

        NewtonReport report;
        StepHooks    hooks;
        hooks.attempt = [&](const double t_new, double) {
          model.save_state();
          report = solve_step(model, t_new, changes);
          return report.converged ? StepAttempt{StepAttempt::Outcome::converged, "", report.iterations}
                                  : StepAttempt{StepAttempt::Outcome::failed, report.failure};
        };
        hooks.undo   = [&](const StepAttempt &, double, double) { model.restore_state(); };
        hooks.accept = [&](const double t, const double dt, const unsigned cutbacks) {
          ++step;
          total_iterations += report.iterations;
          observer.accepted(t, with_damage(model, to_json(report, dt, cutbacks), changes), nullptr, nullptr);
          std::ostringstream info;
          info << "Newton " << report.iterations << " it"
               << (cutbacks ? "  (dt halved " + std::to_string(cutbacks) + "x)" : "");
          progress(step, std::max(expected, step), t, T, info.str());
        };
        hooks.fail = [&](const double t_new, const unsigned cutbacks, const std::string &reason) {
          fail(observer, "step " + std::to_string(step + 1), t_new, cutbacks, reason);
        };
        hooks.keep = [&](double) { return observer.keep_last_accepted(); };
        run_with_cutbacks(
          {T, time.step_size, time.max_cutbacks, 0, time.max_step_size, time.target_iterations, time.maximum_steps}, hooks);
        observer.totals({{"integrator", "quasi-static"}, {"steps", step}, {"newton_iterations_total", total_iterations}});
      }

    private:
      [[noreturn]] static void
      fail(StateObserver &observer, const std::string &what, const double t, const unsigned cutbacks,
           const std::string &reason)
      {
        // the model holds the last converged state again: make sure it is on disk
        const std::string where = observer.keep_last_accepted();
        std::ostringstream s;
        s << "Newton failed at " << what << " (t = " << t << " s) after " << cutbacks
          << " step halvings: " << reason << "; last converged state t = " << observer.last_accepted_time() << " s"
          << (where.empty() ? "" : " in " + where);
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
