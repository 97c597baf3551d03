#pragma once
/**
 * @file
 * A study's reference given as a resolution series (issue 24, `Reference/Series`): the
 * reference scene run at several mesh sizes. Each scalar and each probe component the
 * study measures is extrapolated to h → 0 from the three finest runs — Richardson with
 * the observed order, Celik et al., J. Fluids Eng. 130 (2008) 078001
 * (study/convergence.h) — when they converge monotonically (ε₃₂/ε₂₁ > 0, the order's
 * iteration settled, p > 0). Otherwise (oscillatory, stagnant, fewer than three sizes)
 * the finest run's value stands and the account says why. Curves and the surface field
 * are the finest run's. h is each run's representative cell size (V/N)^(1/3)
 * (summary.json mesh.representative_size).
 *
 * The fine-grid GCI of an extrapolated value is the reference's own uncertainty: a case
 * whose error is below it is not distinguished from the reference.
 */

#include <suturesim/study/case_metrics.h>

#include <nlohmann/json.hpp>

#include <string>
#include <utility>
#include <vector>

namespace suturesim::study
{
  struct SeriesReference
  {
    RunData        data;    ///< the finest run, with the extrapolated metrics in place
    nlohmann::json account; ///< per metric: h, values, order, extrapolated, gci_fine, used, why
  };

  /// The reference of the series @p runs named @p names (any order of size). A run's
  /// size h is its summary.json mesh.representative_size, or its entry in @p sizes (name:
  /// h, m; Figures/Convergence sizes) where given: a locally refined series halves its
  /// cells only where it refines, and its ratio there is 2 while the whole mesh's
  /// (V/N)^(1/3) changes by less. Throws MissingMetric (in_reference) for a metric a run
  /// lacks, std::invalid_argument naming the run for one without a mesh size.
  SeriesReference
  series_reference(const MetricsSpec &spec, const std::vector<RunData> &runs, const std::vector<std::string> &names,
                   const std::vector<std::pair<std::string, double>> &sizes = {});
} // namespace suturesim::study
