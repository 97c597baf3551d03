#pragma once
/**
 * @file
 * What a scene sets of seed 002's knot planner (knot/planner.h; scene subsection Knot,
 * scene/knot_parameters.h), apart from the planner itself, so that the scene's
 * parameters do not depend on how the planner works.
 */

#include <Eigen/Core>

#include <string>
#include <vector>

namespace suturesim::knot
{
  /// One instruction of a plan (seed 002 §5 C: "the type of crossing: which end of the
  /// suture to move, cross over or under", and the target span).
  struct Instruction
  {
    bool        over = false; ///< the moving end passes over the target span
    std::size_t span = 0;     ///< counted from the held end, in the diagram of the moment
    double      at   = 0.5;   ///< where in the span the target lies, 0: its start, 1: its end
    /// The first end moves (and the last is held) instead of the last: the spans are then
    /// counted from the last end, and the rope is read from it
    bool first_end = false;
    /// Once this crossing is made, the end is drawn this far (m) away from the knot
    /// before the next instruction begins (a throw snugged down, and a tail for the next
    /// to go round), as the knot is pulled once tied; 0: at once.
    double draw = 0;
  };

  /// The knot the planner ties and how it moves the end (scene subsection Knot).
  struct PlannerSettings
  {
    /// none, custom (the plan is `instructions`) or one of knot::planned_knots()
    std::string knot = "none";
    /// The scene's own plan (Knot = custom; knot::parse_plan()); empty for a named knot,
    /// whose plan is knot::instructions(knot): knot::plan_of() gives either
    std::vector<Instruction> instructions;
    Eigen::Vector3d normal{0, 0, 1};         ///< projection plane's normal
    /// The plane through the stitch's last three pierce points when the planner starts
    /// (seed 002 §5 A), its normal (p₂ − p₁) × (p₃ − p₁) in the order they were made,
    /// instead of `normal` (KnotPlanner::set_normal(); a realtime stitch)
    bool plane_from_pierce_points = false;
    double          speed            = 0.02; ///< of the moving end, m/s
    double          clearance        = 3e-3; ///< height over or under the target, m
    double          inertia          = 2;    ///< W, weight of factor (4)
    /// W for the first end while it moves, when it differs (a needle held by its driver
    /// rather than a thread's end); negative: `inertia`
    double first_end_inertia = -1;
    double          start_time       = 0;    ///< s
    double          instruction_time = 10;   ///< the longest an instruction may take, s
    double          tighten_distance = 0;    ///< m
    double          tighten_force    = 0;    ///< N; 0: none
  };
} // namespace suturesim::knot
