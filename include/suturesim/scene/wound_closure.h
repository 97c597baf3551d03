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

    /// Whether a step at @p t with gaps @p gaps (one per pair) would tie the stitch off:
    /// the first pair's gap, or with Tie off when = every pair the largest, below the
    /// tie-off gap (and the wound closed).
    bool
    ties_off(double t, const std::vector<double> &gaps) const
    {
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
    /// series gives each stitch's closure; the first pair's is the run's).
    void
    write(nlohmann::json &metrics) const;

    /// What update() has gathered, for a checkpoint (io/checkpoint.h); restore() takes it
    /// back.
    nlohmann::json
    snapshot() const;
    void
    restore(const nlohmann::json &snapshot);

  private:
    const ClosureParameters &prm;
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
