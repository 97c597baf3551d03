#pragma once
/**
 * @file
 * A scene run: its parameters declared (every component into its own subsection, every
 * registered scenario its own), parsed and checked, the registered scenario that runs
 * the scene chosen (scene/scenario.h) and run into a Recorder.
 */

#include <suturesim/core/parameter_file.h>
#include <suturesim/io/recorder.h>
#include <suturesim/scene/scenario.h>
#include <suturesim/scene/scene_parameters.h>

#include <deal.II/base/parameter_handler.h>

#include <memory>
#include <string>

namespace suturesim::scene
{
  class Simulation
  {
  public:
    static void
    declare_parameters(dealii::ParameterHandler &prm);

    /// Parses and checks every parameter (InputError on the first bad one) and builds
    /// the scenario. Mesh-dependent checks (boundary names, probes) happen in run().
    Simulation(dealii::ParameterHandler &prm, const ParameterFile &file);

    /// Runs the scene; fills the recorder's summary. Throws InputError for input found
    /// bad only now and SolverError for a failed solve.
    void
    run(io::Recorder &recorder);

    const std::string &
    name() const
    {
      return scene.name;
    }

  private:
    SceneParameters           scene;
    std::unique_ptr<Scenario> scenario;
  };
} // namespace suturesim::scene
