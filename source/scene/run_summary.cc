#include <suturesim/scene/run_summary.h>

#include <algorithm>
#include <cmath>
#include <sstream>

namespace suturesim::scene
{
  namespace
  {
    /// h = (V/N)^(1/3) (Celik et al. 2008, J. Fluids Eng. 130, 078001, eq. 1), m.
    double
    representative_size(const double volume, const double cells)
    {
      return cells > 0 ? std::cbrt(volume / cells) : 0.0;
    }
  } // namespace

  void
  RunSummary::begin(const SceneParameters &scene)
  {
    json["scene"]      = scene.name;
    json["scene_file"] = scene.file->name();
    json["model"]      = scene.model;
    json["bodies"]     = scene.bodies;
    json["metrics"]    = nlohmann::json::object();
    json["steps"]      = nlohmann::json::array();
  }

  void
  RunSummary::fe_mesh(const std::string &description, const std::uint64_t cells, const std::uint64_t dofs,
                      const double volume, const tissue::TissueParameters &tissue, const std::size_t surface_triangles)
  {
    json["mesh"] = {{"description", description},
                    {"cells", cells},
                    {"dofs", dofs},
                    {"volume", volume},
                    {"representative_size", representative_size(volume, static_cast<double>(cells))},
                    {"element_degree", tissue.degree},
                    {"formulation", tissue.formulation}};
    if (surface_triangles > 0)
      json["mesh"]["surface_triangles"] = surface_triangles;
    json["solver"]["linear_solver"] =
      tissue.linear.method + (tissue.linear.method == "direct" ? std::string(" (MUMPS)") : "+" + tissue.linear.preconditioner);
  }

  void
  RunSummary::simplex_mesh(const std::string &description, const std::size_t vertices, const std::size_t tetrahedra,
                           const double volume, const std::size_t surface_triangles)
  {
    json["mesh"] = {{"description", description},
                    {"vertices", vertices},
                    {"tetrahedra", tetrahedra},
                    {"volume", volume},
                    {"representative_size", representative_size(volume, static_cast<double>(tetrahedra))},
                    {"surface_triangles", surface_triangles}};
  }

  void
  RunSummary::rod(const rod::RodParameters &parameters, const std::size_t elements)
  {
    const auto &section = parameters.section;
    const auto  k       = section.stiffness();
    json["suture"]      = {{"elements", elements},
                           {"centreline", parameters.centreline},
                           {"preset", parameters.preset},
                           {"radius", section.radius},
                           {"EA", k.force[0]},
                           {"GA", k.force[1]},
                           {"EI", k.moment[1]},
                           {"GJ", k.moment[0]},
                           {"self_contact", parameters.contact.enabled}};
    json["solver"]["linear_solver"] =
      parameters.contact.enabled ? "block-tridiagonal LU; sparse LU with contact" : "block-tridiagonal LU";
  }

  void
  RunSummary::coupled_suture(const std::size_t elements, const double length, const double coupling_tolerance)
  {
    json["suture"] = {{"elements", elements},
                      {"length", length},
                      {"coupling_tolerance", coupling_tolerance},
                      {"coupling", "one Newton iteration of tissue and suture, the suture condensed onto the "
                                   "tissue's points; rounds for carriers, contacts and multipliers"}};
  }

  void
  RunSummary::realtime_suture(const std::size_t nodes, const double radius, const double EA, const double EI)
  {
    json["suture"] = {{"nodes", nodes}, {"radius", radius}, {"EA", EA}, {"EI", EI}};
  }

  void
  RunSummary::needle(const NeedleParameters &np, const std::vector<coupling::PunctureEvent> &events,
                     const double peak_pull_force, const std::string &pierce_model)
  {
    auto &list    = json["events"];
    list          = nlohmann::json::array();
    auto &metrics = json["metrics"];
    for (const auto &e : events)
      {
        list.push_back({{"kind", e.kind},
                        {"time", e.time},
                        {"position", {e.position[0], e.position[1], e.position[2]}},
                        {"force", e.force}});
        // a puncture's material point, the surface's normal and the needle's direction at
        // the touch (seed 003's evaluation reads them; the angle between the last two is
        // the entry or exit angle)
        if (e.kind.rfind("puncture_", 0) == 0)
          for (const auto &[key, v] : {std::pair{"reference", &e.reference}, std::pair{"normal", &e.normal},
                                       std::pair{"direction", &e.direction}})
            list.back()[key] = {(*v)[0], (*v)[1], (*v)[2]};
        for (const std::string kind : {"entry", "exit"})
          if (e.kind == "puncture_" + kind && !metrics.contains("puncture_force_" + kind))
            metrics["puncture_force_" + kind] = e.force;
      }
    metrics["peak_pull_force"] = peak_pull_force;
    json["needle"]             = {{"shape", np.shape},
                                  {"wire_diameter", np.wire_diameter},
                                  {"motion", np.motion},
                                  {"enforcement", np.enforcement},
                                  {"puncture_threshold", np.puncture.threshold}};
    if (np.shape == "double-pointed")
      json["needle"].update({{"length", np.length}, {"passes_across", np.passes}});
    else
      json["needle"]["arc_radius"] = np.radius;
    if (np.motion == "pass")
      {
        const auto     pass    = np.planned_pass();
        nlohmann::json entries = nlohmann::json::array();
        for (const auto &p : np.planned_series().passes)
          entries.push_back({p.entry[0], p.entry[1], p.entry[2]});
        json["needle"]["pass"] = {{"stitches", entries.size()},
                                  {"entries", entries},
                                  {"entry_angle_rad", pass.entry_angle},
                                  {"bite_depth", pass.bite_depth},
                                  {"bite_width", pass.bite_width},
                                  {"exit", {pass.exit[0], pass.exit[1], pass.exit[2]}},
                                  {"t_tip_entry", pass.t_tip_entry},
                                  {"t_tip_exit", pass.t_tip_exit},
                                  {"t_swage_exit", pass.t_swage_exit},
                                  {"t_turn_end", pass.t_turn_end},
                                  {"t_end", pass.t_end}};
      }
    if (!pierce_model.empty())
      json["pierce_model"] = pierce_model;
  }

  std::vector<tearing::StitchEvaluation>
  RunSummary::stitch_evaluation(const NeedleParameters &np, const std::vector<coupling::PunctureEvent> &events,
                                const tearing::Wound &wound, const tearing::StitchLimits &limits)
  {
    auto stitches                        = tearing::evaluate_stitches(events, wound, np.radius, limits);
    json["metrics"]["stitch_evaluation"] = tearing::stitches_json(stitches);
    return stitches;
  }

  void
  RunSummary::pass_outcome(const NeedleParameters &np, const std::vector<coupling::PunctureEvent> &events,
                           const double t, const bool suture)
  {
    const nlohmann::json &metrics = json["metrics"];
    // what the pass is for, not reached: no puncture, or the suture drawn out of its hole
    if (np.motion == "pass" && t >= np.planned_pass().t_tip_exit && !metrics.contains("puncture_force_entry"))
      {
        const bool         touched = std::any_of(events.begin(), events.end(),
                                                 [](const auto &e) { return e.kind == "touch_entry"; });
        std::ostringstream why;
        why << "the needle never punctured the tissue, though its tip had turned past the planned exit by t = " << t
            << " s: ";
        if (touched)
          why << "its force stayed below Puncture/Threshold = " << np.puncture.threshold << " N";
        else
          why << "it never touched the tissue";
        incomplete(why.str());
      }
    // the first hole it left says it (a later one the same)
    if (suture)
      for (const auto &e : events)
        if (e.kind == "released")
          {
            std::ostringstream why;
            why << "the suture's far end was drawn out of the tissue at t = " << e.time << " s through the hole at ("
                << e.position[0] << ", " << e.position[1] << ", " << e.position[2]
                << ") m: the suture is too short for this pass";
            incomplete(why.str());
            break;
          }
  }

  void
  RunSummary::incomplete(const std::string &reason)
  {
    // a record finished twice (kept, then finished) gives its reasons once
    auto &reasons = json["incomplete"];
    if (std::find(reasons.begin(), reasons.end(), reason) == reasons.end())
      reasons.push_back(reason);
  }

  void
  RunSummary::step(const nlohmann::json &statistics, const double t)
  {
    nlohmann::json s = statistics;
    s["time"]        = t;
    json["steps"].push_back(s);
  }

  void
  RunSummary::solver(const nlohmann::json &totals)
  {
    for (const auto &[key, value] : totals.items())
      json["solver"][key] = value;
  }

  void
  RunSummary::factorization(const tissue::LinearSolver::Statistics &linear)
  {
    solver({{"factorization_memory_estimate", linear.factorization_memory_estimate},
            {"factorization_memory", linear.factorization_memory},
            {"factorizations", linear.factorizations},
            {"reused_solves", linear.reused_solves},
            {"reuse_iterations", linear.reuse_iterations},
            {"reuse_failures", linear.reuse_failures}});
  }

  void
  RunSummary::timings(const dealii::TimerOutput &timer)
  {
    auto &t = json["timings"];
    for (const auto &[section, seconds] : timer.get_summary_data(dealii::TimerOutput::total_wall_time))
      t[section] = seconds;
  }
} // namespace suturesim::scene
