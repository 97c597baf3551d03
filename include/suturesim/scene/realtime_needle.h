#pragma once
/**
 * @file
 * The needle of a realtime scene: puts it into the world as a tool moved by the scene's
 * trajectory (NeedleParameters), places the attached suture at the swage, and records
 * what the force curves need: forces.csv columns for the needle's force, torque
 * and arc centre, the suture's tension at both ends and, per recorded pierce point, its state
 * (0 none, 1 stick, 2 slip), thread coordinate, slip velocity, normal and friction
 * force; summary.json events (touch, puncture, passage onto the suture, release) and
 * the metrics puncture_force_entry, puncture_force_exit (the first of each, N) and
 * peak_pull_force (largest needle force after the turn, N).
 */

#include <suturesim/realtime/world.h>
#include <suturesim/scene/needle_parameters.h>
#include <suturesim/tearing/stitch_evaluation.h>

#include <nlohmann/json.hpp>

#include <optional>
#include <string>
#include <vector>

namespace suturesim::scene
{
  class RealtimeNeedle
  {
  public:
    /// Adds the needle to @p world (as its next tool; before initialize()), its pierce
    /// points of the model named @p pierce_model (realtime/pierce_model.h, or
    /// "automatic") with XPBD mass scaling @p mass_ratio; a spread pierce point sees the
    /// tissue across @p wound's faces as Pierce points/Load across the wound says
    /// (@p wound, the tissue's reference, must outlive the needle).
    RealtimeNeedle(const NeedleParameters &parameters, realtime::World &world, const std::string &pierce_model,
                   double mass_ratio, const tearing::Wound &wound);

    /// Replaces @p points by a straight suture of the same length and number of nodes
    /// leaving the needle's swage along the needle (the pose at t = 0).
    static void
    place_suture(const NeedleParameters &parameters, std::vector<Eigen::Vector3d> &points);

    std::size_t
    tool() const
    {
      return tool_index;
    }
    /// The pose of the needle's holder at @p t: the driver's, or during a reload the
    /// other hand's (the needle's pose when it took it). In an interrupted series
    /// (Needle/Pass/Series) @p pulls and @p ties give when each stitch's pull and
    /// tightening stopped (tools::SurgicalSeries::pose).
    tools::Pose
    pose(double t, const std::vector<double> &pulls = {}, const std::vector<double> &ties = {}) const
    {
      return parked ? *parked : series ? series->pose(t, pulls, ties) : path.pose(t);
    }

    /// Opens or closes the driver's jaws at the changes up to time @p t (Needle/Jaws or
    /// the planned regrasp): the needle let go (World::release_needle) or taken where it
    /// lies, relative to the driver's pose at the change (World::grasp_needle); events
    /// "needle_released" and "needle_grasped" at the jaws. A reload (the planned series'
    /// reloads) hands the needle to the other hand instead of letting it go, and back to
    /// the driver when the jaws close (World::hand_needle_over; events
    /// "needle_handed_over" and "needle_grasped"). The jaws sit where the driver held the
    /// needle at the start (Pass/Grip point); ParameterError("Jaws") when they open or
    /// close inside the tissue, or close farther than the wire's diameter from the needle.
    /// The Endo Stitch's passes across (Needle/Passes across) turn its double-pointed
    /// needle end for end (World::reverse_needle; event "needle_passed_across" at its
    /// middle); ParameterError("Passes across") when the needle is still in the tissue.
    void
    operate_jaws(realtime::World &world, double t);

    void
    add_columns(std::vector<std::string> &columns) const;
    /// Writes this step's values from row[c] on (advancing c) and tracks the metrics.
    void
    fill_row(const realtime::World &world, std::vector<double> &row, std::size_t &c);
    /// The events in time order (punctures, passage onto the suture, release).
    std::vector<coupling::PunctureEvent>
    events(const realtime::World &world) const;
    /// While the jaws were open: metrics.free_needle of summary.json, with the time the
    /// needle was free (s), the largest move of its centroid from where it was let go
    /// (m), and the pierce points holding it when taken again; empty without a release.
    nlohmann::json
    free_record(const realtime::World &world) const;

    /// Largest needle force after the turn, N.
    double
    peak_pull_force() const
    {
      return peak_pull;
    }

  private:
    const NeedleParameters &prm;
    tools::Trajectory       path;
    std::optional<tools::SurgicalSeries> series; ///< an interrupted series' plan
    double                  pull_start = 0;
    std::size_t             tool_index = 0;
    double                  peak_pull  = 0;
    std::vector<std::pair<double, bool>> jaws; ///< (time, opens)
    std::size_t             next_jaw   = 0; ///< the next of jaws
    std::size_t             next_pass  = 0; ///< the next of NeedleParameters::passes
    std::vector<std::pair<double, double>> reloads; ///< (from, to), s
    std::optional<tools::Pose> parked; ///< the other hand's pose during a reload
    Eigen::Vector3d         jaw_point;      ///< in the driver's frame, m
    Eigen::Vector3d         let_go = Eigen::Vector3d::Zero(); ///< the centroid where last let go, m
    double                  released_at = 0, free_time = 0, largest_move = 0; ///< s, s, m
    std::vector<std::size_t> holding;       ///< pierce points at each grasp
    std::vector<coupling::PunctureEvent> jaw_events;
  };
} // namespace suturesim::scene
