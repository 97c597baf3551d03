#pragma once
/**
 * @file
 * The "Knot" subsection of a scene: which knot seed 002's planner ties in the suture
 * (knot/planner.h), by moving the suture's last end (Suture/Last end/Type = pinned: the
 * grasper the planner moves) while the first is held, and how. Both paths read the same
 * file; today only the realtime path ties (Model = accurate with a knot is refused).
 */

#include <suturesim/core/model_parameters.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/knot/planner_settings.h>

#include <deal.II/base/parameter_handler.h>

namespace suturesim::scene
{
  struct KnotParameters
  {
    static void
    declare(dealii::ParameterHandler &prm);
    /// Reads the current subsection "Knot"; @p model is the scene's Model.
    static knot::PlannerSettings
    parse(const dealii::ParameterHandler &prm, const ParameterScope &scope, const std::string &model);
  };
} // namespace suturesim::scene
