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
  }

  void
  Simulation::run(io::Recorder &recorder)
  {
    scenario->run(recorder);
  }
} // namespace suturesim::scene
