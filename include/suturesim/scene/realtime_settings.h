#pragma once
/**
 * @file
 * The "Realtime" subsection of a scene (Model = realtime): the tissue model, integrator,
 * suture model, pierce model and self-collision response, each chosen from its registry
 * with its own parameters in a subsection of the same name (core/parameter_adapter.h);
 * the haptic rate and substeps, suture–tissue contact, the stability policy.
 * RealtimeModels are the chosen models built from it, so that --validate reports a bad
 * model value with file and line.
 */

#include <suturesim/core/model_parameters.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/realtime/integrator.h>
#include <suturesim/rod/rod_parameters.h>
#include <suturesim/realtime/suture_model.h>
#include <suturesim/realtime/tissue_model.h>
#include <suturesim/tearing/ligament_tear.h>

#include <deal.II/base/parameter_handler.h>

#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace suturesim::scene
{
  struct RealtimeSettings
  {
    std::string tissue_model   = "volume";
    std::string integrator     = "xpbd";
    std::string suture_model   = "xpbd-rod";
    std::string pierce_model   = "automatic";
    std::string self_collision = "off";
    /// XPBD: the suture nodes' inverse masses within a pierce constraint are capped at
    /// this multiple of the tissue point's (mass scaling), 1
    double      pierce_mass_ratio  = 10;
    bool        contact            = true;
    double      contact_stiffness  = 100;  ///< N/m
    double      contact_depth      = 1e-3; ///< m
    bool        contact_load       = false; ///< the ftl thread's pull into the surface loads it
    double      face_contact_stiffness = 0; ///< N/m per pair of the wound's faces; 0: none
    double      rate               = 1000; ///< Hz
    unsigned    substeps           = 1;
    /// loaded surface triangles split into n² for the consistent nodal loads ∫ t Nᵢ dA
    unsigned    traction_subdivision = 1;
    bool        refuse_above_limit = false;
    bool        pacing             = false;
    /// Seed 004's node-access points the suture passes through (name, position in m) and
    /// their stiffness (N/m; 0: that of the suture's links), realtime/node_access.h
    std::vector<std::pair<std::string, Eigen::Vector3d>> access_points;
    double                                               access_stiffness = 0;
    /// A blunt probe (seed 004's external stage, World::add_probe), subsection Probe:
    /// length 0 for none
    struct Probe
    {
      double                                length    = 0;       ///< m
      double                                radius    = 1e-3;    ///< m
      double                                stiffness = 1e3;     ///< N/m
      Eigen::Vector3d                       tip       = Eigen::Vector3d::Zero(); ///< m, at t = 0
      Eigen::Vector3d                       axis      = Eigen::Vector3d::UnitZ();
      /// its keyframes, t (s) → displacement of the tip (m), as a prescribed end's
      rod::EndCondition path;

      /// The tip at time @p t: linear between keyframes, constant outside, m.
      Eigen::Vector3d
      position(const double t) const
      {
        return path.position(t, tip);
      }
    } probe;
    /// Seed 003's tear-into and tear-through (subsection Tearing; realtime/ligament_tearing.h)
    tearing::LigamentTearParameters tearing;

    /// Declares the entries of the current subsection ("Realtime"), and its subsection
    /// Tearing.
    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm, const ParameterScope &scope);
  };

  /// The models a RealtimeSettings chose, built (those of absent bodies left empty).
  struct RealtimeModels
  {
    std::unique_ptr<realtime::TissueModel> tissue;
    std::unique_ptr<realtime::Integrator>  integrator;
    std::unique_ptr<realtime::SutureModel> suture;
    ParameterValues                        self_collision;

    /// Builds them from the current subsection ("Realtime", @p scope); a bad value fails
    /// through @p scope.
    RealtimeModels(dealii::ParameterHandler &prm, const ParameterScope &scope, const RealtimeSettings &settings,
                   bool with_tissue, bool with_suture);
  };
} // namespace suturesim::scene
