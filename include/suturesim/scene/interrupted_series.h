#pragma once
/**
 * @file
 * An interrupted series (Needle/Pass/Series = interrupted), stitch by stitch, as both
 * paths run it: when the other hand takes a stitch's tail, where the stitch is tied off
 * (its two strands held, the thread cut beside the needle strand's hold), and the record
 * of it (metrics.interrupted_series). The paths hold and cut their own threads: the
 * realtime world's tools and follow-the-leader cut (scene/realtime_world.h), the
 * Cosserat rod's clamped nodes and left-out element (scene/accurate_stitch.h).
 *
 * For stitch k, between steps:
 *  - its tail is the suture's last end (k = 0), or the cut end the stitch before left;
 *  - once the thread beyond its entry hole is no longer than Tail length (or its pull has
 *    ended) the other hand takes the tail where it lies, and its pull stops there
 *    (tools::SurgicalSeries::pose): the tightening draws the stitch closed against it;
 *  - once it is tied off (ClosureMonitor::stitch_ties()), each strand is held one stitch
 *    width (entry to exit) beyond its hole, where strands tied over the wound meet, so that
 *    the strands crossing over the wound are kept (held at their holes the realtime
 *    stitches opened again to 0.23-0.28 mm of 0.35-0.40 mm; docs/tearing.md), and the
 *    thread is cut next to the needle strand's hold: the rest, on the needle, is the next
 *    stitch's suture.
 */

#include <suturesim/core/parameter_file.h>
#include <suturesim/scene/needle_parameters.h>
#include <suturesim/scene/wound_closure.h>
#include <suturesim/tools/surgical_pass.h>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

namespace suturesim::scene
{
  class InterruptedSeries
  {
  public:
    /// A pierce point as the series reads it, in the order the paths keep them: thread
    /// coordinate ascending (ζ from the tip along needle and thread), the newest first.
    struct Hole
    {
      double          zeta = 0; ///< m
      Eigen::Vector3d position = Eigen::Vector3d::Zero(); ///< where the tissue point is now, m
      bool            on_suture = false; ///< beyond the swage
    };
    /// What a step asks of the thread (node indices along the suture, 0 at the swage).
    struct Actions
    {
      std::size_t stitch = 0; ///< the stitch they are for
      /// the node the other hand takes now (the tail), or none
      std::optional<std::size_t> tail;
      /// the nodes the tie-off holds now (the needle strand's, and the tail strand's
      /// unless the tail's hand holds that one), empty: no tie-off
      std::vector<std::size_t> tie;
      /// with a tie-off: the element (link) cut, between nodes cut and cut + 1
      std::size_t cut = 0;
    };

    /// The series of @p needle (its passes, Tail length, Tail lay); @p arc: each suture
    /// node's reference arc length from the swage (m, ascending from 0); @p needle_length:
    /// the needle's (ζ at the swage), m.
    InterruptedSeries(const NeedleParameters &needle, std::vector<double> arc, double needle_length);

    /// The closure windows of the series' stitches (ClosureMonitor::set_stitches): each
    /// closes from its pull's start, is tied off from its pull's end (or its tail's
    /// taking) to its tightening's end.
    static std::vector<ClosureMonitor::StitchWindow>
    windows(const tools::SurgicalSeries &planned);

    /// Between steps at @p t: the tail taken (closure.start_stitch() called for it; @p node
    /// gives a suture node's position now, m) and the stitch under way tied off once
    /// @p closure has tied it. A tie-off the thread cannot take fails through @p pass
    /// ("Pull", one line naming the stitch).
    Actions
    advance(double t, const std::vector<Hole> &holes, ClosureMonitor &closure, const ParameterScope &pass,
            const std::function<Eigen::Vector3d(std::size_t)> &node);

    /// How far the other hand has carried stitch @p k's tail at @p t from where it took it
    /// (m): nothing before, then at a constant speed to its Tail lay (the stitch's planned
    /// exit point + the offset) over the Tail lay duration, then on by the Tail draw at a
    /// constant speed until the stitch's tightening's planned end, stopping at the
    /// stitch's tie-off (@p ties, ClosureMonitor::stitch_ties()); nothing without a lay.
    Eigen::Vector3d
    tail_displacement(std::size_t k, double t, const std::vector<double> &ties) const;
    /// Where stitch @p k's tail is held at @p t (m): where it was taken, carried by
    /// tail_displacement().
    Eigen::Vector3d
    tail_position(std::size_t k, double t, const std::vector<double> &ties) const
    {
      return stitches.at(k).taken + tail_displacement(k, t, ties);
    }
    /// Stitch @p k's tail node once taken (its hand's), else none.
    std::optional<std::size_t>
    tail_node(std::size_t k) const
    {
      return std::isfinite(stops.at(k)) ? std::optional<std::size_t>(stitches[k].tail) : std::nullopt;
    }

    /// Per stitch: when its tail was taken and its pull stopped (s; ∞ before): the
    /// needle's pose (tools::SurgicalSeries::pose) reads them.
    const std::vector<double> &
    pull_stops() const
    {
      return stops;
    }
    std::size_t
    size() const
    {
      return stitches.size();
    }
    /// The other hand's pull on stitch @p k's tail (N) when it is tied off (the paths
    /// measure it: the tail's tool, the reaction at the rod's clamped node).
    void
    set_tail_force(std::size_t k, double force)
    {
      stitches.at(k).tail_force = force;
    }
    /// Every node a hand or a tie holds so far, and every element cut (a restart
    /// applies them again).
    std::vector<std::size_t>
    held_nodes() const;
    std::vector<std::size_t>
    cut_elements() const;

    /// metrics.interrupted_series: per stitch when its tail was taken (s) and whether its
    /// pull stopped for it (the tail short before the pull's end), the suture node its
    /// thread was cut at and the hand's pull on its tail then (N; null before its tie-off).
    void
    write(nlohmann::json &metrics) const;
    nlohmann::json
    snapshot() const;
    /// Takes a snapshot() back; std::invalid_argument when it does not fit this series.
    void
    restore(const nlohmann::json &j);

  private:
    struct Stitch
    {
      double                   pull_end = 0;  ///< its pull's planned end, s
      std::size_t              points   = 0;  ///< pierce points counted at its tie-off (0 before)
      std::size_t              cut      = 0;  ///< the needle strand's held node (the cut beside it)
      std::size_t              tail     = 0;  ///< its tail's node, once taken
      std::vector<std::size_t> tie;           ///< the nodes its tie-off holds
      Eigen::Vector3d          lay   = Eigen::Vector3d::Zero(); ///< its tail's lay: the planned exit + offset, m
      Eigen::Vector3d          taken = Eigen::Vector3d::Zero(); ///< where its tail was taken, m
      double                   tightened = 0; ///< its tightening's planned end, s
      double                   tail_force = std::numeric_limits<double>::quiet_NaN(); ///< at its tie-off, N
    };
    /// The first node at or beyond arc length @p s (clamped to the last).
    std::size_t
    node_at_or_beyond(double s) const;
    /// The last node at or before arc length @p s (0 before the first).
    std::size_t
    node_at_or_before(double s) const;

    std::vector<Stitch> stitches;
    std::vector<double> stops;
    std::vector<double> arc;
    double              tail_length = 0, needle_length = 0, lay_duration = 0;
    Eigen::Vector3d     draw = Eigen::Vector3d::Zero();
  };
} // namespace suturesim::scene
