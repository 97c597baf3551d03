#include <suturesim/core/parameter_adapter.h>
#include <suturesim/scene/knot_parameters.h>
#include <suturesim/scene/scene_parameters.h>

#include <deal.II/base/utilities.h>

namespace suturesim::scene
{
  using namespace dealii;

  void
  SceneParameters::declare(ParameterHandler &prm, const std::map<std::string, std::string> &integrators)
  {
    prm.declare_entry("Scene name", "scene", Patterns::Anything(), "Name recorded in summary.json. Unit: none.");
    prm.declare_entry("Model", "accurate", Patterns::Selection("accurate|realtime"),
                      "Model path: 'accurate' (finite-strain hyperelastic FE tissue, "
                      "deal.II + PETSc, implicit; geometrically exact Cosserat-rod suture) or "
                      "'realtime' (the seed papers' reduced models at haptic rate; subsection "
                      "Realtime).");
    prm.declare_entry("Bodies", "tissue", Patterns::Selection("tissue|suture|tissue and suture|fracture specimen|knot specimen"),
                      "What the scene simulates: 'tissue' (subsections Mesh, Tissue), "
                      "'suture' (subsection Suture), both in contact ('tissue and "
                      "suture'; the accurate path couples them through a needle's pierce "
                      "points, the suture attached at its swage), or a 'fracture specimen' "
                      "(subsection Fracture specimen; accurate path: phase-field fracture "
                      "against linear elastic fracture mechanics), or a 'knot specimen' (subsection Knot "
                      "specimen with the Suture's Cross section and Self-contact; accurate path: an overhand "
                      "knot pulled tight against Audoly et al. 2007). "
                      "Unit: none.");
    prm.enter_subsection("Suture");
    rod::RodParameters::declare(prm);
    prm.leave_subsection();
    prm.enter_subsection("Mesh");
    mesh::MeshParameters::declare(prm);
    prm.leave_subsection();
    prm.enter_subsection("Tissue");
    tissue::TissueParameters::declare(prm);
    prm.enter_subsection("Material");
    tissue::Material::declare_parameters(prm);
    prm.leave_subsection();
    prm.enter_subsection("Boundary conditions");
    tissue::BoundaryConditions::declare(prm);
    prm.leave_subsection();
    prm.leave_subsection();
    prm.enter_subsection("Time");
    TimeParameters::declare(prm, integrators);
    prm.leave_subsection();
    NeedleParameters::declare(prm);
    ClosureParameters::declare(prm);
    KnotParameters::declare(prm);
    prm.enter_subsection("Stitch evaluation");
    ParameterDeclarations stitches;
    tearing::StitchLimits::declare(stitches);
    declare_plain(prm, stitches);
    prm.leave_subsection();
    prm.enter_subsection("Tearing");
    tearing::TearCriteria::declare_parameters(prm);
    prm.leave_subsection();
  }

  void
  SceneParameters::parse_common(ParameterHandler &prm, const ParameterFile &parameter_file)
  {
    file   = &parameter_file;
    name   = prm.get("Scene name");
    model  = prm.get("Model");
    bodies = prm.get("Bodies");
    needle.parse(prm, scope());
    // the accurate path's spread touch: refused here, not where the realtime world is
    // built, so that --validate (and a study's) refuses it
    if (model == "realtime" && needle.present() && needle.puncture.touch_radius > 0)
      scope("Puncture").fail("Touch radius", "the realtime path's touch is a node of the surface (a triangle "
                                             "split where the tip touches): set it for the accurate path only "
                                             "(subsection Model accurate)");
    closure.parse(prm, scope());
    // an interrupted series ties each stitch off on its own gap pair
    if (needle.present() && needle.motion == "pass" && needle.series.interrupted)
      {
        const ParameterScope pass = scope("Needle/Pass");
        const std::size_t    n    = needle.series.stitches;
        pass.require(has_suture() && needle.attach_suture, "Series",
                     "an interrupted series ties off the suture the needle draws: Bodies = tissue and suture, "
                     "Needle/Attach suture = true");
        pass.require(closure.present() && closure.tie_off, "Series",
                     "an interrupted series ties each stitch off at its own closure: it needs Closure/Gap probes "
                     "(a pair per stitch) and Closure/Tie off = true");
        pass.require(closure.pairs.size() == n, "Series",
                     "an interrupted series needs one Closure/Gap probes pair per stitch, the k-th for the k-th: " +
                       std::to_string(n) + " stitches, " + std::to_string(closure.pairs.size()) + " pairs");
        scope("Closure").require(!closure.tie_off_every_pair, "Tie off when",
                                 "an interrupted series (Needle/Pass/Series) ties each stitch off on its own pair: "
                                 "leave 'first pair'");
        closure.tie_off_each_stitch = true;
      }
    prm.enter_subsection("Knot");
    knot = KnotParameters::parse(prm, scope("Knot"));
    prm.leave_subsection();
    prm.enter_subsection("Stitch evaluation");
    stitch_evaluation =
      parse_plain(prm, scope("Stitch evaluation"), tearing::StitchLimits::declare, tearing::StitchLimits::parse);
    prm.leave_subsection();
    // a spread stopped at the wound needs its faces (wound() names them), in both paths
    if (needle.present() && !needle.load_across_wound)
      scope("Pierce points")
        .require(!stitch_evaluation.wound_faces.empty() || !closure.face_contact.empty(), "Load across the wound",
                 "false needs the wound's faces (Closure/Face contact or Stitch evaluation/Wound faces)");
  }

  std::vector<dealii::types::boundary_id>
  SceneParameters::wound_face_ids(const mesh::MeshInfo &mesh) const
  {
    std::vector<dealii::types::boundary_id> ids;
    if (!stitch_evaluation.wound_faces.empty())
      for (const auto &face : dealii::Utilities::split_string_list(stitch_evaluation.wound_faces, ','))
        ids.push_back(mesh.boundary_id(face, scope("Stitch evaluation"), "Wound faces"));
    else if (!closure.face_contact.empty())
      {
        const auto [a, b] = closure.face_contact_ids(mesh);
        ids               = {a, b};
      }
    return ids;
  }

  void
  SceneParameters::parse_bodies(ParameterHandler &prm)
  {
    if (has_suture())
      {
        prm.enter_subsection("Suture");
        suture.parse(prm, scope("Suture"));
        prm.leave_subsection();
      }
    if (!has_tissue())
      return;
    prm.enter_subsection("Mesh");
    mesh.parse(prm, scope("Mesh"));
    prm.leave_subsection();
    // the path is one polyline: a series' passes would be joined by a chord across the skin
    if (mesh.local.near_path && needle.present() && needle.motion == "pass" && needle.series.stitches > 1)
      scope("Mesh/Local refinement")
        .fail("Near needle path", "refines along a single pass; not with Needle/Pass/Stitches > 1 (refine near the "
                                  "wound's faces instead)");
    prm.enter_subsection("Tissue");
    const ParameterScope t = scope("Tissue");
    tissue.parse(prm, t);
    prm.enter_subsection("Material");
    material.emplace(tissue::Material::parse_parameters(prm, t.subsection("Material")));
    prm.leave_subsection();
    prm.enter_subsection("Boundary conditions");
    boundary_conditions.parse(prm, t.subsection("Boundary conditions"));
    prm.leave_subsection();
    prm.leave_subsection();
    prm.enter_subsection("Tearing");
    tearing = tearing::TearCriteria::parse_parameters(prm, scope("Tearing"));
    prm.leave_subsection();
    if (model == "realtime" && !tearing.criteria.empty())
      scope("Tearing").fail("Criteria", "the continuum tear criteria are evaluated by the accurate path only (Model = "
                                        "accurate); the realtime path tears by seed 003's rule, Realtime/Tearing/"
                                        "Ligament strength");
    if (model == "realtime" && tissue.phase_field.enabled)
      scope("Tissue/Phase field")
        .fail("Enabled", "the phase field tears the accurate path's tissue (Model = accurate); the realtime path tears "
                         "by seed 003's rule, Realtime/Tearing/Ligament strength");
  }

  void
  SceneParameters::parse_time(ParameterHandler &prm)
  {
    prm.enter_subsection("Time");
    time.parse(prm, scope("Time"));
    prm.leave_subsection();
  }
} // namespace suturesim::scene
