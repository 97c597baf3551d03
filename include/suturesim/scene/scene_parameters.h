#pragma once
/**
 * @file
 * What a scene file says that every model path reads: its name, the model path, the
 * bodies and their subsections (Mesh, Tissue, Suture), the needle, the closure
 * measurement and the time. Each part is declared and parsed by the class that owns it
 * (mesh/, tissue/, rod/, scene/needle_parameters.h, scene/wound_closure.h,
 * core/time_parameters.h); this struct only gathers them, so that a scenario
 * (scene/scenario.h) finds everything it needs in one place.
 */

#include <suturesim/core/parameter_file.h>
#include <suturesim/core/time_parameters.h>
#include <suturesim/mesh/mesh_loader.h>
#include <suturesim/rod/rod_parameters.h>
#include <suturesim/scene/needle_parameters.h>
#include <suturesim/scene/wound_closure.h>
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
    TimeParameters                  time;

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
