#pragma once
/**
 * @file
 * A case's metrics against the study's reference (issue 24), read from the two runs'
 * folders (summary.json, forces.csv). The error columns are those of
 * MetricsSpec::error_columns():
 *
 *   scalar s:        (s − s_ref)/|s_ref|                         (signed, 1)
 *   probe p:         |u_p − u_p,ref| / |u_p,ref|, u_p = p_displacement_{x,y,z}   (1)
 *   probes.max:      the largest probe error                     (1)
 *   curve c:         e₂, e∞, e_p of study/curve_metrics.h at equal time, or after the
 *                    event warp over [E₀, E_last] with e₂ per phase  (1)
 *   events.time:     max_k |e_k − E_k| over the alignment events (s)
 *   surface.l2, surface.max, surface.distance: study/surface_error.h (1, 1, m)
 *
 * and the cost columns: the realtime step-time median and 99th percentile (summary.json,
 * s), the run's wall time and processor time (run.json, s), its peak memory (bytes).
 */

#include <suturesim/io/surface_field.h>
#include <suturesim/study/case_run.h>
#include <suturesim/study/study_definition.h>

#include <nlohmann/json.hpp>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

namespace suturesim::study
{
  /// What a run folder holds for the metrics.
  struct RunData
  {
    nlohmann::json                             summary;
    std::map<std::string, std::vector<double>> columns; ///< forces.csv by name without unit
    std::optional<io::SurfaceField>            surface; ///< surface_displacement.json, if written

    /// Reads @p folder's summary.json and forces.csv (the latter may be absent).
    static RunData
    read(const std::string &folder);

    /// The number at "metrics.<dotted path>" of summary.json, if there is one.
    std::optional<double>
    metric(const std::string &path) const;
  };

  /// A metric the reference or a completed case does not produce; key is the study
  /// file's key that asks for it ("Metrics/Scalars", …). Missing in the reference, the
  /// study cannot measure it (an error at that key); missing in a case only, it is that
  /// case's result (a stitch that never closed has no closure tension): the case's row
  /// is "incomplete", with the other errors measured and this one empty.
  class MissingMetric : public std::runtime_error
  {
  public:
    MissingMetric(std::string key, const std::string &what, const bool in_reference)
      : std::runtime_error(what)
      , key(std::move(key))
      , in_reference(in_reference)
    {}
    std::string key;
    bool        in_reference;
  };

  /// The error columns of @p run against @p reference, in spec.error_columns() order;
  /// NaN for what the case lacks, with the reason in @p missing. Throws MissingMetric
  /// (in_reference) for what the reference lacks.
  std::vector<double>
  case_errors(const MetricsSpec &spec, const RunData &run, const RunData &reference,
              std::vector<std::string> &missing);

  /// The unit of an error column: s (events.time), m (surface.distance), else 1.
  std::string
  error_unit(const std::string &column);

  /// The cost columns, their names and units, in cases.csv order.
  const std::vector<std::pair<std::string, std::string>> &
  cost_columns();

  /// The cost columns of a run (NaN where the run does not measure one: the step times
  /// of an accurate run, the Newton iterations and failed attempts of a realtime one).
  /// The last two are the solver's effort: the most Newton iterations of one step and
  /// the steps whose first attempt failed and were cut back.
  std::vector<double>
  case_costs(const RunData &run, const CaseOutcome &outcome);
} // namespace suturesim::study
