#pragma once
/**
 * @file
 * The "Knot" subsection of a scene: which knot seed 002's planner ties in the suture
 * (knot/planner.h), by moving the suture's last end (Suture/Last end/Type = pinned: the
 * grasper the planner moves) while the first is held, and how. Both paths read the same
 * file: the realtime world's grasper moves its rope's end (scene/realtime_world.h), the
 * accurate path's Cosserat rod has its last node moved (scene/scenarios/accurate_knot.cc).
 */

#include <suturesim/core/model_parameters.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/knot/planner_settings.h>

#include <deal.II/base/parameter_handler.h>

namespace suturesim::scene
{
  struct SceneParameters;

  struct KnotParameters
  {
    static void
    declare(dealii::ParameterHandler &prm);
    /// Reads the current subsection "Knot".
    static knot::PlannerSettings
    parse(const dealii::ParameterHandler &prm, const ParameterScope &scope);
    /// Refuses a Knot in a scene whose suture the planner cannot tie (one line naming
    /// Knot/Knot): no suture, a needle, the last end not pinned from the start, the first
    /// end free, fewer than two elements. Either path, once the bodies are read.
    static void
    check(const SceneParameters &scene);
  };
} // namespace suturesim::scene
