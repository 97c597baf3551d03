#include <suturesim/core/error.h>
#include <suturesim/rod/rod_integrator.h>
#include <suturesim/scene/simulation.h>
#include <suturesim/tissue/time_integrator.h>

namespace suturesim::scene
{
  using namespace dealii;

  void
  Simulation::declare_parameters(ParameterHandler &prm)
  {
    // the integrators of every body under one key, each with its own subsection
    std::map<std::string, std::string> integrators;
    for (const auto &[name, entry] : tissue::TimeIntegrator::Registry::instance().all())
      integrators[name] = "tissue: " + entry.description;
    for (const auto &[name, entry] : rod::RodIntegrator::Registry::instance().all())
      integrators[name] = integrators.count(name) ? integrators[name] + " Suture: " + entry.description
                                                  : "suture: " + entry.description;
    SceneParameters::declare(prm, integrators);
    prm.enter_subsection("Time");
    for (const auto &[name, entry] : tissue::TimeIntegrator::Registry::instance().all())
      if (entry.declare_parameters)
        entry.declare_parameters(prm);
    for (const auto &[name, entry] : rod::RodIntegrator::Registry::instance().all())
      if (entry.declare_parameters)
        entry.declare_parameters(prm);
    prm.leave_subsection();
    for (const auto &entry : Scenario::Registry::instance().all())
      if (entry.declare_parameters)
        entry.declare_parameters(prm);
  }

  Simulation::Simulation(ParameterHandler &prm, const ParameterFile &file)
  {
    scene.parse_common(prm, file);
    const auto *entry = Scenario::Registry::instance().find(scene);
    if (entry == nullptr)
      scene.scope().fail("Bodies", "no scenario runs Model = " + scene.model + " with Bodies = " + scene.bodies +
                                     (scene.needle.present() ? " and a needle" : ""));
    scenario = entry->create(prm, scene);
    if (!scenario->writes_checkpoints())
      {
        prm.enter_subsection("Time");
        const bool by_steps = prm.get_integer("Checkpoint steps") > 0, by_time = prm.get_double("Checkpoint minutes") > 0;
        prm.leave_subsection();
        if (by_steps || by_time)
          scene.scope("Time").fail(by_steps ? "Checkpoint steps" : "Checkpoint minutes",
                                   "only the accurate needle pass and stitch write checkpoints so far; this scene is "
                                   "the " + entry->name + " scenario");
      }
  }

  void
  Simulation::run(io::Recorder &recorder)
  {
    if (recorder.resuming() && !scenario->writes_checkpoints())
      throw InputError("--restart " + recorder.directory() + ": this scene's scenario cannot go on from a checkpoint");
    scenario->run(recorder);
  }
} // namespace suturesim::scene
