#pragma once
/**
 * @file
 * Seed 002's knot planner (§5 B–C): it ties a knot by moving one end of the rope (the
 * last node, or the first; the other is held) through a list of instructions, each "the
 * type of crossing: which end of the suture to move, cross over or under" and the target
 * span, counted from the held end in the rope's current diagram (knot/diagram.h). The
 * planner reads the rope from the held end, so that what follows holds for either end.
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
 *     are equal in magnitude": (1)–(3) are unit vectors, (4) is weighted by W > 1
 *     (the first end may have its own W: PlannerSettings::first_end_inertia);
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
 *    span 4 (the end round the loop's strand once more);
 *  - square knot (reef knot; the trefoil and its mirror image, 3₁ # 3₁*) and granny knot
 *    (3₁ # 3₁), tied in a rope laid as a U (the two ends up, as a stitch's two ends leave
 *    the tissue): the last end makes a half knot round the first end's strand (over
 *    span 0, under span 1, over its own standing part, span 2), then the first end one
 *    round the last's, over span 0, under span 1 and over span 8 (its own standing part)
 *    for the square knot, under, over and under for the granny knot. Reading the rope
 *    closed through its tails, each half knot is a trefoil; the second is the first's
 *    mirror image in the plane (the square knot), or that turned over (the granny).
 *  - surgeon's knot (5₁ # 3₁*): the square knot with its first half knot doubled, the
 *    last end round the first end's strand twice (over 0, under 1, over 2, under 3,
 *    over 4), then the first end's half knot (over 0, under 1, over 12, its own standing
 *    part); determinant 5 × 3, writhe ±2 (5 − 3).
 *  - custom: a scene's own plan (Knot/Instructions, parse_plan()), for a knot not listed
 *    or another way to tie one.
 * tied_code() gives the Gauss code the instructions tie, derived from them alone: each
 * crossing's first occurrence (read from the held end) goes into its target span, its
 * second (the moving end's) to the end of the rope.
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
  /// Where the planner sends the rope's two ends, m.
  struct Ends
  {
    Eigen::Vector3d first = Eigen::Vector3d::Zero(), last = Eigen::Vector3d::Zero();
  };

  /// The knots instructions() has a plan for: overhand, figure-eight, cinquefoil, square,
  /// granny, surgeon.
  const std::vector<std::string> &
  planned_knots();

  /// The instructions of knot @p name (one of planned_knots()); std::invalid_argument for
  /// another name.
  std::vector<Instruction>
  instructions(const std::string &name);

  /// The plan @p settings ask for: their own instructions (Knot = custom), or those of the
  /// named knot (instructions()).
  std::vector<Instruction>
  plan_of(const PlannerSettings &settings);

  /// A plan written as text, instructions separated by ';', each
  /// `[first|last] over|under <span> [at <fraction>] [draw <metres>]` (the last end, at
  /// 0.5 and no draw unless said), e.g. "under 0; over 1; under 2" (the overhand).
  /// std::invalid_argument naming the instruction and what is wrong with it: an unknown
  /// word, a span past the rope's spans (tied_code()), a fraction outside [0, 1], a draw
  /// outside [0, 1] m, more than 32 instructions, none, or a plan whose code is not
  /// reduced (Reidemeister I or II moves remove crossings: each instruction must add a
  /// crossing the knot keeps, so that the planner can tell a knot come undone by its
  /// crossings).
  std::vector<Instruction>
  parse_plan(const std::string &text);

  /// @p plan written as parse_plan() reads it (every field given).
  std::string
  plan_text(const std::vector<Instruction> &plan);

  /// Whether any of @p plan's instructions moves the first end (else it is only held).
  bool
  moves_first_end(const std::vector<Instruction> &plan);

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

    /// Where the ends go in the step from @p t − @p dt to @p t (m): @p rope holds the
    /// rope's nodes (m), first to last; @p end_force the force magnitude the rope pulls
    /// the moving end with (N). The end that does not move stays where it was when the
    /// planner started, or where its last instruction left it.
    Ends
    move(const Eigen::Matrix3Xd &rope, double t, double dt, double end_force);

    /// Puts the projection plane's normal to @p normal (not zero) before the plan starts:
    /// a plane read from the scene at the start (PlannerSettings::plane_from_pierce_points);
    /// std::logic_error once it has started, std::invalid_argument for a zero normal.
    void
    set_normal(const Eigen::Vector3d &normal);

    /// Whether any instruction moves the first end (knot::moves_first_end()).
    bool
    moves_first_end() const
    {
      return knot::moves_first_end(plan_);
    }
    /// Whether the end moving now (or last, once tied) is the first.
    bool
    moving_first_end() const;

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
    /// Steps 2–3: the unit direction the end moves in, @p rope read from the held end.
    Eigen::Vector3d
    tying_direction(const KnotDiagram &d, const Eigen::Matrix3Xd &rope) const;
    /// After the last instruction: pulls the moving end away from the knot of diagram
    /// @p d (@p rope read from the held end) until far or strong enough.
    void
    tighten(const KnotDiagram &d, const Eigen::Matrix3Xd &rope, double dt, double end_force);
    /// Between instructions: draws the end Instruction::draw away from the knot; a
    /// change of the diagram meanwhile fails the plan.
    void
    draw(const KnotDiagram &d, const Eigen::Matrix3Xd &rope, double t, double dt);
    /// The direction in the plane from the knot's crossings to the moving end.
    Eigen::Vector3d
    away_from_knot(const KnotDiagram &d, const Eigen::Matrix3Xd &rope) const;
    void
    fail(const std::string &why, double t);
    /// Where the planner sends the end that moves now.
    Eigen::Vector3d &
    moving()
    {
      return moving_first_end() ? ends.first : ends.last;
    }

    PlannerSettings          settings_;
    Projection               projection_;
    std::vector<Instruction> plan_;
    Phase                    phase_ = Phase::waiting;
    std::size_t              stage  = 0;
    double                   stage_start = 0;
    std::vector<double>      bounds; ///< the spans of the last step's diagram, read from the held end
    Ends                     ends;
    Eigen::Vector3d          pull   = Eigen::Vector3d::Zero();
    double                   pulled = 0;
    double                   drawing = 0; ///< how far the end is still to be drawn, m
    double                   links[2] = {0, 0}; ///< the first and last links' lengths when it started, m
    std::string              failure_;
    double                   failed_at = 0;
    std::vector<Event>       events_;
  };

  /// What @p planner did and what the rope @p rope (m; the run's last state) shows, for
  /// summary.json's metrics.knot: the knot's crossings and Gauss code in the planner's
  /// projection after the Reidemeister reductions (raw_*: before them), the code the
  /// plan ties and whether they agree ("tied"), whether it moves the first end too
  /// (moves_first_end), where the raw code's crossings lie (crossing_points, m, in the
  /// order of their labels), the phase, the instructions done, the failure, the
  /// shortening.
  nlohmann::json
  knot_metrics(const KnotPlanner &planner, const Eigen::Matrix3Xd &rope);

  /// What knot_metrics() reads from the diagram alone: crossings and Gauss code after
  /// the reductions and raw, the knot determinant (GaussCode::determinant()), the
  /// reduced diagram's writhe (GaussCode::writhe()), the projection's normal, the raw
  /// crossings' points.
  nlohmann::json
  diagram_metrics(const Eigen::Matrix3Xd &rope, const Projection &projection);
  /// The planner's events for summary.json (kind "knot_crossing": time, instruction,
  /// the diagram's Gauss code).
  nlohmann::json
  knot_events(const KnotPlanner &planner);
} // namespace suturesim::knot
