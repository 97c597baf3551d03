#include <suturesim/tearing/tear_criterion.h>
#include <suturesim/tissue/tissue_parameters.h>

#include <algorithm>
#include <map>
#include <string>

namespace suturesim::tissue
{
  using namespace dealii;

  void
  NewtonParameters::declare(ParameterHandler &prm)
  {
    const NewtonParameters d;
    prm.declare_entry("Max iterations",
                      std::to_string(d.max_iterations),
                      Patterns::Integer(1, 1000),
                      "Newton iterations per load step before the step is cut back. Unit: "
                      "1. Range: 1-1000.");
    prm.declare_entry("Residual tolerance",
                      Patterns::Tools::to_string(d.residual_tolerance),
                      Patterns::Double(0, 1),
                      "Convergence when the free-DoF residual norm falls below this "
                      "fraction of the largest residual of the step (and the increment "
                      "test holds). Unit: 1. Range: (0, 1).");
    prm.declare_entry("Absolute residual tolerance",
                      Patterns::Tools::to_string(d.absolute_residual_tolerance),
                      Patterns::Double(0),
                      "Convergence whenever the free-DoF residual norm is below this force. "
                      "Unit: N. Range: >= 0.");
    prm.declare_entry("Increment tolerance",
                      Patterns::Tools::to_string(d.increment_tolerance),
                      Patterns::Double(0, 1),
                      "Convergence needs |du| below this fraction of |u|. Unit: 1. Range: "
                      "(0, 1).");
    prm.declare_entry("Line search",
                      d.line_search ? "true" : "false",
                      Patterns::Bool(),
                      "Slack line search on the energy's directional derivative "
                      "R(u + a du).du: accept when it is at most 0.9 of its value at a = 0 "
                      "(Crisfield 1991, FEBio), else interpolate. Not used by the mixed "
                      "formulation's 'Mixed update = newton', which takes full steps (a "
                      "saddle point has no energy to search). Unit: none.");
    prm.declare_entry("Max backtracks",
                      std::to_string(d.max_backtracks),
                      Patterns::Integer(0, 30),
                      "Line-search reductions of a Newton update per iteration. Unit: 1. Range: 0-30.");
  }

  void
  NewtonParameters::parse(const ParameterHandler &prm, const ParameterScope &)
  {
    max_iterations              = prm.get_integer("Max iterations");
    residual_tolerance          = prm.get_double("Residual tolerance");
    absolute_residual_tolerance = prm.get_double("Absolute residual tolerance");
    increment_tolerance         = prm.get_double("Increment tolerance");
    line_search                 = prm.get_bool("Line search");
    max_backtracks              = prm.get_integer("Max backtracks");
  }

  namespace
  {
    const Patterns::Map probe_pattern(Patterns::Anything(),
                                      Patterns::List(Patterns::Double(), 3, 3, ","),
                                      0,
                                      Patterns::Map::max_int_value,
                                      ";",
                                      ":");
  }

  void
  TissueParameters::declare(ParameterHandler &prm)
  {
    prm.declare_entry("Element degree",
                      "2",
                      Patterns::Integer(1, 4),
                      "Polynomial degree of the Lagrange (Q_k) displacement element. Unit: "
                      "1. Range: 1-4.");
    prm.declare_entry("Formulation",
                      "mixed",
                      Patterns::Selection("mixed|displacement"),
                      "'mixed': three-field u-p-J (Simo-Taylor-Pister 1985, deal.II "
                      "step-44) with discontinuous pressure and dilatation condensed per "
                      "cell, free of volumetric locking up to nu = 0.4999; 'displacement': "
                      "plain Q_k, which locks for nearly incompressible tissue.");
    prm.declare_entry("Pressure degree",
                      "-1",
                      Patterns::Integer(-1, 1),
                      "Degree of the discontinuous pressure/dilatation of the mixed "
                      "formulation: 0 (mean dilatation), 1, or -1 for element degree - 1 "
                      "(Q2-P1, Q1-P0). Unit: 1. Range: -1-1.");
    prm.declare_entry("Mixed update",
                      "newton",
                      Patterns::Selection("newton|exact"),
                      "How the mixed formulation's pressure and dilatation follow Newton's "
                      "iterates in a quasi-static solve: 'newton': as Newton unknowns updated "
                      "from the linearised constraints (Simo-Taylor-Pister 1985, deal.II "
                      "step-44); 'exact': recomputed from the displacement at every iterate. "
                      "Both reach the same solution; implicit dynamics always uses 'exact'. "
                      "Unit: none.");
    prm.declare_entry("Probes",
                      "",
                      probe_pattern,
                      "Named points in the reference configuration whose displacement is "
                      "recorded, 'name: x, y, z; name: x, y, z'. Unit: m.");
    prm.declare_entry("Region moduli",
                      "",
                      Patterns::Map(Patterns::Anything(), Patterns::List(Patterns::Double(0), 2, 2, ","),
                                    0, Patterns::Map::max_int_value, ";", ":"),
                      "Layers of other tissue: 'name: mu, K; ...', the gmsh physical volume "
                      "'name' taking shear modulus mu and bulk modulus K in place of the "
                      "Material's (e.g. hypodermis under dermis, Tran et al. 2007: mu = "
                      "0.84e3, K = 36e3). Realtime path only for now. Unit: Pa. Range: "
                      "0 < mu < 1.5 K.");
    prm.enter_subsection("Newton");
    NewtonParameters::declare(prm);
    prm.leave_subsection();
    prm.enter_subsection("Linear solver");
    LinearSolver::Parameters::declare(prm);
    prm.leave_subsection();
    prm.enter_subsection("Phase field");
    prm.declare_entry("Enabled", "false", Patterns::Bool(),
                      "Tear propagation: AT1 phase-field fracture (Pham, Amor, Marigo & Maurini 2011) on the "
                      "finite-strain tissue. A damage field d in [0, 1] degrades the isochoric energy by "
                      "g = (1 - k)(1 - d)^2 + k, and the volumetric energy by g in expansion (J > 1) only "
                      "(Amor, Marigo & Maurini 2009's split: a tear opens, its faces do not interpenetrate). "
                      "Each quasi-static step minimises alternately over the displacement and over d (never "
                      "below the damage the step started from) until d settles. The tissue alone "
                      "(Bodies = tissue), quasi-static steps. Unit: none.");
    prm.declare_entry("Fracture toughness", tearing::default_toughness, Patterns::Double(0), tearing::toughness_help);
    prm.declare_entry("Length", "1e-3", Patterns::Double(0),
                      "Internal length l of the damage field (the specimen's Internal length): damage starts "
                      "where the degradable energy (1 - k)(Psi_iso + Psi_vol in expansion) reaches "
                      "3 G_c / (16 l), and a tear's damage spans 4 l; the cells along its path should be well "
                      "below l (the dissipated toughness is G_c (1 + 3 h / (8 l))). Unit: m. Range: > 0.");
    prm.declare_entry("Residual stiffness", "1e-6", Patterns::Double(0, 1),
                      "k: the share of the degraded energy a fully torn point keeps, so that the displacement "
                      "stays unique; a larger k also drives more damage beside a torn band stretched on, a "
                      "smaller one can stop Newton as a tear snaps (parameters/tearing/phase_field_bar.prm: "
                      "1e-3; docs/tearing.md). Unit: 1. Range: (0, 1).");
    prm.declare_entry("Tolerance", "1e-3", Patterns::Double(0, 1),
                      "A step's alternate minimisation ends when a damage solve changes d by at most this "
                      "anywhere. Unit: 1. Range: (0, 1).");
    prm.declare_entry("Max passes", "50", Patterns::Integer(1, 10000),
                      "Damage solves a step may take before it fails (and is halved). Unit: 1. Range: 1-10000.");
    prm.declare_entry("Initial crack", "", probe_pattern,
                      "A crack there from the start (a notch's faces and tip): d = 1, never to heal, at the damage "
                      "nodes in the box 'from: x, y, z; to: x, y, z' between its lower and upper corners in the "
                      "reference configuration, faces included to 1 nm (benchmarks/sent_tissue). Empty: none. "
                      "Unit: m. Range: 'from' at or below 'to' in x, y and z; needs Enabled = true.");
    prm.leave_subsection();
  }

  void
  TissueParameters::parse(ParameterHandler &prm, const ParameterScope &scope)
  {
    degree      = prm.get_integer("Element degree");
    formulation = prm.get("Formulation");
    const int p = prm.get_integer("Pressure degree");
    pressure_degree = p < 0 ? std::min<unsigned>(degree - 1, 1) : static_cast<unsigned>(p);
    mixed_update    = prm.get("Mixed update");

    probes.clear();
    for (const auto &[name, x] : get_named_points(prm, "Probes", scope, "probe"))
      probes.emplace_back(name, Point<3>(x[0], x[1], x[2]));

    region_moduli.clear();
    for (const auto &[name, v] : get_named_values(prm, "Region moduli"))
      {
        scope.require(v[0] > 0 && v[1] > 0 && v[0] < 1.5 * v[1], "Region moduli",
                      "region '" + name + "': needs 0 < mu < 1.5 K (Poisson's ratio in (0, 0.5))");
        for (const auto &r : region_moduli)
          scope.require(r.name != name, "Region moduli", "region '" + name + "' is named twice");
        region_moduli.push_back({name, v[0], v[1]});
      }

    prm.enter_subsection("Newton");
    newton.parse(prm, scope.subsection("Newton"));
    prm.leave_subsection();
    prm.enter_subsection("Linear solver");
    linear.parse(prm, scope.subsection("Linear solver"));
    prm.leave_subsection();
    prm.enter_subsection("Phase field");
    phase_field.enabled            = prm.get_bool("Enabled");
    phase_field.toughness          = prm.get_double("Fracture toughness");
    phase_field.length             = prm.get_double("Length");
    phase_field.residual_stiffness = prm.get_double("Residual stiffness");
    phase_field.tolerance          = prm.get_double("Tolerance");
    phase_field.max_passes         = static_cast<unsigned>(prm.get_integer("Max passes"));
    phase_field.initial_crack.clear();
    const ParameterScope phase_scope = scope.subsection("Phase field");
    std::map<std::string, Eigen::Vector3d> corner;
    for (const auto &[name, x] : get_named_points(prm, "Initial crack", phase_scope, "corner"))
      {
        phase_scope.require(name == "from" || name == "to", "Initial crack",
                            "corner '" + name + "': write 'from: x, y, z; to: x, y, z'");
        corner[name] = x;
      }
    if (!corner.empty())
      {
        phase_scope.require(corner.size() == 2, "Initial crack", "needs both corners, 'from: x, y, z; to: x, y, z'");
        phase_scope.require(phase_field.enabled, "Initial crack", "needs the phase field (Enabled = true)");
        const Eigen::Vector3d &from = corner["from"], &to = corner["to"];
        phase_scope.require((from.array() <= to.array()).all(), "Initial crack",
                            "the corner 'from' must be below 'to' in x, y and z");
        phase_field.initial_crack = {Point<3>(from[0], from[1], from[2]), Point<3>(to[0], to[1], to[2])};
      }
    prm.leave_subsection();
  }
} // namespace suturesim::tissue
