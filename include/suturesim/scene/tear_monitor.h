#pragma once
/**
 * @file
 * The tear criteria of the accurate stitch (tearing/tear_criterion.h), tract by tract.
 * A tract is the segment a needle's pass through one lip leaves in the tissue: from an
 * entry pierce point to the exit pierce point that follows it along the thread
 * (reference configuration); a stitch through both lips has two. At every accepted
 * state each criterion's process-zone mean over each tract is compared with its
 * critical value; the first state that reaches it is the onset, kept with its time, the suture tension then (the
 * tension the closure is charged to: the grasper's pull on the far end once grasped, else the needle's), where the
 * zone's largest value lies and the direction the tear would open against. summary.json
 * "metrics.tearing"; the cell ratios m / m_c go into the tissue VTU (tear_<criterion>).
 */

#include <suturesim/coupling/accurate/tissue_needle.h>
#include <suturesim/tearing/process_zone.h>
#include <suturesim/tearing/stitch_evaluation.h>
#include <suturesim/tearing/tear_criterion.h>
#include <suturesim/tissue/tissue_model.h>

#include <nlohmann/json.hpp>

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
    /// @p tension (N). Collective.
    void
    update(double t, double tension, tissue::TissueModel &model,
           const std::vector<coupling::AccuratePiercePoint> &pierce);

    /// Per criterion: its unit, critical value and, per tract in the order the tracts
    /// were made, the largest mean / critical so far and the onset (null before it).
    nlohmann::json
    summary() const;

    /// Takes back the tracts of a summary() (a checkpoint's; io/checkpoint.h).
    void
    restore(const nlohmann::json &summary);

  private:
    struct Onset
    {
      double          time = 0, tension = 0, mean = 0;
      tearing::Point3 location{}, direction{};
    };
    struct TractState
    {
      tearing::Tract                    tract;
      std::vector<double>               largest_ratio; ///< per criterion
      std::vector<std::optional<Onset>> onset;         ///< per criterion
    };

    const tearing::TearCriteria &criteria;
    const tearing::Wound        &wound;
    std::vector<TractState>      tract_states;
  };
} // namespace suturesim::scene
