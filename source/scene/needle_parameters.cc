#include <suturesim/scene/needle_parameters.h>

#include <deal.II/base/utilities.h>

#include <stdexcept>

namespace suturesim::scene
{
  using namespace dealii;

  void
  NeedleParameters::declare(ParameterHandler &prm)
  {
    const NeedleParameters d;
    prm.enter_subsection("Needle");
    prm.declare_entry("Shape", d.shape, Patterns::Selection("none|3/8|1/2"),
                      "The curved suture needle: none, a 3/8 circle (135 degrees of arc) or a "
                      "1/2 circle (180 degrees). Unit: none.");
    prm.declare_entry("Arc radius", "0.008", Patterns::Double(0),
                      "Radius R of the needle's arc. Unit: m. Range: > 0.");
    prm.declare_entry("Wire diameter", "4e-4", Patterns::Double(0),
                      "Diameter of the needle wire. Unit: m. Range: (0, R).");
    prm.declare_entry("Attach suture", "true", Patterns::Bool(),
                      "The suture starts at the swage, leaving it along the needle's "
                      "tangent, held there in position and direction (seed 002's hard "
                      "constraint); the Suture subsection's Straight start point and "
                      "direction are then set from the needle. Unit: none.");
    prm.declare_entry("Motion", d.motion, Patterns::Selection("pass|keyframes"),
                      "pass: the standard surgical pass of subsection Pass (the needle "
                      "turns about its arc centre, then is pulled); keyframes: the poses of "
                      "Keyframes. Unit: none.");
    prm.declare_entry("Keyframes", "0: 0, 0, 0.02, 0, 0, 0",
                      Patterns::Map(Patterns::Double(0), Patterns::List(Patterns::Double(), 6, 6, ","),
                                    1, Patterns::Map::max_int_value, ";", ":"),
                      "For Motion = keyframes: 't: cx, cy, cz, rx, ry, rz; ...', the arc "
                      "centre (m) and the rotation vector of the needle's frame (rad; in "
                      "the frame the arc lies in the x-y plane, swage on +x, tip at the arc "
                      "angle); positions linear and rotations by slerp between keyframes. "
                      "Unit: s: m, m, m, rad, rad, rad.");
    prm.enter_subsection("Pass");
    prm.declare_entry("Entry point", "0, 0, 0", vector_pattern(),
                      "Where the tip enters the tissue surface. Unit: m.");
    prm.declare_entry("Surface normal", "0, 0, 1", vector_pattern(),
                      "Outward normal of the surface at the entry point. Unit: none. "
                      "Range: non-zero.");
    prm.declare_entry("Bite direction", "1, 0, 0", vector_pattern(),
                      "From the entry towards the exit (projected onto the surface). Unit: "
                      "none. Range: not along the normal.");
    prm.declare_entry("Bite depth", "0.003", Patterns::Double(0),
                      "Depth delta the tip reaches below the surface; the entry angle is "
                      "then arccos(1 - delta/R). 0: use the entry angle. Unit: m. Range: "
                      "[0, R].");
    prm.declare_entry("Entry angle", "1.5707963267948966", Patterns::Double(0, 1.5707963267948966),
                      "Angle between the tip's path and the surface at entry (used when "
                      "Bite depth = 0). Unit: rad. Range: (0, pi/2].");
    prm.declare_entry("Start time", "0", Patterns::Double(0), "Unit: s. Range: >= 0.");
    prm.declare_entry("Angular speed", "1", Patterns::Double(0),
                      "Turning rate of the needle about its arc centre. Unit: rad/s. Range: "
                      "> 0.");
    prm.declare_entry("Approach", "0.001", Patterns::Double(0),
                      "Arc length of the tip before the entry point at the start. Unit: m. "
                      "Range: >= 0.");
    prm.declare_entry("Pull", "0, 0, 0.03", vector_pattern(),
                      "Translation of the needle after the pass, drawing the suture "
                      "through. Unit: m.");
    prm.declare_entry("Pull duration", "1", Patterns::Double(0), "Unit: s. Range: > 0.");
    prm.declare_entry("Tighten", "0, 0, 0", vector_pattern(),
                      "A second translation after the pull, drawing the suture tight (0: "
                      "none). Unit: m.");
    prm.declare_entry("Tighten duration", "1", Patterns::Double(0), "Unit: s. Range: > 0.");
    prm.leave_subsection();
    prm.leave_subsection();

    prm.enter_subsection("Puncture");
    prm.declare_entry("Threshold", "0.7", Patterns::Double(0),
                      "Normal force of the tip on the surface at which it punctures "
                      "(default: 0.61-0.90 N for suture needles, Maloney et al. 2025). "
                      "Unit: N. Range: > 0.");
    prm.declare_entry("Tip stiffness", "2000", Patterns::Double(0),
                      "Penalty k_c of the tip on the surface before puncture (the dimple). "
                      "Unit: N/m. Range: > 0.");
    prm.declare_entry("Reach", "0.001", Patterns::Double(0),
                      "Distance from the surface within which the tip is looked for. Unit: "
                      "m. Range: > 0.");
    prm.leave_subsection();

    prm.enter_subsection("Pierce points");
    prm.declare_entry("Transverse stiffness", "500", Patterns::Double(0),
                      "k of the pierce point's tie across the thread (node-path "
                      "constraint, seed 004). Unit: N/m. Range: > 0.");
    prm.declare_entry("Friction coefficient", "0.2", Patterns::Double(0),
                      "Coulomb mu between tissue and thread (seed 000 eq. 2). Unit: 1. "
                      "Range: >= 0.");
    prm.declare_entry("Stick stiffness", "500", Patterns::Double(0),
                      "k_t of the elastic stick before slip (regularised Coulomb). Unit: "
                      "N/m. Range: > 0.");
    prm.declare_entry("Grip", "0.05", Patterns::Double(0),
                      "Normal force N0 of the hole on a straight thread; N = N0 + |f_perp|. "
                      "Unit: N. Range: >= 0.");
    prm.declare_entry("Spacing", "1e-4", Patterns::Double(0),
                      "Least distance between pierce points along the thread. Unit: m. "
                      "Range: >= 0.");
    prm.declare_entry("Enforcement", "penalty", Patterns::Selection("penalty|lagrange"),
                      "Accurate path, the tie across the thread: penalty (a gap of "
                      "force / Transverse stiffness remains) or lagrange (Lagrange "
                      "multipliers by augmented-Lagrangian Uzawa updates until the gap is "
                      "below Coupling tolerance; Transverse stiffness then sets the rate). "
                      "The realtime path's XPBD constraints ignore it. Unit: none.");
    prm.declare_entry("Mass ratio", "10", Patterns::Double(1),
                      "Realtime XPBD: the suture nodes' inverse masses within a pierce "
                      "constraint are capped at this multiple of the tissue point's (mass "
                      "scaling). Unit: 1. Range: >= 1.");
    prm.declare_entry("Coupling tolerance", "1e-7", Patterns::Double(0),
                      "Accurate path with the suture or Lagrange enforcement: tissue and "
                      "suture are solved in turn within each step (the multipliers updated "
                      "between) until neither the pierced tissue points nor the suture's "
                      "nodes move by more than this between two rounds and, with lagrange, "
                      "no pierce tie gapes by more. Unit: m. Range: > 0.");
    prm.declare_entry("Coupling iterations", "40", Patterns::Integer(1, 1000),
                      "Accurate path with the suture or Lagrange enforcement: most rounds "
                      "per step; a step that does not converge in them is halved. "
                      "Unit: 1. Range: 1-1000.");
    prm.declare_entry("Recorded", "4", Patterns::Integer(0, 64),
                      "Pierce points given columns in forces.csv (state, slip velocity, "
                      "normal and friction force). Unit: 1. Range: 0-64.");
    prm.leave_subsection();
  }

  void
  NeedleParameters::parse(ParameterHandler &prm, const ParameterScope &root)
  {
    prm.enter_subsection("Needle");
    const ParameterScope scope = root.subsection("Needle");
    shape                      = prm.get("Shape");
    radius                     = prm.get_double("Arc radius");
    wire_diameter              = prm.get_double("Wire diameter");
    attach_suture              = prm.get_bool("Attach suture");
    motion                     = prm.get("Motion");
    if (present())
      {
        scope.require(radius > 0, "Arc radius", "must be > 0 m");
        scope.require(wire_diameter > 0 && wire_diameter < radius, "Wire diameter",
                      "must lie in (0, Arc radius) m");
      }
    keyframes = tools::Trajectory();
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
    prm.enter_subsection("Pass");
    const ParameterScope p = scope.subsection("Pass");
    pass.entry             = get_vector(prm, "Entry point");
    pass.normal            = get_vector(prm, "Surface normal");
    pass.bite_direction    = get_vector(prm, "Bite direction");
    pass.bite_depth        = prm.get_double("Bite depth");
    pass.entry_angle       = prm.get_double("Entry angle");
    pass.start_time        = prm.get_double("Start time");
    pass.angular_speed     = prm.get_double("Angular speed");
    pass.approach          = prm.get_double("Approach");
    pass.pull              = get_vector(prm, "Pull");
    pass.pull_duration     = prm.get_double("Pull duration");
    pass.tighten           = get_vector(prm, "Tighten");
    pass.tighten_duration  = prm.get_double("Tighten duration");
    prm.leave_subsection();
    prm.leave_subsection();
    if (present() && motion == "pass")
      {
        p.require(pass.angular_speed > 0, "Angular speed", "must be > 0 rad/s");
        p.require(pass.pull_duration > 0, "Pull duration", "must be > 0 s");
        p.require(pass.tighten_duration > 0, "Tighten duration", "must be > 0 s");
        p.require(pass.bite_depth <= radius, "Bite depth",
                  "must not exceed the needle's Arc radius (" + std::to_string(radius) + " m)");
        try
          {
            planned_pass();
          }
        catch (const std::invalid_argument &e)
          {
            p.fail("Bite direction", e.what());
          }
      }

    prm.enter_subsection("Puncture");
    const ParameterScope ps = root.subsection("Puncture");
    puncture.threshold      = prm.get_double("Threshold");
    puncture.stiffness      = prm.get_double("Tip stiffness");
    puncture.reach          = prm.get_double("Reach");
    ps.require(puncture.threshold > 0, "Threshold", "must be > 0 N");
    ps.require(puncture.stiffness > 0, "Tip stiffness", "must be > 0 N/m");
    ps.require(puncture.reach > 0, "Reach", "must be > 0 m");
    prm.leave_subsection();

    prm.enter_subsection("Pierce points");
    const ParameterScope pp = root.subsection("Pierce points");
    transverse_stiffness    = prm.get_double("Transverse stiffness");
    friction.mu             = prm.get_double("Friction coefficient");
    friction.stiffness      = prm.get_double("Stick stiffness");
    friction.grip           = prm.get_double("Grip");
    spacing                 = prm.get_double("Spacing");
    enforcement             = prm.get("Enforcement");
    mass_ratio              = prm.get_double("Mass ratio");
    recorded                = prm.get_integer("Recorded");
    coupling_tolerance      = prm.get_double("Coupling tolerance");
    coupling_iterations     = prm.get_integer("Coupling iterations");
    pp.require(coupling_tolerance > 0, "Coupling tolerance", "must be > 0 m");
    pp.require(transverse_stiffness > 0, "Transverse stiffness", "must be > 0 N/m");
    pp.require(friction.stiffness > 0, "Stick stiffness", "must be > 0 N/m");
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

  void
  NeedleParameters::write_summary(nlohmann::json &summary, const std::vector<coupling::PunctureEvent> &events,
                                  const double peak_pull_force) const
  {
    auto &list    = summary["events"];
    list          = nlohmann::json::array();
    auto &metrics = summary["metrics"];
    for (const auto &e : events)
      {
        list.push_back({{"kind", e.kind},
                        {"time", e.time},
                        {"position", {e.position[0], e.position[1], e.position[2]}},
                        {"force", e.force}});
        for (const std::string kind : {"entry", "exit"})
          if (e.kind == "puncture_" + kind && !metrics.contains("puncture_force_" + kind))
            metrics["puncture_force_" + kind] = e.force;
      }
    metrics["peak_pull_force"] = peak_pull_force;
    summary["needle"]          = {{"shape", shape},
                                  {"arc_radius", radius},
                                  {"wire_diameter", wire_diameter},
                                  {"motion", motion},
                                  {"enforcement", enforcement},
                                  {"puncture_threshold", puncture.threshold}};
    if (motion == "pass")
      {
        const auto pass           = planned_pass();
        summary["needle"]["pass"] = {{"entry_angle_rad", pass.entry_angle},
                                     {"bite_depth", pass.bite_depth},
                                     {"bite_width", pass.bite_width},
                                     {"exit", {pass.exit[0], pass.exit[1], pass.exit[2]}},
                                     {"t_tip_entry", pass.t_tip_entry},
                                     {"t_tip_exit", pass.t_tip_exit},
                                     {"t_swage_exit", pass.t_swage_exit},
                                     {"t_turn_end", pass.t_turn_end},
                                     {"t_end", pass.t_end}};
      }
  }

  tools::CurvedNeedle
  NeedleParameters::needle() const
  {
    return {radius, tools::CurvedNeedle::arc_angle_of(shape), wire_diameter};
  }

  tools::SurgicalPass
  NeedleParameters::planned_pass() const
  {
    return tools::plan_pass(needle(), pass);
  }

  tools::Trajectory
  NeedleParameters::trajectory() const
  {
    return motion == "pass" ? planned_pass().trajectory : keyframes;
  }
} // namespace suturesim::scene
