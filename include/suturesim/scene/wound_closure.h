#pragma once
/**
 * @file
 * Wound closure, measured (subsection "Closure"): pairs of tissue probes across the
 * wound, each giving the gap g = (x_b − x_a)·e with e = (X_b − X_a)/|X_b − X_a| (the
 * opening along the line between the two reference points; negative when the edges
 * overlap). The first pair decides closure: the first time its gap falls below
 * "Closure gap" the wound counts as closed. The closure time and tension are read where
 * the gap crosses the closure gap, interpolated linearly between the two steps that
 * bracket the crossing: g(t) and T(t) are smooth over a step, so the reading's error is
 * O(Δt²) instead of the step's O(Δt T') (event location by interpolation, Shampine &
 * Thompson 2000, Appl. Numer. Math. 32, 477–486; on the accurate stitch T' ≈ 10 N/s,
 * so a 20 ms step alone would move the reading by up to 0.2 N). With "Tie off" every
 * prescribed motion stops once the gap falls below
 * "Tie-off gap" (by default the closure gap) — both suture ends are fixed where they
 * are, the tie-off of an interrupted stitch until knots exist. A tie-off gap below the
 * closure gap draws the stitch a little further, as a surgeon lays the first throw
 * past the edges' meeting, so that the held wound stays closed with a margin.
 * Closure counts from "Start time" on: the needle crossing the wound pushes its edges
 * about, and a gap that dips then is not a closure by the suture.
 * Both model paths read the same struct.
 */

#include <suturesim/mesh/mesh_loader.h>
#include <suturesim/core/parameter_file.h>

#include <deal.II/base/parameter_handler.h>

#include <Eigen/Core>

#include <nlohmann/json.hpp>

#include <algorithm>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace suturesim::scene
{
  struct ClosureParameters
  {
    struct Pair
    {
      std::string     name;
      Eigen::Vector3d a = Eigen::Vector3d::Zero(), b = Eigen::Vector3d::Zero(); ///< reference points, m
    };
    std::vector<Pair> pairs;
    double            closure_gap = 1e-4; ///< m
    double            start_time  = 0;    ///< s
    bool              tie_off     = true;
    double            tie_off_gap = 1e-4; ///< m; parsed 0 means the closure gap
    /// the tie-off waits for every pair's gap (a series, a pair per stitch), not the first's
    bool              tie_off_every_pair = false;
    /// An interrupted series (Needle/Pass/Series, set by SceneParameters): stitch k is tied
    /// off on its own, on pair k's gap within its tightening (ClosureMonitor::set_stitches)
    bool              tie_off_each_stitch = false;
    /// Accurate path: the incision's two faces (boundary names or ids; empty: no
    /// contact between them), the penalty per vertex pair (N/m) and the gap below which
    /// a pair is loaded (m); coupling/accurate/wound_contact.h.
    std::vector<std::string> face_contact;
    double                   face_contact_stiffness = 5e4;
    double                   face_contact_margin    = 5e-5;
    std::shared_ptr<ParameterScope> scope; ///< the subsection, for errors found later

    /// The face contact's two boundary ids in @p mesh; an InputError naming the
    /// parameter when a face is not in it.
    std::pair<dealii::types::boundary_id, dealii::types::boundary_id>
    face_contact_ids(const mesh::MeshInfo &mesh) const;

    bool
    present() const
    {
      return !pairs.empty();
    }

    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm, const ParameterScope &scope);
  };

  /// Follows the gaps of a run: call update() once per accepted step with the current
  /// positions of each pair's two points and the suture tension.
  class ClosureMonitor
  {
  public:
    explicit ClosureMonitor(const ClosureParameters &parameters);

    /// Gap of pair @p k for current positions @p xa, @p xb, m.
    double
    gap(std::size_t k, const Eigen::Vector3d &xa, const Eigen::Vector3d &xb) const;

    /// Records the gaps of the step at time @p t (one per pair) and @p tension (N).
    void
    update(double t, const std::vector<double> &gaps, double tension);

    /// An interrupted series' stitch k (tie_off_each_stitch), times in s: its pair's
    /// closure counts from closes_from (the pull's start: the thread drawn through it,
    /// not the needle crossing the wound, nor the stitches before), until its tie-off.
    /// It is tied off at the first step from ties_from on (the pull's end, or
    /// start_stitch()) at which the gap is below the tie-off gap (and closed), else at
    /// the step that reaches ties_by (its tightening's end). The whole series' motions
    /// stop (motion_time) when the last is tied off.
    struct StitchWindow
    {
      double closes_from = 0, ties_from = 0, ties_by = 0;
    };
    void
    set_stitches(std::vector<StitchWindow> windows);
    /// Stitch @p k is drawn tight from @p t on, before its pull's planned end (its tail
    /// taken where the pull stopped): it may be tied off from then.
    void
    start_stitch(std::size_t k, double t)
    {
      windows.at(k).ties_from = std::min(windows.at(k).ties_from, t);
    }
    /// When each stitch was tied off (s; ∞ before), an interrupted series' stops of its
    /// tightenings (tools::SurgicalSeries::pose).
    const std::vector<double> &
    stitch_ties() const
    {
      return stitch_tie;
    }

    /// Whether a step at @p t with gaps @p gaps (one per pair) would tie the stitch off:
    /// the first pair's gap, or with Tie off when = every pair the largest, below the
    /// tie-off gap (and the wound closed).
    bool
    ties_off(double t, const std::vector<double> &gaps) const
    {
      if (prm.tie_off_each_stitch)
        {
          for (std::size_t k = 0; k < stitch_tie.size(); ++k)
            if (stitch_ties_off(k, t, gaps))
              return true;
          return false;
        }
      const double gap = prm.tie_off_every_pair ? *std::max_element(gaps.begin(), gaps.end()) : gaps.front();
      return prm.tie_off && !tied() && t >= prm.start_time && gap < prm.tie_off_gap &&
             (closed() || gap < prm.closure_gap);
    }

    /// The time up to which prescribed motions run: ∞ until a tie-off, then its time.
    double
    motion_time(double t) const
    {
      return t < tie_time ? t : tie_time;
    }
    /// Whether the first pair, the run's closure, has closed.
    bool
    closed() const
    {
      return !closed_at.empty() && closed_at.front() < std::numeric_limits<double>::infinity();
    }
    bool
    tied() const
    {
      return tie_time < std::numeric_limits<double>::infinity();
    }

    /// metrics.initial_gap, final_gap (first pair), closure_tension, closure_time (at the
    /// interpolated crossing; null when never closed), tie_off_time, tie_off_tension (null when never tied off),
    /// gaps.<name>.{initial, final, least, closure_time, closure_tension}: every pair's own
    /// closure, when its gap first fell below the closure gap (one pair per stitch of a
    /// series gives each stitch's closure; the first pair's is the run's); in an
    /// interrupted series also each stitch's tie_off_time, tie_off_tension and tie_off_gap
    /// (the gap then, m; null before), and the run's tie-off is the last stitch's.
    void
    write(nlohmann::json &metrics) const;

    /// What update() has gathered, for a checkpoint (io/checkpoint.h); restore() takes it
    /// back.
    nlohmann::json
    snapshot() const;
    void
    restore(const nlohmann::json &snapshot);

  private:
    /// Whether the step at @p t with @p gaps ties stitch k off (an interrupted series).
    bool
    stitch_ties_off(std::size_t k, double t, const std::vector<double> &gaps) const
    {
      const bool closed_k = k < closed_at.size() && closed_at[k] < std::numeric_limits<double>::infinity();
      return !(stitch_tie[k] < std::numeric_limits<double>::infinity()) && t >= prm.start_time &&
             t >= windows[k].ties_from &&
             ((gaps[k] < prm.tie_off_gap && (closed_k || gaps[k] < prm.closure_gap)) || t >= windows[k].ties_by);
    }

    const ClosureParameters &prm;
    std::vector<StitchWindow> windows;
    /// per stitch: when it was tied off (∞ before), the tension and the gap then
    std::vector<double>      stitch_tie, stitch_tension, stitch_gap;
    std::vector<double>      initial, last, least;
    /// per pair: the interpolated crossing of the closure gap (∞ before) and the tension then
    std::vector<double>      closed_at, closed_tension;
    double                   tie_time    = std::numeric_limits<double>::infinity();
    double                   tie_tension = 0;
    /// the last step counted (t ≥ Start time): the crossing's bracket
    struct Sample
    {
      double              t = 0, tension = 0;
      std::vector<double> gaps;
    };
    std::optional<Sample> previous;
  };
} // namespace suturesim::scene
