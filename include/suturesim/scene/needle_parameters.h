#pragma once
/**
 * @file
 * The needle of a scene and how it couples to the tissue, shared by both model paths:
 * subsections "Needle" (shape, size, motion: a planned surgical pass or keyframes,
 * suture attached at the swage), "Puncture" (coupling/needle_puncture.h declares its
 * own law's parameters) and "Pierce points" (transverse stiffness, spacing, the
 * recorded points; the friction law of coupling/coulomb_friction.h declares its own; a
 * subsection "Accurate" for the accurate path's enforcement and coupled solve). The
 * realtime path's XPBD mass scaling of pierce constraints is Realtime/Pierce mass
 * ratio (scene/realtime_settings.h). Every default is the in-class initialiser,
 * declared through it (a test parses an empty file back to it).
 */

#include <suturesim/core/parameter_file.h>
#include <suturesim/coupling/coulomb_friction.h>
#include <suturesim/coupling/needle_puncture.h>
#include <suturesim/tools/surgical_pass.h>

#include <deal.II/base/parameter_handler.h>

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace suturesim::scene
{
  struct NeedleParameters
  {
    std::string           shape         = "none"; ///< none, 3/8, 1/2, double-pointed
    double                radius        = 0.008;  ///< m
    double                length        = 0.01;   ///< m, a double-pointed needle's, point to point
    double                wire_diameter = 4e-4;   ///< m
    bool                  attach_suture = true;
    std::string           motion        = "pass"; ///< pass | keyframes
    tools::PassParameters pass          = default_pass();
    tools::SeriesParameters series;    ///< a running suture's passes (one by default)
    /// "t: cx, cy, cz, rx, ry, rz; ...": the arc centre (m) and rotation vector (rad)
    std::string       keyframe_text = "0: 0, 0, 0.02, 0, 0, 0";
    tools::Trajectory keyframes; ///< pose of the arc centre (body frame of the needle)
    std::string       jaws_text; ///< "t: open; t: closed; ..."
    std::vector<std::pair<double, bool>> jaws; ///< (time, opens), in time order
    std::string         passes_text; ///< "t; t; ...": Passes across
    std::vector<double> passes;      ///< when the Endo Stitch passes the needle to its other jaw, s
    double            density = 7800; ///< of the wire, kg/m³ (a free needle's weight)
    double            drag    = 1e-3; ///< B of a free needle, N s/m

    coupling::PunctureParameters puncture;
    coupling::FrictionParameters friction;
    double      transverse_stiffness = 500;       ///< N/m
    double      spacing              = 1e-4;      ///< m
    unsigned    recorded             = 4;         ///< pierce points given columns in forces.csv
    std::string enforcement          = "penalty"; ///< penalty | lagrange (accurate path)
    double      coupling_tolerance   = 1e-7;      ///< m, tissue–suture rounds (accurate path)
    unsigned    coupling_iterations  = 40;        ///< accurate path
    double      load_radius          = 0;         ///< m, spread of a pierce load (both paths)
    /// whether a spread pierce load or touch takes tissue beyond the wound's faces too
    /// (true, as before 2026-12-05) or stops at them (false: accurate path)
    bool        load_across_wound    = true;
    double      tail_length          = 0.015;     ///< m, an interrupted series' tail when held
    /// an interrupted series: where the other hand lays each tail, from the stitch's
    /// planned exit point (m, world axes), over tail_lay_duration (s; 0: held still)
    Eigen::Vector3d tail_lay          = Eigen::Vector3d(0.008, 0, 0.002);
    double          tail_lay_duration = 0;
    /// and how far it draws the tail on from there until the stitch's tightening ends (m)
    Eigen::Vector3d tail_draw         = Eigen::Vector3d::Zero();

    /// The pass of a scene that gives none: 3 mm deep, drawn 30 mm up after the turn.
    static tools::PassParameters
    default_pass();

    /// When the driver's jaws open (true) and close (false), in time order: Jaws, or the
    /// planned pass's regrasp.
    std::vector<std::pair<double, bool>>
    jaw_changes() const;
    /// The planned series' reloads (from, to), s: the driver's jaws open while the other
    /// hand holds the needle still (tools::SurgicalSeries::reloads); none otherwise.
    std::vector<std::pair<double, double>>
    reloads() const;
    /// The entry that lets the needle go, as (subsection, key): Needle/Jaws, or
    /// Needle/Pass/Regrasp exposure for the planned regrasp.
    std::pair<std::string, std::string>
    release_entry() const
    {
      return jaws.empty() ? std::pair<std::string, std::string>{"Needle/Pass", "Regrasp exposure"}
                          : std::pair<std::string, std::string>{"Needle", "Jaws"};
    }
    /// Whether the planned pass lets the needle go (Pass/Regrasp exposure).
    bool
    planned_regrasp() const
    {
      return present() && motion == "pass" && pass.regrasp_exposure > 0;
    }
    /// Whether the jaws ever let the needle go.
    bool
    released() const
    {
      return !jaws.empty() || planned_regrasp();
    }

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

    /// The planned pass (motion = pass), for its times and points; the first of a series.
    tools::SurgicalPass
    planned_pass() const;
    /// Every pass of the series (Needle/Pass/Stitches), with the whole motion.
    tools::SurgicalSeries
    planned_series() const;

    /// Refuses, through @p pass (the scope of Needle/Pass), a planned pass (any of a series) whose entry
    /// point lies farther from the tissue's surface than half the bite depth δ: a pass
    /// planned for a flat surface through E reaches δ below E, so an entry point δ above
    /// the tissue misses it and one δ/2 away only grazes it (or starts deep inside).
    /// @p triangles index @p vertices, the surface in its reference state (m).
    void
    check_entry_on_surface(const std::vector<std::array<std::uint32_t, 3>> &triangles,
                           const Eigen::Matrix3Xd &vertices, const ParameterScope &pass) const;

    /// Declares "Needle", "Puncture" and "Pierce points" into the current (root) subsection.
    static void
    declare(dealii::ParameterHandler &prm);
    /// Parses them; bad values fail through @p root (file, line, key).
    void
    parse(dealii::ParameterHandler &prm, const ParameterScope &root);

    /// forces.csv columns both paths keep: needle force (N), torque (N*m) and arc centre
    /// (m), then per recorded pierce point its state, ζ, slip velocity, normal and
    /// friction force.
    void
    add_columns(std::vector<std::string> &columns) const;

  private:
    static void
    declare_needle(dealii::ParameterHandler &prm);
    void
    parse_needle(dealii::ParameterHandler &prm, const ParameterScope &scope);
    void
    parse_jaws(dealii::ParameterHandler &prm, const ParameterScope &scope);
    void
    parse_passes_across(dealii::ParameterHandler &prm, const ParameterScope &scope);
    static void
    declare_pierce_points(dealii::ParameterHandler &prm);
    void
    parse_pierce_points(dealii::ParameterHandler &prm, const ParameterScope &scope);
  };
} // namespace suturesim::scene
