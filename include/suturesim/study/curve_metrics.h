#pragma once
/**
 * @file
 * Error metrics of a candidate run against a reference run (issue 24): force curves,
 * event times and scalars. Plain C++; every formula is stated here and tested on
 * synthetic data with a known answer (tests/unit/study_metrics_test.cc).
 *
 * A curve is y(x) sampled at increasing abscissae (time, drawn length, gap, …) and read
 * between samples by linear interpolation. Over an interval [a, b] inside both curves'
 * ranges, with the candidate c and the reference r:
 *
 *   relative L2:   e₂ = ( ∫ₐᵇ (c − r)² dx / ∫ₐᵇ r² dx )^½
 *   relative L∞:   e∞ = max_[a,b] |c − r| / max_[a,b] |r|
 *   peak error:    e_p = (max_[a,b] |c| − max_[a,b] |r|) / max_[a,b] |r|   (signed)
 *
 * The integrals are exact for the piecewise-linear interpolants: both curves are split
 * at every sample of either, and on each piece (c − r)² is a quadratic integrated by
 * Simpson's rule (exact for it). Maxima are taken over the same breakpoints (a linear
 * piece has its extremes at its ends).
 *
 * Event alignment: a realtime run punctures, grasps and closes at other times than the
 * reference. Given the same ordered events in both runs (times e₀ < e₁ < … in the
 * candidate, E₀ < E₁ < … in the reference), the candidate is compared phase by phase
 * after the piecewise-linear warp that maps each of its phases onto the reference's,
 *   x ↦ E_k + (x − e_k)(E_{k+1} − E_k)/(e_{k+1} − e_k)   on [e_k, e_{k+1}],
 * so that curve errors measure the force within a phase, and the event-time errors
 * e_k − E_k (s) measure when the phases happen.
 */

#include <string>
#include <vector>

namespace suturesim::study
{
  /// y(x) sampled at strictly increasing x.
  struct Curve
  {
    std::vector<double> x, y;

    /// Linear interpolation (constant beyond the ends).
    double
    operator()(double at) const;
    double
    front() const
    {
      return x.front();
    }
    double
    back() const
    {
      return x.back();
    }
  };

  struct CurveErrors
  {
    double relative_l2   = 0; ///< e₂, 1
    double relative_linf = 0; ///< e∞, 1
    double peak          = 0; ///< e_p, 1 (signed: > 0 when the candidate's peak is higher)
  };

  /// e₂, e∞, e_p of @p candidate against @p reference over [a, b]. Throws
  /// std::invalid_argument when [a, b] is empty, outside either curve, or the reference
  /// vanishes on it (a relative error has no meaning there).
  CurveErrors
  curve_errors(const Curve &candidate, const Curve &reference, double a, double b);

  /// The candidate's abscissae mapped through the event warp above (events of both runs,
  /// same count ≥ 2, each strictly increasing). Samples before the first or after the
  /// last event are shifted by that event's offset.
  Curve
  warp_to_events(const Curve &candidate, const std::vector<double> &candidate_events,
                 const std::vector<double> &reference_events);

  /// Curve errors per phase [E_k, E_{k+1}] of the reference after the event warp.
  std::vector<CurveErrors>
  phase_errors(const Curve &candidate, const Curve &reference, const std::vector<double> &candidate_events,
               const std::vector<double> &reference_events);

  /// (v − v_ref)/|v_ref|, 1; throws std::invalid_argument when v_ref = 0.
  double
  relative_error(double value, double reference);
} // namespace suturesim::study
