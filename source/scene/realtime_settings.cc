#include <suturesim/core/model_parameters.h>
#include <suturesim/core/parameter_adapter.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/realtime/pierce_model.h>
#include <suturesim/realtime/self_collision.h>
#include <suturesim/scene/realtime_settings.h>

namespace suturesim::scene
{
  using namespace dealii;
  namespace rt = realtime;

  void
  RealtimeSettings::declare(ParameterHandler &prm)
  {
    const RealtimeSettings d;
    declare_models<rt::TissueModel::Registry>(
      prm, "Tissue model", d.tissue_model,
      "Realtime tissue model, built from the tetrahedra of Mesh (the .geo must offer "
      "tetrahedra, e.g. Geo parameters = hexahedra: 0).");
    declare_models<rt::Integrator::Registry>(prm, "Integrator", d.integrator,
                                             "Realtime time integrator of tissue and suture.");
    declare_models<rt::SutureModel::Registry>(prm, "Suture model", d.suture_model, "Realtime suture model.");
    declare_models<rt::PierceModel::Registry>(
      prm, "Pierce model", d.pierce_model,
      "How pierce points hold on to the needle and suture and slip along them; 'automatic': "
      "soft-constraint with the ftl suture under a force-based integrator, node-path otherwise.",
      "automatic|");
    declare_models<rt::SelfCollision::Registry>(prm, "Self-collision", d.self_collision,
                                                "Suture self-collision response; 'off': none.", "off|");
    prm.declare_entry("Pierce mass ratio", default_text(d.pierce_mass_ratio), Patterns::Double(1),
                      "XPBD: the suture nodes' inverse masses within a pierce constraint are "
                      "capped at this multiple of the tissue point's (mass scaling against "
                      "jitter: a suture node is some 300 times lighter than a tissue node). "
                      "Unit: 1. Range: >= 1.");
    prm.declare_entry("Contact", default_text(d.contact), Patterns::Bool(),
                      "Suture-tissue surface contact (tissue and suture scenes). Unit: none.");
    prm.declare_entry("Contact stiffness", default_text(d.contact_stiffness), Patterns::Double(0),
                      "Penalty stiffness k of suture-tissue contact (compliance 1/k under "
                      "XPBD). Unit: N/m. Range: >= 0.");
    prm.declare_entry("Contact depth", default_text(d.contact_depth), Patterns::Double(0),
                      "How far inside the tissue surface a suture node is still pushed out "
                      "(deeper nodes are taken to have pierced it). Unit: m. Range: >= 0.");
    prm.declare_entry("Contact load", default_text(d.contact_load), Patterns::Bool(),
                      "With Suture model = ftl under a force-based integrator: the thread's "
                      "pull into the tissue surface at the nodes the contact holds loads the "
                      "surface (a frictionless support's reaction, realtime/surface_contact.h). "
                      "false: the contact only moves the thread (seed 002), and the tissue "
                      "feels a thread lying on it only through the penalty. Unit: none.");
    prm.declare_entry("Face contact stiffness", default_text(d.face_contact_stiffness), Patterns::Double(0),
                      "Penalty stiffness k per vertex pair of the incision's faces (Closure/Face "
                      "contact; compliance 1/k under XPBD), pairs listed within Closure/Face "
                      "contact margin: realtime/wound_face_contact.h. 0: none, the seeds' "
                      "realtime stitch, whose faces can pass through each other. Unit: N/m. "
                      "Range: >= 0.");
    prm.declare_entry("Rate", default_text(d.rate), Patterns::Double(1, 1e7),
                      "Haptic rate: one step(tool poses) -> tool forces per 1/Rate of "
                      "simulated time, and the deadline of each step. Unit: Hz. Range: "
                      "[1, 1e7].");
    prm.declare_entry("Substeps", default_text(d.substeps), Patterns::Integer(1, 100000),
                      "Integrator substeps per haptic step (dt = 1/(Rate Substeps)). Unit: "
                      "none. Range: [1, 100000].");
    prm.declare_entry("Above stability limit", d.refuse_above_limit ? "refuse" : "warn",
                      Patterns::Selection("warn|refuse"),
                      "What to do when dt exceeds the integrator's stability limit dt_crit "
                      "(reported in summary.json): warn and run, or refuse to run. Unit: "
                      "none.");
    prm.declare_entry("Traction subdivision", default_text(d.traction_subdivision), Patterns::Integer(1, 16),
                      "Tractions become the consistent nodal loads f_i = integral of t N_i dA "
                      "over each loaded surface triangle (N_i its linear shape functions), "
                      "integrated at the centroids of its n^2 sub-triangles: 1 is the centroid "
                      "rule, exact for a traction uniform over the triangle; a traction that "
                      "jumps inside a triangle (the edge of a pressure patch) needs more. Cost: "
                      "n^2 evaluations of the traction per loaded triangle and step. Unit: 1. "
                      "Range: [1, 16].");
    prm.declare_entry("Pacing", default_text(d.pacing), Patterns::Bool(),
                      "Wait for the wall clock between steps as a haptic loop does (true), "
                      "or step as fast as possible (false, for benchmarks). Unit: none.");
    prm.declare_entry("Access points", "",
                      Patterns::Map(Patterns::Anything(), vector_pattern(), 0, Patterns::Map::max_int_value, ";", ":"),
                      "Seed 004's node-access constraints: fixed points the suture passes "
                      "through, each between two of its nodes, which bend over it at their "
                      "link's rest length (a frictionless peg), 'name: x, y, z; ...'. Each "
                      "starts on the suture link nearest it and stands in for that link's "
                      "spring while it holds it (suture models mass-spring and xpbd-rod). "
                      "Unit: m.");
    prm.declare_entry("Access stiffness", default_text(d.access_stiffness), Patterns::Double(0),
                      "Stiffness k of the node-access constraints, E = k C^2 / 2 (compliance "
                      "1/k under XPBD); 0: that of the suture's links. Unit: N/m. Range: >= 0.");
    prm.enter_subsection("Probe");
    prm.declare_entry("Length", default_text(d.probe.length), Patterns::Double(0),
                      "A blunt probe pressing on the tissue, which it may not penetrate "
                      "(seed 004's external stage: node-triangle constraints between its "
                      "nodes and the tissue surface): the length of its end that can touch, "
                      "from the tip; 0: no probe. Realtime path. Unit: m. Range: >= 0.");
    prm.declare_entry("Radius", default_text(d.probe.radius), Patterns::Double(0),
                      "The probe's radius (its end a hemisphere). Unit: m. Range: > 0.");
    prm.declare_entry("Stiffness", default_text(d.probe.stiffness), Patterns::Double(0),
                      "Penalty stiffness k of the probe's contact with the tissue "
                      "(compliance 1/k under XPBD). Unit: N/m. Range: > 0.");
    prm.declare_entry("Tip", "0, 0, 0", vector_pattern(), "Where the probe's tip is at t = 0: the centre of its hemispherical end. Unit: m.");
    prm.declare_entry("Axis", "0, 0, 1", vector_pattern(),
                      "Direction from the tip towards the handle (normalised). Unit: none. Range: "
                      "non-zero.");
    prm.declare_entry("Keyframes", "",
                      Patterns::Map(Patterns::Double(0), vector_pattern(), 0, Patterns::Map::max_int_value, ";", ":"),
                      "'t: ux, uy, uz; ...': the tip's displacement from its start at time t; "
                      "linear between keyframes, constant outside. Unit: s: m, m, m.");
    prm.leave_subsection();
    prm.enter_subsection("Tearing");
    ParameterDeclarations tear;
    tearing::LigamentTearParameters::declare(tear);
    declare_plain(prm, tear);
    prm.leave_subsection();
  }

  void
  RealtimeSettings::parse(ParameterHandler &prm, const ParameterScope &scope)
  {
    tissue_model       = prm.get("Tissue model");
    integrator         = prm.get("Integrator");
    suture_model       = prm.get("Suture model");
    self_collision     = prm.get("Self-collision");
    pierce_model       = prm.get("Pierce model");
    pierce_mass_ratio  = prm.get_double("Pierce mass ratio");
    contact            = prm.get_bool("Contact");
    contact_stiffness  = prm.get_double("Contact stiffness");
    contact_depth      = prm.get_double("Contact depth");
    contact_load       = prm.get_bool("Contact load");
    face_contact_stiffness = prm.get_double("Face contact stiffness");
    rate               = prm.get_double("Rate");
    substeps           = prm.get_integer("Substeps");
    traction_subdivision = static_cast<unsigned>(prm.get_integer("Traction subdivision"));
    refuse_above_limit = prm.get("Above stability limit") == "refuse";
    pacing             = prm.get_bool("Pacing");
    access_stiffness   = prm.get_double("Access stiffness");
    access_points      = get_named_points(prm, "Access points", scope, "access point");
    prm.enter_subsection("Probe");
    {
      const ParameterScope at = scope.subsection("Probe");
      probe.length            = prm.get_double("Length");
      probe.radius            = prm.get_double("Radius");
      probe.stiffness         = prm.get_double("Stiffness");
      probe.tip               = get_vector(prm, "Tip");
      probe.axis              = get_vector(prm, "Axis");
      probe.path.type         = "prescribed";
      probe.path.keyframes    = get_keyframes(prm, "Keyframes", at);
      if (probe.length > 0)
        {
          at.require(probe.radius > 0, "Radius", "a probe needs a radius > 0 m");
          at.require(probe.stiffness > 0, "Stiffness", "a probe needs a stiffness > 0 N/m");
          at.require(probe.axis.norm() > 0, "Axis", "the probe's axis must not be zero");
        }
    }
    prm.leave_subsection();
    prm.enter_subsection("Tearing");
    tearing = parse_plain(prm, scope.subsection("Tearing"), tearing::LigamentTearParameters::declare,
                          tearing::LigamentTearParameters::parse);
    prm.leave_subsection();
  }

  RealtimeModels::RealtimeModels(ParameterHandler &prm, const ParameterScope &scope, const RealtimeSettings &settings,
                                 const bool with_tissue, const bool with_suture)
  {
    integrator = create_model<rt::Integrator::Registry>(prm, scope, settings.integrator);
    if (with_tissue)
      tissue = create_model<rt::TissueModel::Registry>(prm, scope, settings.tissue_model);
    if (with_suture)
      {
        suture = create_model<rt::SutureModel::Registry>(prm, scope, settings.suture_model);
        if (settings.self_collision != "off")
          self_collision = read_model_values<rt::SelfCollision::Registry>(prm, settings.self_collision);
      }
  }
} // namespace suturesim::scene
