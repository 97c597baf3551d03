#pragma once
/**
 * @file
 * What a scene sets of seed 002's knot planner (knot/planner.h; scene subsection Knot,
 * scene/knot_parameters.h), apart from the planner itself, so that the scene's
 * parameters do not depend on how the planner works.
 */

#include <Eigen/Core>

#include <string>

namespace suturesim::knot
{
  /// The knot the planner ties and how it moves the end (scene subsection Knot).
  struct PlannerSettings
  {
    std::string     knot = "none";           ///< none or one of knot::planned_knots()
    Eigen::Vector3d normal{0, 0, 1};         ///< projection plane's normal
    double          speed            = 0.02; ///< of the moving end, m/s
    double          clearance        = 3e-3; ///< height over or under the target, m
    double          inertia          = 2;    ///< W, weight of factor (4)
    double          start_time       = 0;    ///< s
    double          instruction_time = 10;   ///< the longest an instruction may take, s
    double          tighten_distance = 0;    ///< m
    double          tighten_force    = 0;    ///< N; 0: none
  };
} // namespace suturesim::knot
