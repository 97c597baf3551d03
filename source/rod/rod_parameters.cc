#include <suturesim/rod/rod_parameters.h>

#include <iomanip>
#include <sstream>

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cmath>

namespace suturesim::rod
{
  using namespace dealii;

  namespace
  {
    std::string
    to_string(const Vec3 &v)
    {
      return Utilities::to_string(v[0]) + ", " + Utilities::to_string(v[1]) + ", " +
             Utilities::to_string(v[2]);
    }

    /// A unit frame with first director @p t (the second director is the least
    /// aligned coordinate axis made orthogonal to t).
    Quat
    frame_with_tangent(const Vec3 &t)
    {
      Eigen::Index k;
      t.cwiseAbs().minCoeff(&k);
      const Vec3 e  = Vec3::Unit(k);
      const Vec3 d2 = (e - e.dot(t) * t).normalized();
      Mat3       R;
      R << t, d2, t.cross(d2);
      return Quat(R).normalized();
    }
  } // namespace

  bool
  EndCondition::fixes_rotation() const
  {
    return type == "clamped" || (type == "prescribed" && !keyframes.empty() &&
                                 keyframes.begin()->second.size() == 6);
  }

  std::pair<Vec3, Vec3>
  EndCondition::motion(const double t) const
  {
    const auto at = [](const std::vector<double> &v) {
      return std::make_pair(Vec3(v[0], v[1], v[2]),
                            v.size() == 6 ? Vec3(v[3], v[4], v[5]) : Vec3::Zero());
    };
    if (keyframes.empty())
      return {Vec3::Zero(), Vec3::Zero()};
    if (t <= keyframes.begin()->first)
      return at(keyframes.begin()->second);
    if (t >= keyframes.rbegin()->first)
      return at(keyframes.rbegin()->second);
    const auto hi = keyframes.upper_bound(t);
    const auto lo = std::prev(hi);
    const double w = (t - lo->first) / (hi->first - lo->first);
    const auto [x0, r0] = at(lo->second);
    const auto [x1, r1] = at(hi->second);
    return {(1 - w) * x0 + w * x1, (1 - w) * r0 + w * r1};
  }

  Vec3
  EndCondition::position(const double t, const Vec3 &held_at) const
  {
    if (frame == "grasp" || keyframes.empty())
      return held_at + motion(t).first;
    // world: on a straight line from the hold to the first keyframe, then the keyframes
    const auto   first = keyframes.upper_bound(grasp_time);
    const auto   to    = first == keyframes.end() ? std::prev(first) : first;
    const Vec3   k0(to->second[0], to->second[1], to->second[2]);
    if (t >= to->first)
      return motion(t).first;
    const double w = to->first > grasp_time ? std::clamp((t - grasp_time) / (to->first - grasp_time), 0.0, 1.0) : 1.0;
    return (1 - w) * held_at + w * k0;
  }

  void
  EndCondition::declare(ParameterHandler &prm)
  {
    prm.declare_entry("Type", "free", Patterns::Selection("free|clamped|pinned|prescribed"),
                      "free; clamped (position and frame fixed); pinned (position fixed, "
                      "frame free); prescribed (moved by the keyframes). Unit: none.");
    prm.declare_entry("Keyframes", "",
                      Patterns::Map(Patterns::Double(0), Patterns::List(Patterns::Double(), 3, 6, ","),
                                    0, Patterns::Map::max_int_value, ";", ":"),
                      "For Type = prescribed: 't: ux, uy, uz[, rx, ry, rz]; ...', the "
                      "displacement of the end from its initial position (m) and, when "
                      "given, the rotation vector applied to its initial frame (rad) at "
                      "time t (s >= 0); linear between keyframes, constant outside. With "
                      "three numbers the frame is free (a moving pin), with six it is "
                      "clamped to the motion. Unit: s: m, m, m[, rad, rad, rad].");
    prm.declare_entry("Grasp time", "0", Patterns::Double(0),
                      "Time at which a grasper closes on the end (realtime path): free "
                      "before, held by Type after, the keyframes then displacing it from "
                      "where it was at that time. 0: held from the start. Unit: s. Range: "
                      ">= 0.");
    prm.declare_entry("Keyframes frame", "grasp", Patterns::Selection("grasp|world"),
                      "grasp: the keyframes' first three numbers displace the end from where "
                      "it was held; world: they are its positions, the first after the grasp "
                      "reached in a straight line from where it was held (both model paths "
                      "then pull from the same place). Unit: none.");
  }

  void
  EndCondition::parse(const ParameterHandler &prm, const ParameterScope &scope)
  {
    type       = prm.get("Type");
    keyframes  = get_keyframes(prm, "Keyframes", scope);
    grasp_time = prm.get_double("Grasp time");
    frame      = prm.get("Keyframes frame");
    scope.require(grasp_time == 0 || type != "free", "Grasp time", "needs a Type other than free");
    std::size_t count = 0;
    for (const auto &[t, v] : keyframes)
      {
        scope.require(v.size() == 3 || v.size() == 6, "Keyframes",
                      "each keyframe needs 3 (displacement) or 6 (displacement and rotation) numbers");
        scope.require(count == 0 || v.size() == count, "Keyframes",
                      "every keyframe needs the same number of values (3 or 6)");
        count = v.size();
      }
    scope.require(type != "prescribed" || !keyframes.empty(), "Keyframes",
                  "Type = prescribed needs at least one keyframe");
    scope.require(type == "prescribed" || keyframes.empty(), "Keyframes",
                  "keyframes are only used with Type = prescribed");
  }

  void
  RodParameters::declare(ParameterHandler &prm)
  {
    const RodParameters d;
    prm.declare_entry("Centreline", d.centreline, Patterns::Selection("straight|arc|polyline"),
                      "Initial (stress-free) centreline. Unit: none.");
    prm.declare_entry("Elements", std::to_string(d.elements), Patterns::Integer(1, 1000000),
                      "Number of two-node elements. Unit: 1. Range: >= 1.");
    prm.enter_subsection("Straight");
    prm.declare_entry("Start point", to_string(d.start), vector_pattern(), "First node. Unit: m.");
    prm.declare_entry("Direction", to_string(d.direction), vector_pattern(),
                      "Direction of the rod (normalised). Unit: none. Range: non-zero.");
    prm.declare_entry("Length", "0.1", Patterns::Double(0), "Length. Unit: m. Range: > 0.");
    prm.leave_subsection();
    prm.enter_subsection("Arc");
    prm.declare_entry("Centre", to_string(d.centre), vector_pattern(), "Centre of the circle. Unit: m.");
    prm.declare_entry("Radius", "0.01", Patterns::Double(0), "Radius. Unit: m. Range: > 0.");
    prm.declare_entry("Plane normal", to_string(d.normal), vector_pattern(),
                      "Normal of the arc's plane; angles turn positively about it. Unit: "
                      "none. Range: non-zero.");
    prm.declare_entry("Start angle", "0", Patterns::Double(),
                      "Angle of the first node, measured from the in-plane axis a (the x "
                      "axis, or the y axis when the normal is along x, made orthogonal to "
                      "the normal). Unit: rad.");
    prm.declare_entry("Sweep", "3.141592653589793", Patterns::Double(-2 * M_PI, 2 * M_PI),
                      "Angle from the first to the last node. Unit: rad. Range: [-2 pi, 2 pi], "
                      "non-zero.");
    prm.leave_subsection();
    prm.declare_entry("Polyline points", "",
                      Patterns::List(Patterns::List(Patterns::Double(), 3, 3, ","), 0,
                                     Patterns::List::max_int_value, ";"),
                      "For Centreline = polyline: 'x, y, z; x, y, z; ...', resampled into "
                      "elements of equal length. Unit: m.");

    std::string presets = "custom";
    std::string preset_doc;
    // the table's values as a reader gives them (6 digits: 0.2745 mm, not the double's
    // 0.27450000000000002)
    const auto text = [](const double value) {
      std::ostringstream out;
      out << std::setprecision(6) << value;
      return out.str();
    };
    for (const auto &p : preset_table())
      {
        presets += "|" + p.name;
        preset_doc += p.name + ": d = " + text(p.diameter * 1e3) + " mm, E = " + text(p.E / 1e9) +
                      " GPa, nu = " + text(p.nu) + ", density = " + text(p.density) + " kg/m^3 (" + p.source +
                      "). ";
      }
    prm.declare_entry("Preset", d.preset, Patterns::Selection(presets),
                      "A named suture (USP size + material) that sets the cross-section's "
                      "radius, Young's modulus, Poisson's ratio and density; 'custom' takes "
                      "them from 'Cross section'. " + preset_doc + "Unit: none.");
    prm.enter_subsection("Cross section");
    prm.declare_entry("Radius", Utilities::to_string(d.section.radius), Patterns::Double(0),
                      "Radius of the solid circular section (contact radius too). Unit: m. Range: > 0.");
    prm.declare_entry("Young's modulus", Utilities::to_string(d.section.E), Patterns::Double(0),
                      "E. Unit: Pa. Range: > 0.");
    prm.declare_entry("Poisson's ratio", Utilities::to_string(d.section.nu), Patterns::Double(-1, 0.5),
                      "nu, gives G = E/(2(1+nu)). Unit: 1. Range: (-1, 0.5].");
    prm.declare_entry("Density", Utilities::to_string(d.section.density), Patterns::Double(0),
                      "Mass density (inertia, gravity). Unit: kg/m^3. Range: >= 0.");
    for (const auto &[key, unit] : std::vector<std::pair<std::string, std::string>>{
           {"EA", "N"}, {"GA", "N"}, {"EI", "N m^2"}, {"GJ", "N m^2"}})
      prm.declare_entry(key, "0", Patterns::Double(0),
                        "Section stiffness " + key + " given directly; 0 computes it from "
                        "the section (GA with Cowper's shear factor). Unit: " + unit + ". Range: >= 0.");
    prm.leave_subsection();

    for (const std::string end : {"Start end", "Last end"})
      {
        prm.enter_subsection(end);
        EndCondition::declare(prm);
        prm.leave_subsection();
      }

    prm.enter_subsection("Loads");
    prm.declare_entry("End force", "0, 0, 0", vector_pattern(),
                      "Force of fixed direction at the last end. Unit: N.");
    prm.declare_entry("End moment", "0, 0, 0", vector_pattern(),
                      "Moment of fixed (spatial) direction at the last end. Unit: N m.");
    prm.declare_entry("Gravity", "0, 0, 0", vector_pattern(),
                      "Gravitational acceleration (weight rho A g per length). Unit: m/s^2.");
    prm.declare_entry("Distributed load", "0, 0, 0", vector_pattern(),
                      "Force per unit reference length, fixed direction. Unit: N/m.");
    prm.declare_entry("Load ramp", d.load_ramp, Patterns::Selection("linear|constant"),
                      "linear: loads grow as t/T over the run (load stepping); constant: full "
                      "loads from t = 0. Unit: none.");
    prm.leave_subsection();

    prm.enter_subsection("Self-contact");
    prm.declare_entry("Enabled", "false", Patterns::Bool(),
                      "Penalty contact between non-adjacent segments (contact at centreline "
                      "distance 2 r). Unit: none.");
    prm.declare_entry("Penalty stiffness", "1e3", Patterns::Double(0),
                      "k of the penalty energy. Unit: N/m. Range: > 0.");
    prm.declare_entry("Smoothing width", "0", Patterns::Double(0),
                      "Penetration over which the penalty stiffens from 0 to k (C2 "
                      "penalty); 0 = plain quadratic. Unit: m. Range: >= 0.");
    prm.declare_entry("Friction coefficient", "0", Patterns::Double(0, 10),
                      "Coulomb mu of the thread on itself, regularised by an elastic stick "
                      "with history (the pierce points' law), isotropic in the contact's "
                      "tangent plane (docs/cosserat_rod.md); 0 = frictionless. Unit: 1. "
                      "Range: [0, 10].");
    prm.declare_entry("Stick stiffness", "1e3", Patterns::Double(0),
                      "k_t of the elastic stick before the strands slip on each other. "
                      "Unit: N/m. Range: > 0.");
    prm.leave_subsection();

    prm.enter_subsection("Tissue contact");
    prm.declare_entry("Enabled", d.tissue_contact.enabled ? "true" : "false", Patterns::Bool(),
                      "Accurate path with the tissue: the suture's nodes outside the pierce "
                      "points' tracts are pushed out of the tissue's surface by a frictionless "
                      "penalty, and the surface back (the realtime path's contact is "
                      "Realtime/Contact). Unit: none.");
    prm.declare_entry("Penalty stiffness", Utilities::to_string(d.tissue_contact.stiffness), Patterns::Double(0),
                      "k per node: a node a gap g < 0 closer to the surface than the suture's "
                      "radius feels -k g along the surface's normal. Unit: N/m. Range: > 0.");
    prm.declare_entry("Depth", Utilities::to_string(d.tissue_contact.depth), Patterns::Double(0),
                      "A node at most this far behind the surface is still pushed out (deeper "
                      "ones are taken to be inside on purpose). Unit: m. Range: > 0.");
    prm.declare_entry("Smoothing width", Utilities::to_string(d.tissue_contact.smoothing), Patterns::Double(0),
                      "delta: the penalty -k g holds where a node presses by more than delta; "
                      "over |g| < delta it is rounded to k (delta - g)^2 / (4 delta), which meets "
                      "it with value and slope, so that Newton's tangent sees a node grazing "
                      "the surface (0: the sharp law). Unit: m. Range: 0 to a tenth of the "
                      "suture's radius.");
    prm.leave_subsection();

    prm.enter_subsection("Newton");
    prm.declare_entry("Max iterations", std::to_string(d.newton.max_iterations), Patterns::Integer(1, 1000),
                      "Newton iterations per step before the step is cut back. Unit: 1. Range: 1-1000.");
    prm.declare_entry("Tolerance", Utilities::to_string(d.newton.tolerance), Patterns::Double(0, 1),
                      "Residual norm relative to the larger of the first residual and the "
                      "load. Unit: 1. Range: (0, 1).");
    prm.declare_entry("Line search steps", std::to_string(d.newton.line_search_steps), Patterns::Integer(0, 50),
                      "Energy line-search trials per iteration; 0 takes full Newton steps. Unit: 1. Range: 0-50.");
    prm.declare_entry("Stall window", std::to_string(d.newton.stall_window), Patterns::Integer(0, 1000),
                      "Full steps (Line search steps = 0): after this many iterations in a row "
                      "without the residual falling below 0.99 of its least value so far (the "
                      "window runs on when a pierce point changes its carrier element), the "
                      "solve goes on with the energy line search (4 trials a step, from the "
                      "capped step). Full steps cycle where a pierce point's slip reverses "
                      "across its stick band (docs/interrupted_stitch.md). 0: never. Unit: 1. "
                      "Range: 0-1000.");
    prm.declare_entry("Trust region", d.newton.trust_region ? "true" : "false", Patterns::Bool(),
                      "Accurate path with tissue and suture (whose solve caps a correction at "
                      "half the shortest element and 0.25 rad): a Newton correction longer "
                      "than the caps is replaced by the Levenberg-Marquardt step of a trust "
                      "region of the caps' size, which turns towards the residual where the "
                      "slack thread's Jacobian is indefinite; false: the Newton correction "
                      "scaled down to the caps (docs/interrupted_stitch.md). Unit: none.");
    prm.declare_entry("Trace failures", "false", Patterns::Bool(),
                      "Accurate path with tissue and suture: every iteration of each suture "
                      "solve that fails goes to suture_newton_trace.csv in the output folder, "
                      "its residual split by contribution (elements, self-contact, applied "
                      "loads, pierce-point ties, stabilization, tissue contact), the step "
                      "taken, and the node with the largest residual; and every trial "
                      "state of each coupled tissue-suture solve that fails goes to "
                      "coupled_newton_trace.csv (residual, step, pierce points' stick or "
                      "slip; diagnostics: docs/interrupted_stitch.md). Unit: none.");
    prm.leave_subsection();
    prm.declare_entry("Damping", "0", Patterns::Double(0),
                      "Mass-proportional damping c of the dynamics (force c m v, moment c J "
                      "omega). Unit: 1/s. Range: >= 0.");
    prm.declare_entry("Stabilization", "0", Patterns::Double(0),
                      "Quasi-static suture coupled to the tissue (accurate needle pass): a "
                      "viscous drag c v per unit length on every node, v its displacement over "
                      "the step divided by the step, which holds the free, weightless tail "
                      "that the quasi-static rod leaves nearly undetermined (as ABAQUS "
                      "*STATIC, STABILIZE); the drag's total is recorded "
                      "(suture_stabilization_force in forces.csv) so that its share of the "
                      "forces can be checked. Accurate knot (Knot with Model = accurate): the "
                      "drag the planner's end pulls the rod along against, what the rope lies "
                      "on (required, > 0; parameters/knots/overhand.prm). Unit: N s/m^2. "
                      "Range: >= 0.");
  }

  void
  RodParameters::parse(ParameterHandler &prm, const ParameterScope &scope)
  {
    centreline = prm.get("Centreline");
    elements   = prm.get_integer("Elements");
    prm.enter_subsection("Straight");
    const auto s = scope.subsection("Straight");
    start        = get_vector(prm, "Start point");
    direction    = get_vector(prm, "Direction");
    length       = prm.get_double("Length");
    prm.leave_subsection();
    if (centreline == "straight")
      {
        s.require(direction.norm() > 0, "Direction", "must not be zero");
        s.require(length > 0, "Length", "must be > 0 m");
      }
    direction.normalize();
    prm.enter_subsection("Arc");
    const auto a = scope.subsection("Arc");
    centre       = get_vector(prm, "Centre");
    arc_radius   = prm.get_double("Radius");
    normal       = get_vector(prm, "Plane normal");
    start_angle  = prm.get_double("Start angle");
    sweep        = prm.get_double("Sweep");
    prm.leave_subsection();
    if (centreline == "arc")
      {
        a.require(arc_radius > 0, "Radius", "must be > 0 m");
        a.require(normal.norm() > 0, "Plane normal", "must not be zero");
        a.require(sweep != 0, "Sweep", "must not be zero");
      }
    normal.normalize();
    polyline.clear();
    for (const auto &point : Utilities::split_string_list(prm.get("Polyline points"), ';'))
      {
        std::vector<double> v;
        try
          {
            v = Utilities::string_to_double(Utilities::split_string_list(point, ','));
          }
        catch (const ExceptionBase &)
          {
            // the pattern passes a denormal that strtod reports as out of range
            scope.fail("Polyline points", "'" + point + "' is not three finite numbers within the machine's range");
          }
        polyline.emplace_back(v[0], v[1], v[2]);
      }
    if (centreline == "polyline")
      {
        scope.require(polyline.size() >= 2, "Polyline points", "needs at least two points");
        for (std::size_t i = 1; i < polyline.size(); ++i)
          scope.require((polyline[i] - polyline[i - 1]).norm() > 0, "Polyline points",
                        "point " + std::to_string(i + 1) + " repeats the previous one");
      }

    preset = prm.get("Preset");
    prm.enter_subsection("Cross section");
    const auto c    = scope.subsection("Cross section");
    section.radius  = prm.get_double("Radius");
    section.E       = prm.get_double("Young's modulus");
    section.nu      = prm.get_double("Poisson's ratio");
    section.density = prm.get_double("Density");
    section.EA      = prm.get_double("EA");
    section.GA      = prm.get_double("GA");
    section.EI      = prm.get_double("EI");
    section.GJ      = prm.get_double("GJ");
    prm.leave_subsection();
    if (preset != "custom")
      {
        for (const auto &entry : preset_table())
          if (entry.name == preset)
            {
              // A value given next to the preset is a contradiction unless it is the
              // preset's own: the parameters.prm a run records holds the values used,
              // and must read back. The values used are set in the handler, so that
              // parameters.prm records them.
              const std::vector<std::pair<std::string, double>> values{
                {"Radius", entry.diameter / 2}, {"Young's modulus", entry.E},
                {"Poisson's ratio", entry.nu}, {"Density", entry.density}};
              prm.enter_subsection("Cross section");
              for (const auto &[key, value] : values)
                {
                  const double given = prm.get_double(key);
                  c.require(!scope.parameter_file().given("Suture/Cross section/" + key) ||
                              std::abs(given - value) <= 1e-12 * std::abs(value),
                            key,
                            "is set by 'Preset = " + preset + "' to " + Utilities::to_string(value) +
                              "; set either the preset or the value");
                  // the shortest text that reads back as the same double
                  std::string text;
                  for (int digits = 15; digits <= 17; ++digits)
                    {
                      std::ostringstream out;
                      out << std::setprecision(digits) << value;
                      text = out.str();
                      if (std::stod(text) == value)
                        break;
                    }
                  prm.set(key, text);
                }
              prm.leave_subsection();
              section.radius  = entry.diameter / 2;
              section.E       = entry.E;
              section.nu      = entry.nu;
              section.density = entry.density;
            }
      }
    c.require(section.radius > 0, "Radius", "must be > 0 m");
    c.require(section.E > 0, "Young's modulus", "must be > 0 Pa");
    c.require(section.nu < 0.5 && section.nu > -1, "Poisson's ratio", "must lie in (-1, 0.5)");

    const std::vector<std::pair<std::string, EndCondition *>> ends{{"Start end", &start_end},
                                                                   {"Last end", &last_end}};
    for (const auto &[name, end] : ends)
      {
        prm.enter_subsection(name);
        end->parse(prm, scope.subsection(name));
        prm.leave_subsection();
      }

    prm.enter_subsection("Loads");
    end_force   = get_vector(prm, "End force");
    end_moment  = get_vector(prm, "End moment");
    gravity     = get_vector(prm, "Gravity");
    distributed = get_vector(prm, "Distributed load");
    load_ramp   = prm.get("Load ramp");
    prm.leave_subsection();

    prm.enter_subsection("Self-contact");
    const auto sc     = scope.subsection("Self-contact");
    contact.enabled   = prm.get_bool("Enabled");
    contact.stiffness = prm.get_double("Penalty stiffness");
    contact.smoothing = prm.get_double("Smoothing width");
    contact.radius    = section.radius;
    contact.friction  = prm.get_double("Friction coefficient");
    contact.stick_stiffness = prm.get_double("Stick stiffness");
    prm.leave_subsection();
    sc.require(!contact.enabled || contact.stiffness > 0, "Penalty stiffness", "must be > 0 N/m");

    prm.enter_subsection("Tissue contact");
    const auto tc            = scope.subsection("Tissue contact");
    tissue_contact.enabled   = prm.get_bool("Enabled");
    tissue_contact.stiffness = prm.get_double("Penalty stiffness");
    tissue_contact.depth     = prm.get_double("Depth");
    tissue_contact.smoothing = prm.get_double("Smoothing width");
    prm.leave_subsection();
    tc.require(!tissue_contact.enabled || tissue_contact.stiffness > 0, "Penalty stiffness", "must be > 0 N/m");
    tc.require(!tissue_contact.enabled || tissue_contact.depth > 0, "Depth", "must be > 0 m");
    tc.require(!tissue_contact.enabled || tissue_contact.smoothing <= 0.1 * section.radius, "Smoothing width",
               "must be at most a tenth of the suture's radius (Suture/Radius)");

    prm.enter_subsection("Newton");
    newton.max_iterations    = prm.get_integer("Max iterations");
    newton.tolerance         = prm.get_double("Tolerance");
    newton.line_search_steps = prm.get_integer("Line search steps");
    newton.stall_window      = prm.get_integer("Stall window");
    newton.trust_region      = prm.get_bool("Trust region");
    trace_failures           = prm.get_bool("Trace failures");
    prm.leave_subsection();
    scope.subsection("Newton").require(newton.tolerance > 0, "Tolerance", "must be > 0");
    damping       = prm.get_double("Damping");
    stabilization = prm.get_double("Stabilization");
  }

  void
  RodParameters::initial_configuration(std::vector<Vec3> &x, std::vector<Quat> &q) const
  {
    const unsigned N = elements;
    x.resize(N + 1);
    q.resize(N + 1);
    if (centreline == "straight")
      {
        const Quat frame = frame_with_tangent(direction);
        for (unsigned i = 0; i <= N; ++i)
          {
            x[i] = start + (length * i / N) * direction;
            q[i] = frame;
          }
        return;
      }
    if (centreline == "arc")
      {
        const Vec3 axis = std::abs(normal.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY();
        const Vec3 a    = (axis - axis.dot(normal) * normal).normalized();
        const Vec3 b    = normal.cross(a);
        const double sign = sweep > 0 ? 1 : -1;
        for (unsigned i = 0; i <= N; ++i)
          {
            const double phi = start_angle + sweep * i / N;
            x[i]             = centre + arc_radius * (std::cos(phi) * a + std::sin(phi) * b);
            const Vec3 t     = sign * (-std::sin(phi) * a + std::cos(phi) * b);
            Mat3       R;
            R << t, sign * normal.cross(t), sign * normal;
            q[i] = Quat(R).normalized();
          }
        return;
      }
    // polyline: resample by arc length, then parallel transport a frame along the nodes
    std::vector<double> s{0};
    for (std::size_t k = 1; k < polyline.size(); ++k)
      s.push_back(s.back() + (polyline[k] - polyline[k - 1]).norm());
    std::size_t seg = 0;
    for (unsigned i = 0; i <= N; ++i)
      {
        const double target = s.back() * i / N;
        while (seg + 2 < polyline.size() && s[seg + 1] < target)
          ++seg;
        const double w = std::clamp((target - s[seg]) / (s[seg + 1] - s[seg]), 0.0, 1.0);
        x[i]           = (1 - w) * polyline[seg] + w * polyline[seg + 1];
      }
    std::vector<Vec3> t(N + 1);
    for (unsigned i = 0; i <= N; ++i)
      {
        const Vec3 back  = i > 0 ? (x[i] - x[i - 1]).normalized() : Vec3::Zero();
        const Vec3 ahead = i < N ? (x[i + 1] - x[i]).normalized() : Vec3::Zero();
        t[i]             = (back + ahead).normalized();
      }
    q[0] = frame_with_tangent(t[0]);
    for (unsigned i = 1; i <= N; ++i)
      q[i] = (Quat::FromTwoVectors(t[i - 1], t[i]) * q[i - 1]).normalized();
  }

  RodModel
  RodParameters::create_model() const
  {
    std::vector<Vec3> x;
    std::vector<Quat> q;
    initial_configuration(x, q);
    RodModel model(x, q, section.stiffness(), section.mass_per_length(),
                   section.rotational_inertia_per_length());
    const auto constrain = [&](const EndCondition &end, const std::size_t node) {
      if (end.type == "free")
        return;
      const bool r = end.fixes_rotation();
      model.constrain(node, {{true, true, true, r, r, r}});
    };
    constrain(start_end, 0);
    constrain(last_end, model.n_nodes() - 1);
    model.set_contact(contact);
    return model;
  }

  double
  RodParameters::load_factor(const double t, const double end_time) const
  {
    return load_ramp == "linear" ? std::min(t / end_time, 1.0) : 1.0;
  }

  void
  RodParameters::apply_loads(RodModel &model, const double t, const double end_time) const
  {
    const double lambda = load_factor(t, end_time);
    const auto  &ref    = model.references();
    const Vec3   weight = section.mass_per_length() * gravity + distributed;
    for (std::size_t i = 0; i < model.n_nodes(); ++i)
      {
        const double l = 0.5 * ((i > 0 ? ref[i - 1].length : 0) + (i < ref.size() ? ref[i].length : 0));
        model.forces()[i]  = lambda * l * weight;
        model.moments()[i] = Vec3::Zero();
      }
    model.forces().back() += lambda * end_force;
    model.moments().back() += lambda * end_moment;
  }

  void
  RodParameters::apply_motion(RodModel &model, const RodModel &initial, const double t) const
  {
    const auto move = [&](const EndCondition &end, const std::size_t node) {
      if (end.type != "prescribed")
        return;
      const Vec3 r      = end.motion(t).second;
      const Quat q      = end.fixes_rotation() ? quaternion_exp(r) * initial.rotations()[node]
                                               : model.rotations()[node];
      model.set_node(node, end.position(t, initial.positions()[node]), q);
    };
    move(start_end, 0);
    move(last_end, model.n_nodes() - 1);
  }
} // namespace suturesim::rod
