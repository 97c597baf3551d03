#pragma once
/**
 * @file
 * The speed–accuracy trade-off of a study's cases (issue 24): the non-dominated (Pareto)
 * front of (cost, error), both minimised, and the cheapest case within a tolerance.
 *
 * Case i dominates case j when cost_i ≤ cost_j and error_i ≤ error_j with at least one
 * strict; the front is the set of completed cases no completed case dominates, in
 * increasing cost (Deb, Multi-objective optimization using evolutionary algorithms,
 * 2001, §2.4). Failed cases (diverged, refused, no result) are never on the front and
 * never chosen, but stay in the study's tables and charts as failed.
 */

#include <cstddef>
#include <optional>
#include <vector>

namespace suturesim::study
{
  struct TradeOff
  {
    double cost      = 0;    ///< e.g. step-time median, s; or wall time, s
    double error     = 0;    ///< e.g. a relative error, 1
    bool   completed = true; ///< false: failed, diverged or without the metric
  };

  /// Indices of the non-dominated completed cases, by increasing cost (ties in cost: the
  /// smaller error only; equal pairs: each is kept).
  std::vector<std::size_t>
  pareto_front(const std::vector<TradeOff> &cases);

  /// The completed case of least cost whose error is ≤ @p tolerance (ties in cost: the
  /// smaller error), or none.
  std::optional<std::size_t>
  cheapest_within(const std::vector<TradeOff> &cases, double tolerance);
} // namespace suturesim::study
