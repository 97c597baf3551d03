#pragma once
/**
 * @file
 * The needle in the accurate path (Model = accurate, Bodies = tissue, or tissue and
 * suture): quasi-static steps along the needle's trajectory, each a Newton solve of the
 * FE tissue with the needle's loads at embedded material points
 * (coupling/accurate/tissue_needle.h).
 *  - With the suture (Bodies = tissue and suture, Needle/Attach suture): a Cosserat rod
 *    (rod/rod_model.h) clamped at the swage (position and frame move with the needle:
 *    the hard constraint of seed 002), its far end free or held by a grasper from its
 *    Grasp time on. Pierce points pass onto it at the swage and slide along it with the
 *    same friction law. Tissue and suture are solved in turn (block Gauss–Seidel) until
 *    neither the pierced tissue points nor the suture's nodes move by more than
 *    Pierce points/Coupling tolerance between two rounds (the suture sees the tissue
 *    points under Aitken relaxation); a step that does not converge
 *    in Coupling iterations rounds is halved like a failed Newton solve. No contact
 *    between the suture and the tissue's surface outside the pierce points yet.
 *  - A step whose Newton solve fails is halved (Time/Max cutbacks in a row) and the
 *    needle's state with it; the run stops with the reason, keeping the last converged
 *    state on disk.
 *  - A step that would carry the touch force past 1.04 × the puncture threshold is
 *    halved too, so that the puncture lands within 4 % above the threshold.
 *  - Closure (scene/wound_closure.h): the gap probes join the tissue's probes; gaps,
 *    closure tension (the grasper's reaction on the suture's far end, else the needle's
 *    pull) and the tie-off that stops the needle's and the far end's motions.
 *  - Enforcement = lagrange adds the multipliers' Uzawa update to each round
 *    (coupling/accurate/tissue_needle.h); a step converges once, besides, no tie gapes
 *    by more than the coupling tolerance.
 * Records as the realtime path does (scene/realtime_needle.h): forces.csv columns for
 * the needle force, torque and arc centre and per pierce point its state, ζ, slip
 * velocity, normal and friction force; summary.json events and puncture / pull metrics.
 */

#include <suturesim/io/recorder.h>
#include <suturesim/mesh/mesh_loader.h>
#include <suturesim/rod/rod_parameters.h>
#include <suturesim/scene/needle_parameters.h>
#include <suturesim/scene/wound_closure.h>
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
    const rod::RodParameters         *suture = nullptr; ///< attached at the swage when given
    const ClosureParameters          *closure = nullptr; ///< wound gaps, closure and tie-off
  };

  /// Runs the scene into @p recorder; SolverError when a step fails after every
  /// cut-back (the last converged state is on disk).
  void
  run_accurate_needle_pass(const AccurateNeedleInputs &in, io::Recorder &recorder,
                           dealii::TimerOutput &timer, dealii::ConditionalOStream &pcout);
} // namespace suturesim::scene
