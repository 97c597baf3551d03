#pragma once
/**
 * @file
 * A scene: its parameters (declared by each component into its own subsection), their
 * checks, and the run of the chosen model path into a Recorder. Model paths: "accurate"
 * (finite-strain FE tissue, Cosserat-rod suture) and "realtime" (RealtimeScene). Bodies:
 * the tissue alone, the suture alone, or both (realtime only until the accurate path has
 * the pierce points).
 */

#include <suturesim/io/recorder.h>
#include <suturesim/mesh/mesh_loader.h>
#include <suturesim/rod/rod_integrator.h>
#include <suturesim/rod/rod_parameters.h>
#include <suturesim/scene/needle_parameters.h>
#include <suturesim/scene/wound_closure.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/scene/realtime_scene.h>
#include <suturesim/tissue/boundary_conditions.h>
#include <suturesim/tissue/material.h>
#include <suturesim/tissue/time_integrator.h>
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/timer.h>

#include <memory>
#include <optional>
#include <string>

namespace suturesim::scene
{
  class Simulation
  {
  public:
    static void
    declare_parameters(dealii::ParameterHandler &prm);

    /// Parses and checks every parameter (InputError on the first bad one). Mesh-
    /// dependent checks (boundary names, probes) happen in run().
    Simulation(dealii::ParameterHandler &prm, const ParameterFile &file);

    /// Runs the scene; fills and finishes the recorder's summary. Throws InputError for
    /// input found bad only now and SolverError for a failed solve.
    void
    run(io::Recorder &recorder);

    const std::string &
    name() const
    {
      return scene_name;
    }

  private:
    void
    parse_realtime(dealii::ParameterHandler &prm);
    void
    run(io::Recorder &recorder, dealii::TimerOutput &timer, dealii::ConditionalOStream &pcout);
    void
    run_suture(io::Recorder &recorder, dealii::TimerOutput &timer, dealii::ConditionalOStream &pcout);

    const ParameterFile              &file;
    std::string                        scene_name;
    std::string                        model_path;
    std::string                        bodies;
    rod::RodParameters                 rod_parameters;
    NeedleParameters                   needle_parameters;
    ClosureParameters                  closure_parameters;
    std::unique_ptr<rod::RodIntegrator> rod_integrator;
    mesh::MeshParameters               mesh_parameters;
    tissue::TissueParameters           tissue_parameters;
    std::optional<tissue::Material>    material;
    tissue::BoundaryConditions         boundary_conditions;
    tissue::TimeParameters             time_parameters;
    std::unique_ptr<tissue::TimeIntegrator> integrator;
    std::unique_ptr<RealtimeScene>          realtime;
  };
} // namespace suturesim::scene
