#include <suturesim/collision/proximity.h>
#include <suturesim/core/parameter_adapter.h>
#include <suturesim/scene/needle_parameters.h>

#include <deal.II/base/utilities.h>

#include <limits>
#include <sstream>
#include <stdexcept>

namespace suturesim::scene
{
  using namespace dealii;

  namespace
  {
    std::string
    to_text(const Eigen::Vector3d &v)
    {
      return default_text(v[0]) + ", " + default_text(v[1]) + ", " + default_text(v[2]);
    }
  } // namespace

  tools::PassParameters
  NeedleParameters::default_pass()
  {
    tools::PassParameters p;
    p.bite_depth = 0.003;
    p.pull       = {0, 0, 0.03};
    return p;
  }

  void
  NeedleParameters::declare(ParameterHandler &prm)
  {
    declare_needle(prm);
    prm.enter_subsection("Puncture");
    ParameterDeclarations puncture;
    coupling::PunctureParameters::declare(puncture);
    declare_plain(prm, puncture);
    prm.leave_subsection();
    declare_pierce_points(prm);
  }

  void
  NeedleParameters::declare_needle(ParameterHandler &prm)
  {
    const NeedleParameters d;
    prm.enter_subsection("Needle");
    prm.declare_entry("Shape", d.shape, Patterns::Selection("none|3/8|1/2|double-pointed"),
                      "The suture needle: none; a curved needle, a 3/8 circle (135 degrees of arc) or a "
                      "1/2 circle (180 degrees); or double-pointed, the Endo Stitch's straight needle pointed at "
                      "both ends with the suture attached at its middle (seed 001 sec. 5; Length, Passes across; "
                      "realtime path, Motion = keyframes). Unit: none.");
    prm.declare_entry("Length", default_text(d.length), Patterns::Double(0),
                      "For Shape = double-pointed: the needle's length, point to point. Unit: m. Range: > 0.");
    prm.declare_entry("Passes across", d.passes_text,
                      Patterns::List(Patterns::Double(0), 0, Patterns::List::max_int_value, ";"),
                      "For Shape = double-pointed: when the Endo Stitch passes the needle to its other jaw, "
                      "'t; t; ...' (increasing). From each the other point leads: the needle turns half a turn "
                      "about its middle, whose frame Keyframes move (the device's: +y from the jaw that holds "
                      "the needle at the start towards the other). Then the needle must be out of the tissue, "
                      "with every hole it made on the suture. Unit: s. Range: >= 0.");
    prm.declare_entry("Arc radius", default_text(d.radius), Patterns::Double(0),
                      "Radius R of the needle's arc. Unit: m. Range: > 0.");
    prm.declare_entry("Wire diameter", default_text(d.wire_diameter), Patterns::Double(0),
                      "Diameter of the needle wire. Unit: m. Range: (0, R).");
    prm.declare_entry("Attach suture", default_text(d.attach_suture), Patterns::Bool(),
                      "The suture starts at the swage, leaving it along the needle's "
                      "tangent, held there in position and direction (seed 002's hard "
                      "constraint); the Suture subsection's Straight start point and "
                      "direction are then set from the needle. Unit: none.");
    prm.declare_entry("Motion", d.motion, Patterns::Selection("pass|keyframes"),
                      "pass: the standard surgical pass of subsection Pass (the needle "
                      "turns about its arc centre, then is pulled); keyframes: the poses of "
                      "Keyframes. Unit: none.");
    prm.declare_entry("Keyframes", d.keyframe_text,
                      Patterns::Map(Patterns::Double(0), Patterns::List(Patterns::Double(), 6, 6, ","), 1,
                                    Patterns::Map::max_int_value, ";", ":"),
                      "For Motion = keyframes: 't: cx, cy, cz, rx, ry, rz; ...', the arc "
                      "centre (m) and the rotation vector of the needle's frame (rad; in "
                      "the frame the arc lies in the x-y plane, swage on +x, tip at the arc "
                      "angle); positions linear and rotations by slerp between keyframes. "
                      "Unit: s: m, m, m, rad, rad, rad.");
    prm.declare_entry("Jaws", d.jaws_text,
                      Patterns::Map(Patterns::Double(0), Patterns::Selection("open|closed"), 0,
                                    Patterns::Map::max_int_value, ";", ":"),
                      "When the needle driver's jaws open and close, 't: open; t: closed; ...' "
                      "(closed at the start; empty: never open). While open the needle is a free "
                      "rigid body moved by the tissue's pierce points, the suture's pull and its "
                      "weight (seed 001 sec. 5-6), by the quasi-static law V = F/B; closing takes it "
                      "where it lies, relative to where the driver then is (Motion). Realtime path "
                      "under the quasi-static integrator. Unit: s: none.");
    prm.declare_entry("Density", default_text(d.density), Patterns::Double(0),
                      "Of the needle's wire, for its weight while free: 7800, the martensitic "
                      "stainless steels (type 420, 455) needles are made of. Unit: kg/m^3. Range: > 0.");
    prm.declare_entry("Drag", default_text(d.drag), Patterns::Double(0),
                      "B of the free needle in V = F/B (its rotation: B R^2 about the centroid); sets how "
                      "fast it settles, not where. Unit: N s/m. Range: > 0.");
    const tools::PassParameters &p = d.pass;
    prm.enter_subsection("Pass");
    prm.declare_entry("Entry point", to_text(p.entry), vector_pattern(),
                      "Where the tip enters the tissue surface. Unit: m.");
    prm.declare_entry("Surface normal", to_text(p.normal), vector_pattern(),
                      "Outward normal of the surface at the entry point. Unit: none. Range: non-zero.");
    prm.declare_entry("Bite direction", to_text(p.bite_direction), vector_pattern(),
                      "From the entry towards the exit (projected onto the surface). Unit: "
                      "none. Range: not along the normal.");
    prm.declare_entry("Bite depth", default_text(p.bite_depth), Patterns::Double(0),
                      "Depth delta the tip reaches below the surface; the entry angle is "
                      "then arccos(1 - delta/R). 0: use the entry angle. Unit: m. Range: "
                      "[0, R].");
    prm.declare_entry("Bite", default_text(p.bite), Patterns::Double(0),
                      "The stitch's bite b, from where it crosses the wound (Wound crossing) to the entry and "
                      "to the exit, symmetric: the entry is b before the crossing along Bite direction, the "
                      "exit b beyond it, the entry angle arcsin(b/R); Entry point, Bite depth and Entry angle "
                      "are then not used. 0: off. Unit: m. Range: [0, R].");
    prm.declare_entry("Wound crossing", to_text(p.crossing), vector_pattern(),
                      "With Bite > 0: the point of the surface where the stitch crosses the wound (the "
                      "wound's mid-plane). Unit: m.");
    prm.declare_entry("Entry angle", default_text(p.entry_angle), Patterns::Double(0, 1.5707963267948966),
                      "Angle between the tip's path and the surface at entry (used when "
                      "Bite depth = 0). Unit: rad. Range: (0, pi/2].");
    prm.declare_entry("Start time", default_text(p.start_time), Patterns::Double(0), "Unit: s. Range: >= 0.");
    prm.declare_entry("Angular speed", default_text(p.angular_speed), Patterns::Double(0),
                      "Turning rate of the needle about its arc centre. Unit: rad/s. Range: > 0.");
    prm.declare_entry("Approach", default_text(p.approach), Patterns::Double(0),
                      "Arc length of the tip before the entry point at the start. Unit: m. Range: >= 0.");
    prm.declare_entry("Pull", to_text(p.pull), vector_pattern(),
                      "Translation of the needle after the pass, drawing the suture through. Unit: m.");
    prm.declare_entry("Pull duration", default_text(p.pull_duration), Patterns::Double(0), "Unit: s. Range: > 0.");
    prm.declare_entry("Tighten", to_text(p.tighten), vector_pattern(),
                      "A second translation after the pull, drawing the suture tight (0: none). Unit: m.");
    prm.declare_entry("Tighten duration", default_text(p.tighten_duration), Patterns::Double(0),
                      "Unit: s. Range: > 0.");
    prm.declare_entry("Regrasp exposure", default_text(p.regrasp_exposure), Patterns::Double(0),
                      "The needle driver's regrasp (seed 001 sec. 5-6): once the tip is out of the exit by this "
                      "arc length the jaws let the needle go, move along it to the middle of its exposed part and "
                      "take it there, and the turn goes on (realtime path, quasi-static integrator). With "
                      "Stitches > 1 each pass but the last is followed by a reload: the other hand holds the needle "
                      "still while the driver's jaws go back to the Grip point. 0: none. Unit: m. Range: [0, "
                      "needle length).");
    prm.declare_entry("Regrasp duration", default_text(p.regrasp_duration), Patterns::Double(0),
                      "From letting the needle go to taking it again (the turn waits), and the length of each "
                      "reload. Unit: s. Range: > 0.");
    prm.declare_entry("Grip point", default_text(p.grip), Patterns::Double(0, 1),
                      "Where the driver's jaws hold the needle at the start, as a fraction of its arc from the "
                      "swage (surgeons hold it a third to a half of the way from the swage). Unit: 1. Range: "
                      "(0, 1).");
    const tools::SeriesParameters &s = d.series;
    prm.declare_entry("Stitches", default_text(s.stitches), Patterns::Integer(1, 100),
                      "Passes of a series: the needle makes this many, each entering Spacing beyond the last; "
                      "the pull follows each, the tightening the last (Series = running) or each (interrupted). "
                      "Unit: 1. Range: 1-100.");
    prm.declare_entry("Tail length", default_text(d.tail_length), Patterns::Double(0),
                      "Series = interrupted: the pull draws the thread through each stitch until this much is "
                      "left beyond its entry (the tail), then stops; the other hand takes the tail there (and "
                      "lays it: Tail lay) while the tightening draws the stitch closed (at the pull's end if the "
                      "tail is still longer). "
                      "Unit: m. Range: > 0.");
    prm.declare_entry("Tail lay", to_text(d.tail_lay), vector_pattern(),
                      "Series = interrupted, with a Tail lay duration: where the other hand carries each "
                      "stitch's tail once it has taken it, from the stitch's planned exit point (where the "
                      "needle's strand leaves the skin), in world axes: across the wound and beyond the exit, "
                      "as a first throw is laid, so that the tightening draws the two strands apart (the "
                      "default stitch's grasper lays its tail 8 mm beyond the exit, 2 mm up). The hand then "
                      "holds it there; it stops where it is at the stitch's tie-off. Unit: m.");
    prm.declare_entry("Tail lay duration", default_text(d.tail_lay_duration), Patterns::Double(0),
                      "Series = interrupted: how long the other hand takes to carry a tail to its Tail lay, "
                      "from where it took it, at a constant speed. 0: it holds the tail still where it took "
                      "it. Unit: s. Range: >= 0.");
    prm.declare_entry("Tail draw", to_text(d.tail_draw), vector_pattern(),
                      "Series = interrupted, with a Tail lay duration: how far the other hand draws each tail on "
                      "from its Tail lay, at a constant speed until the stitch's tightening ends (or the stitch "
                      "is tied off), in world axes: the tail drawn one way while the needle draws the other, "
                      "as a throw is drawn down (the default stitch's grasper draws its tail 18 mm on). 0: the "
                      "hand holds the tail at its lay. Unit: m.");
    prm.declare_entry("Series", "running", Patterns::Selection("running|interrupted"),
                      "With Stitches > 1: 'running', one continuous suture drawn through every pass; "
                      "'interrupted', each stitch pulled through to a short tail (Tail length), held by the "
                      "other hand, drawn tight by its own tightening and tied off when its own Closure gap pair "
                      "(the k-th pair for the k-th stitch) falls below the Tie-off gap, or at the tightening's "
                      "end: each strand is held a stitch width beyond its hole, where a knot over the wound "
                      "would hold it, the thread is cut there, and the rest on the needle is the next stitch's "
                      "suture (Suture/Last end free). Unit: none.");
    prm.declare_entry("Spacing", to_text(s.spacing), vector_pattern(),
                      "From one pass's entry point to the next's, in the surface (used with Stitches > 1). Unit: m.");
    prm.declare_entry("Transfer duration", default_text(s.transfer_duration), Patterns::Double(0),
                      "Time from one pass's pull to the next pass's start, the needle turning on about its "
                      "centre (used with Stitches > 1). Unit: s. Range: > 0.");
    prm.leave_subsection();
    prm.leave_subsection();
  }

  void
  NeedleParameters::declare_pierce_points(ParameterHandler &prm)
  {
    const NeedleParameters d;
    prm.enter_subsection("Pierce points");
    prm.declare_entry("Transverse stiffness", default_text(d.transverse_stiffness), Patterns::Double(0),
                      "k of the pierce point's tie across the thread (node-path "
                      "constraint, seed 004). Unit: N/m. Range: > 0.");
    ParameterDeclarations friction;
    coupling::FrictionParameters::declare(friction);
    declare_plain(prm, friction);
    prm.declare_entry("Spacing", default_text(d.spacing), Patterns::Double(0),
                      "Least distance between pierce points along the thread. Unit: m. Range: >= 0.");
    prm.declare_entry("Recorded", default_text(d.recorded), Patterns::Integer(0, 64),
                      "Pierce points given columns in forces.csv (state, slip velocity, "
                      "normal and friction force). Unit: 1. Range: 0-64.");
    prm.declare_entry("Load radius", default_text(d.load_radius), Patterns::Double(0, 0.01),
                      "Radius of the tissue that carries a pierce point's force, in both paths: "
                      "the point moves with, and loads, the tissue within this distance of it, "
                      "weighted by (1 - r^2/radius^2)^2 (mesh/spread_kernel.h; the accurate path "
                      "integrates it over the cells, the realtime path samples it at the nodes, "
                      "which needs a radius above the surface's longest edge). 0: a point load, "
                      "whose displacement grows without bound as the mesh is refined. Unit: m. "
                      "Range: 0-0.01.");
    prm.declare_entry("Load across the wound", default_text(d.load_across_wound), Patterns::Bool(),
                      "Whether a spread pierce point or touch (Load radius, Puncture/Touch radius) also "
                      "takes the tissue beyond the wound's faces within its radius (true; a point on a "
                      "face then shares its load with the other lip, as every study measured before "
                      "2026-12-05 did) or only the tissue a straight line from it reaches without "
                      "passing through the wound (false: the visibility criterion, both paths; needs the "
                      "wound's faces from Closure/Face contact or Stitch evaluation/Wound faces). "
                      "Unit: 1. Range: true, false.");
    prm.enter_subsection("Accurate");
    prm.declare_entry("Enforcement", d.enforcement, Patterns::Selection("penalty|lagrange"),
                      "The tie across the thread: penalty (a gap of force / Transverse "
                      "stiffness remains) or lagrange (Lagrange multipliers by augmented-"
                      "Lagrangian Uzawa updates until the gap is below Coupling tolerance; "
                      "Transverse stiffness then sets the rate). Unit: none.");
    prm.declare_entry("Coupling tolerance", default_text(d.coupling_tolerance), Patterns::Double(0),
                      "With the suture or Lagrange enforcement: the rounds of a step (contacts, "
                      "multipliers) end once no pierce tie gapes by more than this; it also sets "
                      "the force floor of the coupled solve (a hundredth of Transverse stiffness "
                      "times it). Unit: m. Range: > 0.");
    prm.declare_entry("Coupling iterations", default_text(d.coupling_iterations), Patterns::Integer(1, 1000),
                      "Most rounds per step; a step that does not settle in them is halved. "
                      "Unit: 1. Range: 1-1000.");
    prm.leave_subsection();
    prm.leave_subsection();
  }

  void
  NeedleParameters::parse(ParameterHandler &prm, const ParameterScope &root)
  {
    parse_needle(prm, root.subsection("Needle"));
    prm.enter_subsection("Puncture");
    puncture = parse_plain(prm, root.subsection("Puncture"), coupling::PunctureParameters::declare,
                           coupling::PunctureParameters::parse);
    prm.leave_subsection();
    parse_pierce_points(prm, root.subsection("Pierce points"));
  }

  void
  NeedleParameters::parse_jaws(ParameterHandler &prm, const ParameterScope &scope)
  {
    density = prm.get_double("Density");
    drag    = prm.get_double("Drag");
    scope.require(density > 0, "Density", "must be > 0 kg/m^3");
    scope.require(drag > 0, "Drag", "must be > 0 N s/m");
    jaws_text = prm.get("Jaws");
    jaws.clear();
    bool open = false;
    for (const auto &entry : Utilities::split_string_list(jaws_text, ';'))
      {
        const auto   pair = Utilities::split_string_list(entry, ':');
        const double t    = Utilities::string_to_double(pair.at(0));
        const bool   opens = pair.at(1) == "open";
        std::ostringstream why;
        if (!jaws.empty() && !(t > jaws.back().first))
          why << "the times must increase: " << t << " s after " << jaws.back().first << " s";
        else if (opens == open)
          why << "at " << t << " s the jaws are " << (open ? "open" : "closed") << " already";
        if (!why.str().empty())
          scope.fail("Jaws", why.str());
        jaws.emplace_back(t, opens);
        open = opens;
      }
  }

  void
  NeedleParameters::parse_passes_across(ParameterHandler &prm, const ParameterScope &scope)
  {
    // the pattern has checked each time (a number >= 0); only their order is left
    passes_text = prm.get("Passes across");
    passes      = Utilities::string_to_double(Utilities::split_string_list(passes_text, ';'));
    for (std::size_t k = 1; k < passes.size(); ++k)
      if (!(passes[k] > passes[k - 1]))
        scope.fail("Passes across", "the times must increase: " + default_text(passes[k]) + " s after " +
                                      default_text(passes[k - 1]) + " s");
  }

  void
  NeedleParameters::parse_needle(ParameterHandler &prm, const ParameterScope &scope)
  {
    prm.enter_subsection("Needle");
    shape         = prm.get("Shape");
    radius        = prm.get_double("Arc radius");
    wire_diameter = prm.get_double("Wire diameter");
    attach_suture = prm.get_bool("Attach suture");
    motion        = prm.get("Motion");
    length        = prm.get_double("Length");
    if (shape == "double-pointed")
      {
        scope.require(length > 0, "Length", "must be > 0 m");
        scope.require(wire_diameter > 0 && wire_diameter < length / 2, "Wire diameter", "must lie in (0, Length/2) m");
        scope.require(motion == "keyframes", "Motion",
                      "a double-pointed needle moves with the Endo Stitch's jaws by Keyframes (a planned pass turns "
                      "a curved needle about its arc centre)");
      }
    else if (present())
      {
        scope.require(radius > 0, "Arc radius", "must be > 0 m");
        scope.require(wire_diameter > 0 && wire_diameter < radius, "Wire diameter", "must lie in (0, Arc radius) m");
      }
    keyframe_text = prm.get("Keyframes");
    keyframes     = tools::Trajectory();
    for (const auto &[t, v] : get_keyframes(prm, "Keyframes", scope))
      {
        const Eigen::Vector3d r(v[3], v[4], v[5]);
        const double          angle = r.norm();
        tools::Pose           pose;
        pose.position = {v[0], v[1], v[2]};
        if (angle > 0)
          pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(angle, r / angle));
        keyframes.add(t, pose);
      }
    parse_jaws(prm, scope);
    parse_passes_across(prm, scope);
    prm.enter_subsection("Pass");
    const ParameterScope p = scope.subsection("Pass");
    pass.entry             = get_vector(prm, "Entry point");
    pass.normal            = get_vector(prm, "Surface normal");
    pass.bite_direction    = get_vector(prm, "Bite direction");
    pass.bite_depth        = prm.get_double("Bite depth");
    pass.entry_angle       = prm.get_double("Entry angle");
    pass.bite              = prm.get_double("Bite");
    pass.crossing          = get_vector(prm, "Wound crossing");
    pass.start_time        = prm.get_double("Start time");
    pass.angular_speed     = prm.get_double("Angular speed");
    pass.approach          = prm.get_double("Approach");
    pass.pull              = get_vector(prm, "Pull");
    pass.pull_duration     = prm.get_double("Pull duration");
    pass.tighten           = get_vector(prm, "Tighten");
    pass.tighten_duration  = prm.get_double("Tighten duration");
    pass.regrasp_exposure  = prm.get_double("Regrasp exposure");
    pass.regrasp_duration  = prm.get_double("Regrasp duration");
    pass.grip              = prm.get_double("Grip point");
    series.stitches          = prm.get_integer("Stitches");
    series.spacing           = get_vector(prm, "Spacing");
    series.transfer_duration = prm.get_double("Transfer duration");
    series.interrupted       = prm.get("Series") == "interrupted";
    tail_length              = prm.get_double("Tail length"); // > 0: its Range
    tail_lay                 = get_vector(prm, "Tail lay");
    tail_lay_duration        = prm.get_double("Tail lay duration");
    tail_draw                = get_vector(prm, "Tail draw");
    prm.leave_subsection();
    prm.leave_subsection();
    scope.require(jaws.empty() || shape != "double-pointed", "Jaws",
                  "the Endo Stitch holds its double-pointed needle in one jaw or the other throughout (Passes "
                  "across)");
    scope.require(passes.empty() || shape == "double-pointed", "Passes across", "needs Shape = double-pointed");
    scope.require(jaws.empty() || !planned_regrasp(), "Jaws",
                  "the planned pass's regrasp (Pass/Regrasp exposure) opens and closes the jaws itself");
    if (!present() || motion != "pass")
      return;
    p.require(pass.angular_speed > 0, "Angular speed", "must be > 0 rad/s");
    p.require(pass.pull_duration > 0, "Pull duration", "must be > 0 s");
    p.require(pass.tighten_duration > 0, "Tighten duration", "must be > 0 s");
    p.require(pass.bite_depth <= radius, "Bite depth",
              "must not exceed the needle's Arc radius (" + std::to_string(radius) + " m)");
    p.require(pass.bite <= radius, "Bite", "must not exceed the needle's Arc radius (" + std::to_string(radius) + " m)");
    try
      {
        planned_series();
      }
    catch (const std::invalid_argument &e)
      {
        // the entry the planner's refusal is about (tools/surgical_pass.cc's messages)
        const std::string what = e.what();
        p.fail(what.find("grip must") != std::string::npos        ? "Grip point"
               : what.find("regrasp") != std::string::npos        ? "Regrasp exposure"
               : what.find("surface normal") != std::string::npos ? "Surface normal"
               : what.find("entry angle") != std::string::npos  ? "Entry angle"
               : what.find("spacing") != std::string::npos      ? "Spacing"
               : what.find("pull") != std::string::npos         ? "Pull"
               : what.find("transfer") != std::string::npos     ? "Transfer duration"
                                                                : "Bite direction",
               what);
      }
  }

  void
  NeedleParameters::parse_pierce_points(ParameterHandler &prm, const ParameterScope &scope)
  {
    prm.enter_subsection("Pierce points");
    transverse_stiffness = prm.get_double("Transverse stiffness");
    friction = parse_plain(prm, scope, coupling::FrictionParameters::declare, coupling::FrictionParameters::parse);
    spacing  = prm.get_double("Spacing");
    recorded = prm.get_integer("Recorded");
    load_radius = prm.get_double("Load radius");
    load_across_wound = prm.get_bool("Load across the wound");
    scope.require(transverse_stiffness > 0, "Transverse stiffness", "must be > 0 N/m");
    prm.enter_subsection("Accurate");
    enforcement         = prm.get("Enforcement");
    coupling_tolerance  = prm.get_double("Coupling tolerance");
    coupling_iterations = prm.get_integer("Coupling iterations");
    scope.subsection("Accurate").require(coupling_tolerance > 0, "Coupling tolerance", "must be > 0 m");
    prm.leave_subsection();
    prm.leave_subsection();
  }

  void
  NeedleParameters::add_columns(std::vector<std::string> &columns) const
  {
    for (const std::string q : {"needle_force_", "needle_torque_", "needle_centre_"})
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(q + c + (q == "needle_force_" ? " [N]" : q == "needle_torque_" ? " [N*m]" : " [m]"));
    for (unsigned k = 0; k < recorded; ++k)
      for (const std::string q : {"state [0:none|1:stick|2:slip]", "anchor [m]", "slip_velocity [m/s]",
                                  "normal_force [N]", "friction_force [N]"})
        columns.push_back("pierce_" + std::to_string(k) + "_" + q);
  }

  tools::CurvedNeedle
  NeedleParameters::needle() const
  {
    if (shape == "double-pointed")
      return tools::CurvedNeedle::double_pointed(length, wire_diameter);
    return {radius, tools::CurvedNeedle::arc_angle_of(shape), wire_diameter};
  }

  tools::SurgicalPass
  NeedleParameters::planned_pass() const
  {
    return tools::plan_pass(needle(), pass);
  }

  tools::SurgicalSeries
  NeedleParameters::planned_series() const
  {
    return tools::plan_series(needle(), pass, series);
  }

  std::vector<std::pair<double, bool>>
  NeedleParameters::jaw_changes() const
  {
    return planned_regrasp() ? planned_series().jaws : jaws;
  }

  std::vector<std::pair<double, double>>
  NeedleParameters::reloads() const
  {
    return planned_regrasp() ? planned_series().reloads : std::vector<std::pair<double, double>>();
  }

  void
  NeedleParameters::check_entry_on_surface(const std::vector<std::array<std::uint32_t, 3>> &triangles,
                                           const Eigen::Matrix3Xd &vertices, const ParameterScope &scope) const
  {
    if (motion != "pass" || triangles.empty())
      return;
    const auto planned = planned_series();
    for (std::size_t k = 0; k < planned.passes.size(); ++k)
      {
        const Eigen::Vector3d &entry   = planned.passes[k].entry;
        double                 nearest = std::numeric_limits<double>::infinity();
        Eigen::Vector3d        at      = entry, bary;
        for (const auto &t : triangles)
          {
            const Eigen::Vector3d q = collision::closest_point_on_triangle(entry, vertices.col(t[0]),
                                                                           vertices.col(t[1]), vertices.col(t[2]), bary);
            if ((q - entry).norm() < nearest)
              {
                nearest = (q - entry).norm();
                at      = q;
              }
          }
        if (nearest <= 0.5 * planned.passes[k].bite_depth)
          continue;
        std::ostringstream why;
        if (k > 0)
          why << "with Spacing, pass " << k + 1 << "'s entry (" << entry[0] << ", " << entry[1] << ", " << entry[2]
              << " m) ";
        why << "lies " << nearest << " m from the tissue's surface (nearest point " << at[0] << ", " << at[1] << ", "
            << at[2] << " m), more than half the bite depth (" << planned.passes[k].bite_depth
            << " m): the pass would miss the tissue or graze it; put the entry point on the surface";
        scope.fail(k > 0 ? "Spacing" : "Entry point", why.str());
      }
  }

  tools::Trajectory
  NeedleParameters::trajectory() const
  {
    return motion == "pass" ? planned_series().trajectory : keyframes;
  }
} // namespace suturesim::scene
