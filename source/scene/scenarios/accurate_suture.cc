/**
 * The accurate suture alone (Model = accurate, Bodies = suture): the Cosserat rod of
 * rod/ with its loads and end motions, integrated by the registered rod integrator of
 * Time/Integrator (quasi-static load stepping or generalized-α dynamics), recorded by
 * scene/suture_recorder.h.
 */
#include <suturesim/rod/rod_integrator.h>
#include <suturesim/scene/scenario.h>
#include <suturesim/scene/suture_recorder.h>
#include <suturesim/scene/timed_run.h>

#include <sstream>

namespace suturesim::scene
{
  using namespace dealii;

  namespace
  {
    class AccurateSuture : public Scenario
    {
    public:
      AccurateSuture(ParameterHandler &prm, SceneParameters &s)
        : scene(s)
      {
        scene.scope("Closure").require(!scene.closure.present(), "Gap probes",
                                       "wound closure needs the suture in the tissue: Bodies = tissue and suture");
        scene.scope("Needle").require(!scene.needle.present(), "Shape",
                                      "the needle needs the tissue (Bodies = tissue, or tissue and suture)");
        scene.parse_bodies(prm);
        for (const auto &[name, end] : {std::pair{"Suture/Start end", &scene.suture.start_end},
                                        std::pair{"Suture/Last end", &scene.suture.last_end}})
          scene.scope(name).require(end->grasp_time == 0, "Grasp time",
                                    "a grasp during the run is realtime only (Model = realtime)");
        scene.parse_time(prm);
        const ParameterScope time     = scene.scope("Time");
        const auto          &registry = rod::RodIntegrator::Registry::instance();
        const std::string   &name     = scene.time.integrator;
        time.require(registry.all().count(name) > 0, "Integrator",
                     "'" + name + "' does not integrate a suture; use " + registry.selection_pattern());
        time.require(scene.time.max_step_size <= scene.time.step_size, "Max step size",
                     "adaptive steps are for the tissue and the needle scenes; the suture alone steps by Step size");
        if (name != "quasi-static")
          scene.scope("Suture/Cross section")
            .require(scene.suture.section.density > 0, "Density",
                     "must be > 0 kg/m^3 for dynamics (Time/Integrator = " + name + ")");
        prm.enter_subsection("Time");
        integrator = registry.get(name).create(prm, time);
        prm.leave_subsection();
      }

      void
      run(io::Recorder &recorder) override
      {
        run_timed(recorder, [&](TimerOutput &timer, ConditionalOStream &pcout) {
          std::ostringstream what;
          what << " (" << scene.suture.centreline << "), EI = " << scene.suture.section.stiffness().moment[1]
               << " N m^2, " << scene.time.integrator;
          SutureRun          suture(scene, recorder, pcout, what.str());
          TimerOutput::Scope section(timer, "suture");
          integrator->run(suture.problem, suture.observer);
        });
      }

    private:
      SceneParameters                    &scene;
      std::unique_ptr<rod::RodIntegrator> integrator;
    };

    const bool registered = Scenario::Registry::instance().add(
      {"accurate suture",
       "the Cosserat-rod suture alone, quasi-static or dynamic (Model = accurate, Bodies = suture)",
       nullptr,
       [](const SceneParameters &s) { return s.model == "accurate" && s.bodies == "suture" && s.knot.knot == "none"; },
       [](ParameterHandler &prm, SceneParameters &s) { return std::unique_ptr<Scenario>(new AccurateSuture(prm, s)); }});
  } // namespace
} // namespace suturesim::scene
