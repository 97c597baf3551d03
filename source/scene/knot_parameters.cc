#include <suturesim/scene/knot_parameters.h>
#include <suturesim/scene/scene_parameters.h>

#include <suturesim/knot/planner.h>

namespace suturesim::scene
{
  using namespace dealii;

  namespace
  {
    std::string
    vector_text(const Eigen::Vector3d &v)
    {
      return shortest_text(v[0]) + ", " + shortest_text(v[1]) + ", " + shortest_text(v[2]);
    }
  } // namespace

  void
  KnotParameters::declare(ParameterHandler &prm)
  {
    const knot::PlannerSettings d;
    prm.enter_subsection("Knot");
    std::string names = "none";
    for (const auto &k : knot::planned_knots())
      names += "|" + k;
    names += "|custom";
    prm.declare_entry("Knot", d.knot, Patterns::Selection(names),
                      "The knot seed 002's planner ties by moving the suture's last end (Suture/Last end/Type = "
                      "pinned) while the first is held: 'overhand' (the trefoil), 'figure-eight', 'cinquefoil' (the "
                      "overhand's end taken round once more: the (2, 5) torus knot); or by moving each end in turn "
                      "(both pinned), in a suture laid as a U with both ends up: 'square' (reef knot) and 'granny' "
                      "(two half knots, the second the first's mirror image or not), 'surgeon' (the square knot with "
                      "its first half knot doubled); 'custom': the plan given in "
                      "Instructions; or 'none'. In a stitch (realtime) the needle holds the first end and the "
                      "planner moves the needle. Unit: none. Range: " +
                        Utilities::replace_in_string(names, "|", ", ") + ".");
    prm.declare_entry("Instructions", "", Patterns::Anything(),
                      "The plan when Knot = custom: instructions separated by ';', each '[first|last] over|under "
                      "<span> [at <fraction>] [draw <metres>]': which end moves (default last), whether it passes "
                      "over or under the target span, the span counted from the held end in the diagram of the "
                      "moment (0 to twice the crossings made so far), where in the span it aims (default 0.5), "
                      "and how far the end is drawn from the knot once it has crossed (default 0). E.g. 'under 0; "
                      "over 1; under 2' ties the overhand. Each instruction must add a crossing that Reidemeister "
                      "moves cannot remove. Given with a named knot or none, it is an error. Unit: span none, fraction none, draw m. "
                      "Range: 1-32 instructions; fraction [0, 1]; draw [0, 1] m.");
    prm.declare_entry("Projection normal", vector_text(d.normal), vector_pattern(),
                      "Normal of the plane the suture is projected onto to read its crossings and spans (seed 002 "
                      "sec. 5 A) when Projection plane = given; 'over' is along it. Unit: none (a direction, not "
                      "zero).");
    prm.declare_entry("Projection plane", "given", Patterns::Selection("given|pierce points"),
                      "The plane the suture is projected onto: 'given' (Projection normal), or in a stitch "
                      "'pierce points', the plane through the needle's last three pierce points when the planner "
                      "starts (seed 002 sec. 5 A), its normal (p2 - p1) x (p3 - p1) in the order the needle made "
                      "them. Unit: none. Range: given, pierce points.");
    prm.declare_entry("Speed", default_text(d.speed), Patterns::Double(0),
                      "Speed of the moving end. Unit: m/s. Range: > 0.");
    prm.declare_entry("Clearance", default_text(d.clearance), Patterns::Double(0),
                      "Height over (or under) the target span the end aims at when it crosses it. Unit: m. Range: "
                      "> 0.");
    prm.declare_entry("Inertia weight", default_text(d.inertia), Patterns::Double(0),
                      "Weight W of seed 002's fourth factor, the rope's orientation at the end, against the other "
                      "three (unit vectors). Unit: none. Range: >= 0.");
    prm.declare_entry("First end inertia weight", default_text(d.first_end_inertia), Patterns::Double(-1),
                      "W for the first end while the planner moves it, when it should differ from Inertia weight "
                      "(in a stitch the first end is the needle's, moved by its driver, not a thread's end that "
                      "its rope steers); -1: Inertia weight. Unit: none. Range: >= 0, or -1.");
    prm.declare_entry("Start time", default_text(d.start_time), Patterns::Double(0),
                      "When the planner starts moving the end: not earlier than the last end's Grasp time and "
                      "last keyframe, nor, in a stitch, than the end of the needle's motion. Unit: s. Range: >= 0.");
    prm.declare_entry("Instruction time", default_text(d.instruction_time), Patterns::Double(0),
                      "The longest one instruction (one crossing) may take before the plan fails. Unit: s. Range: "
                      "> 0.");
    prm.declare_entry("Tighten distance", default_text(d.tighten_distance), Patterns::Double(0),
                      "How far the end is pulled away from the knot once tied. Unit: m. Range: >= 0.");
    prm.declare_entry("Tighten force", default_text(d.tighten_force), Patterns::Double(0),
                      "The tightening stops early when the suture pulls the end back with this force; 0: no limit. "
                      "Unit: N. Range: >= 0.");
    prm.leave_subsection();
  }

  knot::PlannerSettings
  KnotParameters::parse(const ParameterHandler &prm, const ParameterScope &scope)
  {
    knot::PlannerSettings s;
    s.knot             = prm.get("Knot");
    s.normal           = get_vector(prm, "Projection normal");
    s.plane_from_pierce_points = prm.get("Projection plane") == "pierce points";
    s.speed            = prm.get_double("Speed");
    s.clearance        = prm.get_double("Clearance");
    s.inertia          = prm.get_double("Inertia weight");
    s.first_end_inertia = prm.get_double("First end inertia weight");
    s.start_time       = prm.get_double("Start time");
    s.instruction_time = prm.get_double("Instruction time");
    s.tighten_distance = prm.get_double("Tighten distance");
    s.tighten_force    = prm.get_double("Tighten force");
    // a plan given beside a named knot (or none) would be dropped without a word
    scope.require(s.knot == "custom" || prm.get("Instructions").find_first_not_of(" \t") == std::string::npos,
                  "Instructions", "is read only with Knot = custom, and Knot is '" + s.knot + "'");
    if (s.knot == "none")
      return s;
    if (s.knot == "custom")
      try
        {
          s.instructions = knot::parse_plan(prm.get("Instructions"));
        }
      catch (const std::invalid_argument &e)
        {
          scope.fail("Instructions", e.what());
        }
    scope.require(s.normal.norm() > 0, "Projection normal", "must not be zero");
    scope.require(s.first_end_inertia >= 0 || s.first_end_inertia == -1, "First end inertia weight",
                  "must be >= 0, or -1 for the Inertia weight");
    scope.require(s.speed > 0, "Speed", "must be > 0 m/s");
    scope.require(s.clearance > 0, "Clearance", "must be > 0 m");
    scope.require(s.instruction_time > 0, "Instruction time", "must be > 0 s");
    return s;
  }

  void
  KnotParameters::check(const SceneParameters &scene)
  {
    if (scene.knot.knot == "none")
      return;
    const ParameterScope knot = scene.scope("Knot");
    knot.require(scene.has_suture(), "Knot", "a knot needs a suture (Bodies = suture or tissue and suture)");
    const auto  &ends  = scene.suture;
    const double start = scene.knot.start_time;
    knot.require(ends.elements >= 2, "Knot", "the suture needs at least two elements");
    // the last end's grasper is the planner's from its start on, wherever it took the end
    // (realtime); the accurate rod's last node is the planner's from the start
    const bool realtime = scene.model == "realtime";
    knot.require(ends.last_end.type == "pinned" ||
                   (realtime && ends.last_end.type == "prescribed" && !ends.last_end.fixes_rotation()),
                 "Knot",
                 std::string("the planner moves the suture's last end: Suture/Last end/Type = pinned") +
                   (realtime ? ", or prescribed by displacements only" : ""));
    knot.require(realtime || ends.last_end.grasp_time == 0, "Knot",
                 "the planner moves the accurate suture's last end from the start: Suture/Last end/Grasp time = 0");
    knot.require(ends.last_end.grasp_time <= start &&
                   (ends.last_end.keyframes.empty() || ends.last_end.keyframes.rbegin()->first <= start),
                 "Start time",
                 "the planner takes the suture's last end from its grasper: the end's Grasp time and last keyframe "
                 "must not be after Knot/Start time (" + shortest_text(start) + " s)");
    knot.require(!scene.knot.plane_from_pierce_points || scene.needle.present(), "Projection plane",
                 "'pierce points' needs the stitch's needle (Needle/Shape); give the plane by Projection normal");
    if (scene.needle.present())
      {
        // a stitch tied off (realtime only: scenarios/accurate_needle.cc refuses a Knot): the
        // needle holds the first end at its swage, and the planner moves the needle
        // (translated, as the driver holds it) once its motion is over
        knot.require(scene.needle.attach_suture && !scene.needle.released(), "Knot",
                     "the planner moves the suture's first end with the needle: Needle/Attach suture = true, and "
                     "the driver holding the needle throughout (no Jaws, no Regrasp exposure)");
        const double motion_end = scene.needle.trajectory().end_time();
        knot.require(motion_end <= start, "Start time",
                     "the planner takes the needle over when its motion ends, at " + shortest_text(motion_end) +
                       " s: Knot/Start time must not be earlier");
        knot.require(!scene.closure.present() || !scene.closure.tie_off, "Knot",
                     "a stitch tied off with a knot does not hold its ends at the closure: Closure/Tie off = false");
        return;
      }
    knot.require(ends.start_end.type != "free", "Knot",
                 "the suture's first end must be held while the planner ties (Suture/Start end/Type = pinned, "
                 "clamped or prescribed)");
    knot.require((ends.start_end.type == "pinned" && ends.start_end.grasp_time == 0) ||
                   !knot::moves_first_end(knot::plan_of(scene.knot)),
                 "Knot",
                 "the planner moves both ends to tie a " + scene.knot.knot +
                   " knot: Suture/Start end/Type = pinned, grasped from the start");
  }
} // namespace suturesim::scene
