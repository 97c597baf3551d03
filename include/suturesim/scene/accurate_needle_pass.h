#pragma once
/**
 * @file
 * The needle in the accurate path (Model = accurate, Bodies = tissue): quasi-static
 * steps along the needle's trajectory, each a Newton solve of the FE tissue with the
 * needle's loads at embedded material points (coupling/accurate/tissue_needle.h).
 *  - A step whose Newton solve fails is halved (Time/Max cutbacks in a row) and the
 *    needle's state with it; the run stops with the reason, keeping the last converged
 *    state on disk.
 *  - A step that would carry the touch force past 1.04 × the puncture threshold is
 *    halved too, so that the puncture lands within 4 % above the threshold.
 *  - Penalty enforcement only, so far.
 * Records as the realtime path does (scene/realtime_needle.h): forces.csv columns for
 * the needle force, torque and arc centre and per pierce point its state, ζ, slip
 * velocity, normal and friction force; summary.json events and puncture / pull metrics.
 */

#include <suturesim/io/recorder.h>
#include <suturesim/mesh/mesh_loader.h>
#include <suturesim/scene/needle_parameters.h>
#include <suturesim/tissue/boundary_conditions.h>
#include <suturesim/tissue/material.h>
#include <suturesim/tissue/time_integrator.h>
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

namespace suturesim::scene
{
  struct AccurateNeedleInputs
  {
    std::string                       scene_name, scene_file;
    const mesh::MeshParameters       *mesh     = nullptr;
    const tissue::TissueParameters   *tissue   = nullptr;
    const tissue::Material           *material = nullptr;
    tissue::BoundaryConditions       *boundary_conditions = nullptr;
    const tissue::TimeParameters     *time   = nullptr;
    const NeedleParameters           *needle = nullptr;
  };

  /// Runs the scene into @p recorder; SolverError when a step fails after every
  /// cut-back (the last converged state is on disk).
  void
  run_accurate_needle_pass(const AccurateNeedleInputs &in, io::Recorder &recorder,
                           dealii::TimerOutput &timer, dealii::ConditionalOStream &pcout);
} // namespace suturesim::scene
