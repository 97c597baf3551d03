#pragma once
/**
 * @file
 * The realtime model path of a scene (`Model = realtime`): the "Realtime" subsection
 * (tissue model, integrator, suture model and self-collision, each chosen from its
 * registry with its own parameters; haptic rate, substeps, contact, stability policy),
 * and the run of a realtime::World from the scene's other subsections:
 *  - Mesh: the same gmsh file as the accurate path, read as tetrahedra;
 *  - Tissue/Material: E and ν from the shear and bulk moduli of the small-strain limit,
 *    ρ from the density; Tissue/Boundary conditions: fixed and prescribed boundaries
 *    hold their surface nodes, tractions become nodal loads, gravity acts on every node;
 *    Tissue/Probes: interpolated displacements;
 *  - Suture: centreline, section (EA, EI, radius, density) and ends: an end whose frame
 *    is fixed (clamped, or prescribed with rotations) is a tool holding its two end
 *    nodes (a grasper fixes position and direction); a pinned end, or one prescribed by
 *    displacements only, a tool holding one;
 *  - Time: End time and Output interval (Step size and Integrator are the accurate
 *    path's; the realtime step is 1/Rate split into Substeps).
 * Outputs: forces.csv every haptic step (tool forces, boundary reactions, probes,
 * energies), tissue.pvd and suture.pvd at the output interval, summary.json with the
 * step-time statistics of the haptic loop.
 */

#include <suturesim/io/recorder.h>
#include <suturesim/mesh/mesh_loader.h>
#include <suturesim/realtime/integrator.h>
#include <suturesim/core/model_parameters.h>
#include <suturesim/realtime/suture_model.h>
#include <suturesim/realtime/tissue_model.h>
#include <suturesim/rod/rod_parameters.h>
#include <suturesim/scene/needle_parameters.h>
#include <suturesim/scene/wound_closure.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/tissue/boundary_conditions.h>
#include <suturesim/tissue/material.h>
#include <suturesim/tissue/time_integrator.h>

#include <deal.II/base/parameter_handler.h>

#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace suturesim::scene
{
  /// What the realtime path reads from the scene's shared subsections.
  struct RealtimeInputs
  {
    std::string                                       scene_name;
    bool                                              tissue = false, suture = false;
    const mesh::MeshParameters                       *mesh = nullptr;
    const tissue::Material                           *material = nullptr;
    tissue::BoundaryConditions                       *boundary_conditions = nullptr;
    std::vector<std::pair<std::string, dealii::Point<3>>> probes;
    std::vector<tissue::TissueParameters::RegionModuli> region_moduli;
    const rod::RodParameters                         *rod = nullptr;
    const NeedleParameters                           *needle = nullptr; ///< nullptr or shape none: no needle
    const ClosureParameters                          *closure = nullptr; ///< nullptr: no closure measurement
    const tissue::TimeParameters                     *time = nullptr;
  };

  class RealtimeScene
  {
  public:
    /// Declares the entries of the current subsection ("Realtime").
    static void
    declare(dealii::ParameterHandler &prm);

    /// Parses the current subsection ("Realtime") and builds the chosen models, so that
    /// --validate reports every bad value (InputError naming file, line and key).
    RealtimeScene(dealii::ParameterHandler &prm, const ParameterScope &scope, RealtimeInputs inputs);
    ~RealtimeScene();

    /// Runs the scene into @p recorder. InputError for input found bad only now (mesh,
    /// boundary names, probes, a step above the stability limit under "refuse");
    /// SolverError when the divergence guard stops the run (the outputs hold the last
    /// good state).
    void
    run(io::Recorder &recorder);

  private:
    ParameterScope scope;
    RealtimeInputs in;

    std::string                            tissue_name, integrator_name, suture_name;
    std::string                            self_collision_name, pierce_model_name;
    ParameterValues              self_collision_values;
    std::unique_ptr<realtime::TissueModel> tissue_model;
    std::unique_ptr<realtime::Integrator>  integrator;
    std::unique_ptr<realtime::SutureModel> suture_model;
    bool                                   contact = true;
    double                                 contact_stiffness = 0, contact_depth = 0;
    double                                 rate = 1000;
    unsigned                               substeps = 1;
    bool                                   refuse_above_limit = false, pacing = false;
  };
} // namespace suturesim::scene
