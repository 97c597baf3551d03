#pragma once
/**
 * @file
 * The tear criteria of the accurate stitch (tearing/tear_criterion.h), tract by tract.
 * A tract is the segment a needle's pass through one lip leaves in the tissue: from an
 * entry pierce point to the exit pierce point that follows it along the thread
 * (reference configuration); a stitch through both lips has two. At every accepted
 * state each criterion's process-zone mean over each tract is compared with its
 * critical value; the first state that reaches it is the onset, kept with its time, the suture tension then (the
 * tension the closure is charged to: the grasper's pull on the far end once grasped, else the needle's), the
 * force on the tract's holes then (the larger of its two pierce points' |f| on the tissue: what the thread puts
 * on the tissue there, whichever end pulls; the realtime rule's onset force is that of the tract's top start,
 * realtime/ligament_tearing.h), where the zone's largest value lies and the direction the tear would open
 * against. summary.json
 * "metrics.tearing"; the cell ratios m / m_c go into the tissue VTU (tear_<criterion>),
 * and the largest zone mean / critical value of each state into forces.csv.
 *
 * The onset's time, tension and force are interpolated linearly in the mean between the last
 * accepted state below the critical value and the first at or above it, as the closure
 * is read at the gap's crossing (core/level_crossing.h): read at the step, an onset
 * would move by up to a step's rise of the tension (0.23 N, 2.5 %, per 20 ms step near
 * the default stitch's onset; adaptive steps reach 80 ms), which is of the order of the
 * change under refinement it is meant to show (docs/tearing.md).
 */

#include <suturesim/coupling/accurate/tissue_needle.h>
#include <suturesim/tearing/process_zone.h>
#include <suturesim/tearing/stitch_evaluation.h>
#include <suturesim/tearing/tear_criterion.h>
#include <suturesim/tissue/tissue_model.h>

#include <nlohmann/json.hpp>

#include <cmath>
#include <optional>
#include <vector>

namespace suturesim::scene
{
  class TearMonitor
  {
  public:
    /// @p wound: the cut the zones do not reach across (tearing::ProcessZones); it must
    /// outlive the monitor (no faces: the zones are whole capsules).
    TearMonitor(const tearing::TearCriteria &criteria, const tearing::Wound &wound);

    /// The tracts of @p pierce (the needle's pierce points, newest first) and every
    /// criterion over them at the accepted state of time @p t (s), with suture tension
    /// @p tension (N) and each pierce point's force on the tissue @p forces (|f|, N; one
    /// per pierce point). Collective.
    void
    update(double t, double tension, tissue::TissueModel &model,
           const std::vector<coupling::AccuratePiercePoint> &pierce, const std::vector<double> &forces);

    /// Per criterion: its unit, critical value, the largest mean / critical over its
    /// tracts (absent before the first tract) and, per tract in the order the tracts
    /// were made, the largest mean / critical so far, the latest, and the onset (null
    /// before it); the last state's time and tension, which a restart interpolates from.
    nlohmann::json
    summary() const;

    /// Takes back the tracts of a summary() (a checkpoint's; io/checkpoint.h).
    void
    restore(const nlohmann::json &summary);

    /// Per criterion, the largest zone mean / critical value over the tracts at the last
    /// update() (forces.csv's tear_<criterion> columns: the criterion's history against
    /// the tension); NaN while there is no tract or no tract's zone holds a point.
    std::vector<double>
    current() const;
    /// Per criterion, the force on the holes (N) of the tract whose zone mean / critical
    /// value is largest at the last update() (forces.csv's tear_force_<criterion>
    /// columns: what the onset's force is interpolated from); NaN as current() is.
    std::vector<double>
    current_forces() const;

  private:
    struct Onset
    {
      double          time = 0, tension = 0, force = 0, mean = 0;
      tearing::Point3 location{}, direction{};
    };
    struct TractState
    {
      tearing::Tract                    tract;
      std::vector<double>               largest_ratio; ///< per criterion
      std::vector<double>               last_ratio;    ///< per criterion, at the last state; NaN before it
      std::vector<std::optional<Onset>> onset;         ///< per criterion
      double last_force = std::nan(""); ///< on its holes at the last state, N; NaN before it or once a hole is gone

      TractState(const tearing::Tract &tract, std::size_t n_criteria);
    };

    const tearing::TearCriteria &criteria;
    const tearing::Wound        &wound;
    std::vector<TractState>      tract_states;
    /// Time (s) and suture tension (N) of the last update(); NaN before the first.
    double last_time = std::nan(""), last_tension = std::nan("");
  };
} // namespace suturesim::scene
