#pragma once
/**
 * @file
 * What a study writes into its output folder once its cases have run (issue 24):
 *
 * - `cases.csv`: one row per case (the reference first): name, status, reason, the axis
 *   values (parameter paths as columns, with the parameter's unit), every error column
 *   of MetricsSpec::error_columns() and every cost column (study/case_metrics.h), units
 *   in the header; empty cells where a case has no value (a failed case's errors).
 * - `study.json`: the definition, the rows, the Pareto front of (cost, |error|), the
 *   cheapest adequate case, the account of a resolution-series reference (per metric:
 *   sizes, values, order, extrapolation, GCI, which value is used), the stability map
 *   and the convergence table, for the figures
 *   (postprocess/study_figures.py) and for scripts.
 * - `best.prm`: the cheapest case whose errors are within every tolerance, as a complete
 *   scene (its parameters.prm) headed by the evidence row and the settings that made it;
 *   with a reference per physical value (Reference/Per axis), one per reference,
 *   `best_<values>.prm`, since what suffices for a stiff suture need not for a soft one.
 * - `stability.csv`: per case of the stability map's two axes, the cell's state (stable,
 *   diverged, inaccurate = completed beyond a tolerance), dt and the predicted dt_crit;
 *   a study with more axes than the map's two has one map (panel) per combination of the
 *   others' values, named in the `panel` column.
 * - `map.csv`: per case of the map's two axes (Figures/Map axes), its panel, each map
 *   metric of the case and of its reference, and each flag.
 * - `convergence.csv`: the convergence metric against h, observed orders, Richardson
 *   extrapolation and Roache's grid-convergence index (study/convergence.h); h is each
 *   run's own representative cell size (V/N)^(1/3) (Celik et al. 2008), or the size the
 *   study gives the case (Figures/Convergence sizes).
 */

#include <suturesim/study/case_run.h>
#include <suturesim/study/study_definition.h>

#include <nlohmann/json.hpp>

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace suturesim::study
{
  /// One case's row.
  struct CaseRow
  {
    const Case         *definition = nullptr;
    CaseOutcome         outcome;
    std::vector<double> errors; ///< MetricsSpec::error_columns() order; NaN when absent
    std::vector<double> costs;  ///< cost_columns() order; NaN when absent
    double              dt = std::numeric_limits<double>::quiet_NaN(), dt_crit = dt; ///< realtime, s
    double              convergence_value = dt; ///< the convergence metric, if any
    double              mesh_size = dt; ///< summary.json mesh.representative_size, m
    std::vector<double> limit_values; ///< Objective/Limits' metrics of the case; NaN when absent
    std::vector<double> map_values;   ///< Figures/Map metrics of the case; NaN when absent
    std::vector<double> map_flags;    ///< Figures/Map flags of the case; NaN when absent
    /// The largest of |error|/tolerance and |value|/limit over the Objective's bounds:
    /// ≤ 1 within every one (NaN for a case not completed or a study without bounds).
    double              bound_ratio = std::numeric_limits<double>::quiet_NaN();
    bool                within_tolerance = false; ///< bound_ratio ≤ 1
  };

  class StudyReport
  {
  public:
    /// @p series: the account of a resolution-series reference (study/reference_series.h), else null.
    StudyReport(const StudyDefinition &study, std::vector<CaseRow> rows, nlohmann::json series = nullptr);

    /// Writes every output above into @p folder; throws InputError naming a file that
    /// cannot be written.
    void
    write(const std::string &folder, const nlohmann::json &timing) const;

    /// The study as study.json holds it.
    nlohmann::json
    to_json(const nlohmann::json &timing) const;

    /// Per reference (StudyDefinition::references), the index into rows of the cheapest
    /// case measured against it within every tolerance (cost: Objective/Cost).
    std::vector<std::optional<std::size_t>>
    best() const;

  private:
    const StudyDefinition &study;
    std::vector<CaseRow>   rows; ///< the references first
    nlohmann::json         series;
    std::size_t            error_index, cost_index; ///< Objective/Error's and Objective/Cost's columns

    /// What row @p k is measured against: its reference's name, or "series".
    std::string
    against(std::size_t k) const;

    double
    cost(const CaseRow &row) const;
    double
    error(const CaseRow &row) const;
    void
    write_cases_csv(const std::string &file) const;
    /// map.csv, from @p map (map()).
    void
    write_map_csv(const std::string &file, const nlohmann::json &map) const;
    /// Writes best.prm (per reference best_<values>.prm).
    void
    write_best(const std::string &folder) const;
    void
    write_best(const std::string &folder, const CaseRow &row, const std::string &name,
               const std::string &reference) const;
    nlohmann::json
    stability() const;
    /// The map of Figures/Map: per case, its metrics and flags and its reference's metrics.
    nlohmann::json
    map() const;
    /// The panel of a case on a map over axes @p x and @p y: the values of its other axes
    /// ("" when it has none).
    std::string
    panel_of(const Case &c, const std::string &x, const std::string &y) const;
    nlohmann::json
    convergence() const;
  };

  /// The unit of a scene parameter, from the "Unit: …" of its documentation ("" if none).
  std::string
  parameter_unit(const std::string &path);
} // namespace suturesim::study
