#pragma once
/**
 * @file
 * The needle of a scene and how it couples to the tissue, shared by both model paths:
 * subsections "Needle" (shape, size, motion: a planned surgical pass or keyframes,
 * suture attached at the swage), "Puncture" (threshold force, tip penalty) and "Pierce
 * points" (transverse stiffness, Coulomb friction, spacing, enforcement). Parsed once
 * into plain structs the paths use (tools/, coupling/).
 *
 * Default puncture threshold 0.7 N: the force to puncture with 3-0 to 5-0 taper and
 * reverse-cutting suture needles measured 0.61–0.90 N (Maloney et al. 2025, Ann. Plast.
 * Surg. 95:423, rabbit ear cartilage); sheepskin shows the entry and exit peaks
 * (Frick et al. 2001, J. Biomech. 34:1335). Scenes set their own.
 */

#include <suturesim/coupling/coulomb_friction.h>
#include <suturesim/coupling/needle_puncture.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/tools/surgical_pass.h>

#include <deal.II/base/parameter_handler.h>

#include <nlohmann/json.hpp>

#include <optional>
#include <string>

namespace suturesim::scene
{
  struct NeedleParameters
  {
    std::string shape         = "none"; ///< none, 3/8, 1/2
    double      radius        = 0.008;  ///< m
    double      wire_diameter = 4e-4;   ///< m
    bool        attach_suture = true;
    std::string motion        = "pass"; ///< pass | keyframes
    tools::PassParameters pass;
    tools::Trajectory     keyframes; ///< pose of the arc centre (body frame of the needle)

    coupling::PunctureParameters puncture{0.7, 2000, 1e-3};
    coupling::FrictionParameters friction{0.2, 500, 0.05};
    double      transverse_stiffness = 500;  ///< N/m
    double      spacing              = 1e-4; ///< m
    double      mass_ratio           = 10;
    std::string enforcement          = "penalty"; ///< penalty | lagrange (accurate path)
    unsigned    recorded             = 4; ///< pierce points given columns in forces.csv
    double      coupling_tolerance   = 1e-7; ///< m, tissue–suture rounds (accurate path)
    unsigned    coupling_iterations  = 40;

    bool
    present() const
    {
      return shape != "none";
    }

    /// The needle's geometry (shape ≠ none).
    tools::CurvedNeedle
    needle() const;

    /// The needle's motion: the planned pass, or the keyframes.
    tools::Trajectory
    trajectory() const;

    /// The planned pass (motion = pass), for its times and points.
    tools::SurgicalPass
    planned_pass() const;

    /// Declares "Needle", "Puncture" and "Pierce points" into the current (root) subsection.
    static void
    declare(dealii::ParameterHandler &prm);
    /// Parses them; bad values fail through @p root (file, line, key).
    void
    parse(dealii::ParameterHandler &prm, const ParameterScope &root);

    // --- the record both paths keep ------------------------------------------------------

    /// forces.csv columns: needle force (N), torque (N*m) and arc centre (m), then per
    /// recorded pierce point its state, ζ, slip velocity, normal and friction force.
    void
    add_columns(std::vector<std::string> &columns) const;

    /// summary.json: @p events (in time order) under "events", the first entry and exit
    /// puncture forces and @p peak_pull_force under "metrics", the needle and its pass
    /// under "needle".
    void
    write_summary(nlohmann::json &summary, const std::vector<coupling::PunctureEvent> &events,
                  double peak_pull_force) const;
  };
} // namespace suturesim::scene
