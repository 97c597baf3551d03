/**
 * The needle in the accurate path: a needle pass through the FE tissue (Bodies =
 * tissue) or a stitch with the Cosserat suture attached at the swage (Bodies = tissue
 * and suture), built and stepped by scene/accurate_stitch.h, recorded by
 * scene/accurate_stitch_record.h; quasi-static steps under core/cutback_stepper.h.
 */
#include <suturesim/core/error.h>
#include <suturesim/io/checkpoint.h>
#include <suturesim/scene/accurate_stitch_record.h>
#include <suturesim/scene/scenario.h>
#include <suturesim/scene/timed_run.h>

#include <iomanip>
#include <sstream>

namespace suturesim::scene
{
  using namespace dealii;

  namespace
  {
    /// Thrown from an accepted step after which the run cannot go on as its scene asks
    /// (NeedleClearance::reason()): it ends there, incomplete, its state kept.
    struct EndsEarly
    {};

    /// Where the steps stand, for a checkpoint (io/checkpoint.h), and back.
    nlohmann::json
    stepper_state(const StepperState &s)
    {
      return {{"t", s.t},
              {"dt", s.dt},
              {"steps", s.steps},
              {"recent", io::pack_doubles(s.recent)},
              {"recent_sum", s.recent_sum}};
    }

    StepperState
    stepper_from(const nlohmann::json &j)
    {
      return {j.at("t").get<double>(), j.at("dt").get<double>(), j.at("steps").get<unsigned>(),
              io::unpack_doubles(j.at("recent")), j.at("recent_sum").get<double>()};
    }

    class AccurateNeedle : public Scenario
    {
    public:
      AccurateNeedle(ParameterHandler &prm, SceneParameters &s)
        : scene(s)
      {
        const ParameterScope root = scene.scope();
        scene.scope("Closure").require(!scene.closure.present() || scene.bodies == "tissue and suture", "Gap probes",
                                       "wound closure needs the suture in the tissue: Bodies = tissue and suture");
        root.require(scene.bodies != "tissue and suture" || (scene.needle.present() && scene.needle.attach_suture),
                     "Bodies",
                     "the accurate path couples tissue and suture through a needle's pierce points: "
                     "set Needle/Shape and Needle/Attach suture = true, or use Model = realtime");
        // the planner ties a free rod in this path (scenarios/accurate_knot.cc), not a stitch
        scene.scope("Knot").require(scene.knot.knot == "none", "Knot",
                                    "the accurate path ties knots in a free suture (Bodies = suture); a stitch is "
                                    "tied off with a knot in the realtime path only (Model = realtime)");
        scene.parse_bodies(prm);
        if (scene.has_suture())
          scene.scope("Suture/Start end")
            .require(scene.suture.start_end.type == "free", "Type",
                     "must be free: the needle holds the suture's start (Needle/Attach suture)");
        if (scene.has_suture() && scene.closure.tie_off_each_stitch)
          {
            // the realtime path's checks (RealtimeWorld::add_series)
            scene.scope("Suture/Last end")
              .require(scene.suture.last_end.type == "free", "Type",
                       "must be free in an interrupted series (Needle/Pass/Series): the other hand takes each "
                       "stitch's tail once it is Tail length long");
            // a cut element would join the two pieces' ends in the self-contact's segments
            scene.scope("Suture/Self-contact")
              .require(!scene.suture.contact.enabled, "Enabled",
                       "an interrupted series (Needle/Pass/Series) cuts its thread: the suture's self-contact must "
                       "be off");
          }
        scene.scope("Tissue").require(scene.tissue.region_moduli.empty(), "Region moduli",
                                      "layered tissue is realtime only so far: use Model = realtime");
        scene.parse_time(prm);
        // the needle's steps are quasi-static (the needle is kinematic, the tissue in
        // equilibrium at each pose): another integrator is refused, not ignored
        scene.scope("Time").require(scene.time.integrator == "quasi-static", "Integrator",
                                    "the accurate needle pass steps quasi-statically; use quasi-static "
                                    "(dynamics of the needle scenes: not yet)");
      }

      void
      run(io::Recorder &recorder) override
      {
        run_timed(recorder, [&](TimerOutput &timer, ConditionalOStream &pcout) {
          AccurateStitch       stitch(scene, recorder.directory(), timer);
          AccurateStitchRecord record(stitch, recorder);
          const auto          &np = scene.needle;
          pcout << "suturesim: scene '" << scene.name << "', " << stitch.mesh_info.description << ", "
                << stitch.tria.n_global_active_cells() << " cells, " << stitch.model->n_dofs() << " DoFs, needle "
                << np.shape << " R = " << np.radius << " m, " << np.enforcement << " pierce points"
                << (stitch.suture ? ", Cosserat suture of " + std::to_string(stitch.suture->n_elements()) + " elements"
                                  : "")
                << "\n";

          double       t = 0;
          unsigned     steps = 0, total_iterations = 0, failed_attempts = 0;
          StepperState stepper;
          io::CheckpointSchedule schedule(scene.time.checkpoint_steps, scene.time.checkpoint_minutes, MPI_COMM_WORLD);
          const auto             checkpoint = [&] {
            recorder.checkpoint(t,
                                {{"newton_iterations_total", total_iterations},
                                 {"failed_attempts", failed_attempts},
                                 {"stepper", stepper_state(stepper)},
                                 {"stitch", stitch.snapshot()},
                                 {"record", record.snapshot()}},
                                stitch.local_snapshot());
          };
          // @p replayable: a checkpoint of the last accepted state was written
          const auto fail = [&](const double tn, const std::string &reason, const bool replayable) {
            // the state is the last accepted one again: keep it
            const std::string where = record.keep(t);
            record.finish(t);
            std::ostringstream s;
            s << "Newton failed at t = " << tn << " s after " << scene.time.max_cutbacks
              << " step halvings: " << reason << "; last converged state t = " << t << " s"
              << (where.empty() ? "" : " in " + where);
            if (replayable)
              s << " (suturesim --restart " << recorder.directory() << " replays the failed step from it)";
            throw SolverError(s.str());
          };
          if (recorder.resuming())
            {
              // a restart: the state of the checkpoint, as the run had it after that step
              try
                {
                  const auto &state = recorder.resumed_state();
                  stitch.restore(state.at("stitch"), recorder.resumed_local_state());
                  record.restore(state.at("record"));
                  total_iterations = state.at("newton_iterations_total").get<unsigned>();
                  failed_attempts  = state.at("failed_attempts").get<unsigned>();
                  stepper          = stepper_from(state.at("stepper"));
                  t                = stepper.t;
                  steps            = stepper.steps;
                }
              catch (const nlohmann::json::exception &e)
                {
                  throw InputError("--restart " + recorder.directory() + ": the checkpoint does not fit this scene (" +
                                   e.what() + ")");
                }
              pcout << "suturesim: restarting from the checkpoint after step " << steps << " at t = " << t << " s\n";
            }
          else
            {
              std::string failure;
              if (!stitch.solve_initial(failure))
                fail(0, failure, false);
              record.record(0, stitch.step_statistics(0, 0));
            }

          StepHooks hooks;
          hooks.attempt = [&](const double tn, const double dt) { return stitch.attempt(tn, dt); };
          hooks.undo    = [&](const StepAttempt &attempt, const double tn, const double dt) {
            if (attempt.outcome == StepAttempt::Outcome::failed)
              {
                ++failed_attempts;
                pcout << "t = " << tn << " s: step of " << dt << " s failed: " << attempt.reason << "\n";
              }
            stitch.undo();
          };
          hooks.accept = [&](const double tn, const double dt, const unsigned cutbacks) {
            stitch.accept();
            t = tn;
            ++steps;
            const nlohmann::json statistics = stitch.step_statistics(dt, cutbacks);
            total_iterations += statistics["newton_iterations"].get<unsigned>();
            record.record(t, statistics);
            stitch.advance();
            // one line a step (as ASPECT): a run that slows down shows where and why
            pcout << "step " << steps << "  t = " << std::setprecision(5) << t << " s  dt = " << dt << " s  Newton "
                  << statistics["newton_iterations"] << " it (suture at most "
                  << statistics["suture_newton_iterations"] << ")  rounds " << statistics["coupling_rounds"]
                  << "  pierce points " << stitch.needle->pierce_points().size() << "  contacts "
                  << (stitch.contact ? stitch.contact->contacts().size() : 0);
            if (statistics.contains("damage"))
              pcout << "  damage " << statistics["damage"]["max"].get<double>() << " ("
                    << statistics["damage"]["passes"] << " passes)";
            pcout << std::endl;
            // a needle driven back into the tissue (scene/needle_clearance.h) ends the run
            if (!stitch.clearance->reason().empty())
              throw EndsEarly();
          };
          hooks.fail = [&](const double tn, unsigned, const std::string &reason) {
            // the last accepted state as a checkpoint too: a restart with the failure
            // traces on (Suture/Newton/Trace failures) replays the failing step alone
            checkpoint();
            fail(tn, reason, true);
          };
          hooks.next_event = [&](const double tn) { return stitch.next_event(tn); };
          hooks.keep = [&](const double tn) {
            // a run stopped early can go on from here: the checkpoint before the state is
            // written out of turn, so that a restart's outputs are the uninterrupted run's
            checkpoint();
            const std::string where = record.keep(tn);
            record.finish(tn);
            return (where.empty() ? recorder.directory() : where) + " (suturesim --restart " + recorder.directory() +
                   " goes on from it)";
          };
          hooks.accepted = [&](const StepperState &state) {
            stepper = state;
            if (schedule.due())
              checkpoint();
          };
          // a step that overshoots the puncture threshold is halved up to 8 more times
          const auto &time = scene.time;
          try
            {
              run_with_cutbacks({time.end_time, time.step_size, time.max_cutbacks, 8, time.max_step_size,
                                 time.target_iterations, time.maximum_steps},
                                hooks, 0, recorder.resuming() ? &stepper : nullptr);
            }
          catch (const EndsEarly &)
            {
              record.keep(t); // the state it stopped in, out of turn
            }

          record.finish(t);
          if (!stitch.clearance->reason().empty())
            RunSummary(recorder.summary()).incomplete(stitch.clearance->reason());
          // failed_attempts: steps whose solve failed and was halved (events' refinements
          // of a step that overshot a threshold are not failures)
          RunSummary summary(recorder.summary());
          summary.solver({{"steps", steps}, {"newton_iterations_total", total_iterations}, {"failed_attempts", failed_attempts}});
          summary.factorization(stitch.model->linear_solver().statistics());
        });
      }

      bool
      writes_checkpoints() const override
      {
        return true;
      }

    private:
      SceneParameters &scene;
    };

    const bool registered = Scenario::Registry::instance().add(
      {"accurate needle",
       "a needle pass through the FE tissue, with the Cosserat suture attached at its swage (a stitch) "
       "when Bodies = tissue and suture (Model = accurate)",
       nullptr,
       [](const SceneParameters &s) {
         return s.model == "accurate" && s.has_tissue() && s.bodies != "fracture specimen" && s.bodies != "knot specimen" &&
                (s.needle.present() || s.bodies == "tissue and suture");
       },
       [](ParameterHandler &prm, SceneParameters &s) { return std::unique_ptr<Scenario>(new AccurateNeedle(prm, s)); }});
  } // namespace
} // namespace suturesim::scene
