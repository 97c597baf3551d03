#pragma once
/**
 * @file
 * What a scene file says that every model path reads: its name, the model path, the
 * bodies and their subsections (Mesh, Tissue, Suture), the needle, the closure
 * measurement, the knot and the time. Each part is declared and parsed by the class
 * that owns it (mesh/, tissue/, rod/, scene/needle_parameters.h, scene/wound_closure.h,
 * scene/knot_parameters.h, core/time_parameters.h); this struct only gathers them, so
 * that a scenario (scene/scenario.h) finds everything it needs in one place.
 */

#include <suturesim/core/parameter_file.h>
#include <suturesim/core/time_parameters.h>
#include <suturesim/knot/planner_settings.h>
#include <suturesim/mesh/mesh_loader.h>
#include <suturesim/rod/rod_parameters.h>
#include <suturesim/scene/needle_parameters.h>
#include <suturesim/scene/wound_closure.h>
#include <suturesim/tearing/stitch_evaluation.h>
#include <suturesim/tearing/tear_criterion.h>
#include <suturesim/tissue/boundary_conditions.h>
#include <suturesim/tissue/material.h>
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/base/parameter_handler.h>

#include <optional>
#include <string>

namespace suturesim::scene
{
  struct SceneParameters
  {
    const ParameterFile *file = nullptr; ///< for errors found later (file, line, key)
    std::string          name, model, bodies;

    mesh::MeshParameters            mesh;
    tissue::TissueParameters        tissue;
    std::optional<tissue::Material> material;
    tissue::BoundaryConditions      boundary_conditions;
    rod::RodParameters              suture;
    NeedleParameters                needle;
    ClosureParameters               closure;
    tearing::TearCriteria           tearing; ///< evaluated by the accurate stitch (scene/tear_monitor.h)
    tearing::StitchLimits           stitch_evaluation; ///< seed 003's, both paths (tearing/stitch_evaluation.h)
    TimeParameters                  time;
    knot::PlannerSettings           knot; ///< Knot (scene/knot_parameters.h)

    bool
    has_tissue() const
    {
      return bodies != "suture";
    }
    bool
    has_suture() const
    {
      return bodies != "tissue";
    }

    /// The scope of subsection @p path of the scene file ("" for the top level).
    ParameterScope
    scope(const std::string &path = "") const
    {
      return ParameterScope(*file, path);
    }

    /// The wound for the stitch evaluation: the triangles of a surface over @p vertices
    /// (reference, m) whose @p tags are among Stitch evaluation/Wound faces, else among
    /// Closure/Face contact's; none when both are empty. An unknown face in @p mesh is an
    /// InputError naming the entry.
    template <typename Tag>
    tearing::Wound
    wound(const mesh::MeshInfo &mesh, const Eigen::Matrix3Xd &vertices,
          const std::vector<std::array<std::uint32_t, 3>> &triangles, const std::vector<Tag> &tags) const
    {
      const auto        faces = wound_face_ids(mesh);
      std::vector<char> on_face(tags.size(), 0);
      for (std::size_t t = 0; t < tags.size(); ++t)
        for (const auto id : faces)
          on_face[t] = on_face[t] || static_cast<long>(tags[t]) == static_cast<long>(id);
      return tearing::Wound(vertices, triangles, on_face);
    }
    /// The ids of wound()'s faces.
    std::vector<dealii::types::boundary_id>
    wound_face_ids(const mesh::MeshInfo &mesh) const;

    /// Declares the top-level entries and the subsections above (the Time subsection
    /// with @p integrators, name → description, as the choices of Time/Integrator).
    static void
    declare(dealii::ParameterHandler &prm, const std::map<std::string, std::string> &integrators);

    /// Name, model path, bodies, needle and closure.
    void
    parse_common(dealii::ParameterHandler &prm, const ParameterFile &file);
    /// The bodies' subsections: Suture when the scene has a suture, then Mesh and
    /// Tissue (material, boundary conditions) when it has tissue.
    void
    parse_bodies(dealii::ParameterHandler &prm);
    /// The Time subsection, whole.
    void
    parse_time(dealii::ParameterHandler &prm);
  };
} // namespace suturesim::scene
