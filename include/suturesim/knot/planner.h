#pragma once
/**
 * @file
 * Seed 002's knot planner (§5 B–C): it ties a knot by moving one end of the rope (the
 * last node; the first is held) through a list of instructions, each "the type of
 * crossing: which end of the suture to move, cross over or under" and the target span,
 * counted from the held end in the rope's current diagram (knot/diagram.h).
 *
 * Per step, as the seed lists its "four actions per timestep":
 *  1. check whether a new target is needed: the diagram has one crossing more than when
 *     the instruction began, the moving end's strand over (or under) as instructed and
 *     the other strand in the target span; then the next instruction is loaded. Any
 *     other change of the diagram (a crossing made the wrong way, or by another strand),
 *     an instruction that takes longer than the instruction time, or the end's link
 *     stretched by more than 10 % (the rope behind the end held, not following it) fails
 *     the plan, which then holds the end where it is and says why;
 *  2. the target point: the middle of the target span T, raised (over) or lowered
 *     (under) by the clearance c along the plane's normal n;
 *  3. the direction, the sum of the seed's four factors: (1) the straight line to T in
 *     the plane, (2) the shortest way to the line through T perpendicular to the target
 *     link ("most crossings should be at right angles to the target link"), (3) the
 *     height to go, n clamp((h* − n·p)/c, −1, 1), and (4) the rope's orientation at the
 *     end (its last link), "used for inertia, … the most significant; the other three
 *     are equal in magnitude": (1)–(3) are unit vectors, (4) is weighted by W > 1;
 *  4. the end moves along it at the planner's speed.
 * The seed's "obstructing link" target (a strand lying between the end and the target
 * span) is not modelled: such a crossing fails the plan with its reason.
 *
 * After the last instruction the end is pulled away from the knot (in the plane, along
 * the line from the crossings' centroid to the end) to tighten it, until it has moved
 * the tightening distance or the rope pulls back with the tightening force. A knot whose
 * diagram, after the Reidemeister reductions, has fewer crossings than the plan's (each
 * instruction one crossing of a minimal diagram: the knot's crossing number) while it is
 * pulled fails the plan: it came undone, the strands of a rope that cannot hold a tight
 * knot passing through each other. Other changes of the code (the knot seen from its
 * other side, a Reidemeister III move) are not failures; metrics.knot.tied reads the
 * last state.
 *
 * Knots (instructions derived in docs/knots.md from the Gauss codes):
 *  - overhand (trefoil): under span 0 (a loop), over span 1 (into the loop), under span 2
 *    (out of it);
 *  - figure-eight: over span 0 (a loop), under span 0 (behind the standing part), over
 *    span 2, under span 2 (down through the loop);
 *  - cinquefoil (the (2, 5) torus knot): the overhand's three, then over span 3 and under
 *    span 4 (the end round the loop's strand once more).
 * tied_code() gives the Gauss code the instructions tie, derived from them alone: each
 * crossing's first occurrence goes into its target span, its second (the moving end's)
 * to the end of the rope.
 */

#include <suturesim/knot/diagram.h>
#include <suturesim/knot/planner_settings.h>

#include <Eigen/Core>

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace suturesim::knot
{
  struct Instruction
  {
    bool        over = false; ///< the moving end passes over the target span
    std::size_t span = 0;     ///< counted from the held end, in the diagram of the moment
    double      at   = 0.5;   ///< where in the span the target lies, 0: its start, 1: its end
  };

  /// The instructions of knot @p name ("overhand", "figure-eight", "cinquefoil"); std::invalid_argument
  /// for another name.
  std::vector<Instruction>
  instructions(const std::string &name);

  /// The Gauss code @p instructions tie in a rope whose diagram had no crossing.
  GaussCode
  tied_code(const std::vector<Instruction> &instructions);

  class KnotPlanner
  {
  public:
    enum class Phase
    {
      waiting,
      tying,
      tightening,
      done,
      failed
    };
    struct Event
    {
      double      time = 0;
      std::size_t instruction = 0; ///< completed: 1, 2, …
      std::string code;            ///< the diagram's Gauss code then
    };

    explicit KnotPlanner(const PlannerSettings &settings);

    /// Where the moving end goes in the step from @p t − @p dt to @p t (m): @p rope holds
    /// the rope's nodes (m), its last column the moving end; @p end_force the force
    /// magnitude the rope pulls the end with (N).
    Eigen::Vector3d
    move(const Eigen::Matrix3Xd &rope, double t, double dt, double end_force);

    Phase
    phase() const
    {
      return phase_;
    }
    static std::string
    name(Phase phase);
    std::size_t
    instructions_done() const
    {
      return stage;
    }
    const std::vector<Instruction> &
    plan() const
    {
      return plan_;
    }
    /// Why the plan failed (empty unless it did).
    const std::string &
    failure() const
    {
      return failure_;
    }
    /// When it failed, s.
    double
    failure_time() const
    {
      return failed_at;
    }
    const std::vector<Event> &
    events() const
    {
      return events_;
    }
    /// How far the end has been pulled to tighten the knot, m.
    double
    shortening() const
    {
      return pulled;
    }
    const PlannerSettings &
    settings() const
    {
      return settings_;
    }
    const Projection &
    projection() const
    {
      return projection_;
    }

  private:
    /// Step 1: advances the plan or fails it on the diagram @p d at @p t.
    void
    check(const KnotDiagram &d, double t);
    /// Steps 2–3: the unit direction the end moves in.
    Eigen::Vector3d
    tying_direction(const KnotDiagram &d, const Eigen::Matrix3Xd &rope) const;
    void
    fail(const std::string &why, double t);

    PlannerSettings          settings_;
    Projection               projection_;
    std::vector<Instruction> plan_;
    Phase                    phase_ = Phase::waiting;
    std::size_t              stage  = 0;
    double                   stage_start = 0;
    std::vector<double>      bounds; ///< the spans of the last step's diagram
    Eigen::Vector3d          end = Eigen::Vector3d::Zero(), pull = Eigen::Vector3d::Zero();
    double                   pulled = 0;
    double                   link   = 0; ///< the end's link length when the planner started, m
    std::string              failure_;
    double                   failed_at = 0;
    std::vector<Event>       events_;
  };

  /// What @p planner did and what the rope @p rope (m; the run's last state) shows, for
  /// summary.json's metrics.knot: the knot's crossings and Gauss code in the planner's
  /// projection after the Reidemeister reductions (raw_*: before them), the code the
  /// plan ties and whether they agree ("tied"), where the raw code's crossings lie
  /// (crossing_points, m, in the order of their labels), the phase, the instructions
  /// done, the failure, the shortening.
  nlohmann::json
  knot_metrics(const KnotPlanner &planner, const Eigen::Matrix3Xd &rope);

  /// What knot_metrics() reads from the diagram alone: crossings and Gauss code after
  /// the reductions and raw, the knot determinant (GaussCode::determinant()), the
  /// projection's normal, the raw crossings' points.
  nlohmann::json
  diagram_metrics(const Eigen::Matrix3Xd &rope, const Projection &projection);
  /// The planner's events for summary.json (kind "knot_crossing": time, instruction,
  /// the diagram's Gauss code).
  nlohmann::json
  knot_events(const KnotPlanner &planner);
} // namespace suturesim::knot
