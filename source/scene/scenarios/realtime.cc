/**
 * The realtime path (Model = realtime, any bodies): the seed papers' reduced models at
 * haptic rate (libsuturesim_realtime), the world built by scene/realtime_world.h from
 * the same scene file as the accurate path, driven through the haptic loop one step per
 * 1/Rate, recorded by scene/realtime_record.h. Of Time only the end and the output
 * interval apply (the step is 1/Rate split into Substeps).
 */
#include <suturesim/core/error.h>
#include <suturesim/core/interruption.h>
#include <suturesim/realtime/divergence_guard.h>
#include <suturesim/scene/knot_parameters.h>
#include <suturesim/scene/realtime_record.h>
#include <suturesim/scene/run_summary.h>
#include <suturesim/scene/scenario.h>

#include <chrono>
#include <cmath>
#include <iostream>

namespace suturesim::scene
{
  using namespace dealii;
  namespace rt = realtime;

  namespace
  {
    class Realtime : public Scenario
    {
    public:
      Realtime(ParameterHandler &prm, SceneParameters &s)
        : scene(s)
      {
        scene.parse_bodies(prm);
        // the realtime step is 1/Rate; of Time only the end and the output interval apply
        prm.enter_subsection("Time");
        scene.time.end_time        = prm.get_double("End time");
        scene.time.output_interval = prm.get_double("Output interval");
        scene.time.maximum_steps   = prm.get_double("Maximum steps");
        scene.time.maximum_outputs = prm.get_double("Maximum outputs");
        scene.scope("Time").require(scene.time.end_time > 0, "End time", "must be > 0 s");
        scene.scope("Time").require(prm.get_double("Max step size") == 0, "Max step size",
                                    "the realtime step is the haptic step 1/Rate (Realtime/Rate)");
        prm.leave_subsection();
        if (scene.needle.present() && scene.has_suture() && scene.needle.attach_suture)
          scene.scope("Suture/Start end")
            .require(scene.suture.start_end.type == "free", "Type",
                     "must be free: the needle holds the suture's start (Needle/Attach suture)");
        prm.enter_subsection("Realtime");
        const ParameterScope realtime = scene.scope("Realtime");
        settings.parse(prm, realtime);
        // the guard of TimeParameters::parse() for the haptic step: End time = 1e308 at
        // 1 kHz overflowed the step count
        scene.time.check_counts(scene.time.end_time * settings.rate, scene.scope("Time"), "End time",
                                "haptic steps at Realtime/Rate", false);
        models = std::make_unique<RealtimeModels>(prm, realtime, settings, scene.has_tissue(), scene.has_suture());
        prm.leave_subsection();
        if (scene.has_tissue() && scene.has_suture() && settings.contact)
          realtime.require(settings.contact_stiffness > 0, "Contact stiffness", "must be > 0 N/m when Contact = true");
        refuse_what_is_not_modelled();
        KnotParameters::check(scene);
      }

      void
      run(io::Recorder &recorder) override
      {
        RealtimeWorld  world(scene, settings, std::move(*models), recorder.directory());
        RealtimeRecord record(world, settings, recorder);
        auto          &rw = *world.world;

        const double      end_time = scene.time.end_time, rate = settings.rate;
        const std::size_t n_steps  = static_cast<std::size_t>(std::llround(end_time * rate));
        if (n_steps == 0)
          scene.scope("Time").fail("End time", "is shorter than one haptic step 1/Rate");
        const double interval = scene.time.output_interval;
        std::cout << "suturesim: scene '" << scene.name << "', realtime: "
                  << (scene.has_tissue() ? settings.tissue_model + " tissue (" + world.tissue_mesh.description + "), "
                                         : "")
                  << (scene.has_suture() ? settings.suture_model + " suture of " +
                                             std::to_string(rw.system().suture.size()) + " nodes, "
                                         : "")
                  << settings.integrator << ", " << rate << " Hz x " << settings.substeps << " substeps, " << n_steps
                  << " steps\n";

        world.measure_closure();
        record.write_state();
        record.row(true);
        const auto                wall_start = std::chrono::steady_clock::now();
        rt::HapticLoop            loop(rw, rate, n_steps, settings.pacing);
        std::vector<rt::ToolPose> poses;
        double                    next_output = interval;
        std::string               failure;
        int                       stop_signal = 0;
        for (std::size_t step = 1; step <= n_steps; ++step)
          {
            // prescribed motions stop at a tie-off
            const double t = world.closure ? world.closure->motion_time(step / rate) : step / rate;
            // the tools' poses (a knot planner reading the rope) are part of the tick
            loop.begin_tick();
            world.tool_poses(t, poses);
            // a needle driven back into the tissue: the run ends at the last state before
            if (!world.stop_reason().empty())
              break;
            try
              {
                loop.tick(poses);
              }
            catch (const rt::DivergenceError &e)
              {
                failure = e.what();
                break;
              }
            // seed 003's tears, between steps
            if (world.tearing)
              world.tearing->check(rw, world.closure_tension());
            world.measure_closure();
            world.advance_series(); // an interrupted series' tails taken and stitches tied off
            const bool output = interval > 0 && t >= next_output - 1e-12 * end_time;
            record.row(output || step == n_steps); // the last state is always written
            if (output)
              {
                record.write_state();
                next_output += interval;
              }
            loop.end_tick();
            // a failed write stops the run (record.finish() throws it; exit 5)
            if (record.output_failed())
              break;
            // a signal stops the run here, between two ticks (core/interruption.h)
            if (step < n_steps && (stop_signal = stop_requested()) != 0)
              break;
          }
        // The last state (the last good one after a divergence) is always written.
        if (!record.state_written())
          record.write_state(true);
        const auto stats = loop.statistics(), tick = loop.tick_statistics();
        record.finish(stats, tick, loop.phase_statistics(),
                      std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count());
        std::cout << "suturesim: " << stats.steps << " steps, step time median " << stats.median_us << " us, p99 "
                  << stats.p99_us << " us, max " << stats.max_us << " us, " << stats.deadline_misses
                  << " deadline misses (" << stats.deadline_us << " us); whole tick median " << tick.median_us
                  << " us, p99 " << tick.p99_us << " us, " << tick.deadline_misses << " misses\n";
        if (!world.stop_reason().empty())
          RunSummary(recorder.summary()).incomplete(world.stop_reason());
        if (!failure.empty())
          throw SolverError(failure + "; outputs hold the last good state (t = " + std::to_string(rw.time()) + " s)");
        if (stop_signal != 0)
          throw Interrupted(stop_signal, rw.time(), recorder.directory());
      }

    private:
      /// What the realtime path does not model is refused, not silently dropped.
      void
      refuse_what_is_not_modelled() const
      {
        if (scene.has_suture())
          {
            const ParameterScope suture = scene.scope("Suture");
            const auto          &rod    = scene.suture;
            const ParameterScope loads = suture.subsection("Loads");
            loads.require(rod.end_force.isZero(), "End force",
                          "end loads are not applied by the realtime path (Model = realtime); "
                          "move the end with Last end = prescribed instead");
            loads.require(rod.end_moment.isZero(), "End moment",
                           "end loads are not applied by the realtime path (Model = realtime); "
                           "move the end with Last end = prescribed instead");
            loads.require(rod.distributed.isZero(), "Distributed load",
                           "is not applied by the realtime path (Model = realtime)");
            suture.subsection("Cross section")
              .require(rod.section.density > 0, "Density", "must be > 0 kg/m^3: the realtime suture has mass");
          }
        if (scene.has_tissue())
          {
            scene.scope("Tissue/Material")
              .require(scene.material->density() > 0, "Density", "must be > 0 kg/m^3: the realtime tissue has mass");
          }
      }

      SceneParameters                &scene;
      RealtimeSettings                settings;
      std::unique_ptr<RealtimeModels> models;
    };

    const bool registered = Scenario::Registry::instance().add(
      {"realtime",
       "the seed papers' reduced models at haptic rate: tissue, suture, needle and graspers in one "
       "realtime world (Model = realtime; subsection Realtime)",
       [](ParameterHandler &prm) {
         prm.enter_subsection("Realtime");
         RealtimeSettings::declare(prm);
         prm.leave_subsection();
       },
       [](const SceneParameters &s) {
         return s.model == "realtime" && s.bodies != "fracture specimen" && s.bodies != "knot specimen";
       },
       [](ParameterHandler &prm, SceneParameters &s) { return std::unique_ptr<Scenario>(new Realtime(prm, s)); }});
  } // namespace
} // namespace suturesim::scene
