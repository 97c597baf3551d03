#pragma once
/**
 * @file
 * A study file (issue 24): a deal.II .prm, checked like a scene (file:line errors), that
 * names a base scene, the settings every run shares (`Settings`, before each run's own),
 * the settings of a reference case, the settings every case shares,
 * the cases — the product of axes over any scene parameter by its path, and/or a list —
 * the metrics, the objective and the figures. Each case is the base scene with its
 * settings applied as `--set` would apply them, so it is an ordinary suturesim run,
 * reproducible by itself.
 *
 *   set Name       = patch_load_pareto
 *   set Base scene = ../../benchmarks/block_patch_load/block_patch_load.prm
 *   subsection Reference
 *     set Settings = Model=accurate
 *   end
 *   subsection Cases
 *     set Settings = Model=realtime, "Mesh/Geo parameters=h: 0.004, hexahedra: 0"
 *     set Axes     = Realtime/Integrator = xpbd | quasi-static; Realtime/xpbd/Iterations = 1 | 4
 *     set List     = few: Realtime/xpbd/Iterations=2, Time/Step size=0.002
 *   end
 *   subsection Metrics
 *     set Probes = top_centre, mid_depth_centre
 *   end
 *   subsection Objective
 *     set Error = probes.max
 *     set Cost  = step_time_median
 *     set Tolerances = probes.max: 0.2
 *   end
 *
 * A physical axis (a material's modulus, a load) changes the answer, not only the
 * approximation: `Reference/Per axis` names such axes, and the study then has one
 * reference per combination of their values, each case measured against the reference
 * with its own values (named "reference_<values>"; otherwise the one "reference").
 * `Reference/Series` instead runs the reference at several resolutions and measures
 * every case against their extrapolation (study/reference_series.h).
 *
 * Settings are "Path/Key=value" separated by ",", axes "Path/Key = v1 | v2 | …"
 * separated by ";", listed cases "name: settings" separated by ";"; a part in double
 * quotes keeps its separators (the quotes are dropped). Axis cases are named by their
 * values (characters other than letters, digits, '.', '-' become '_'), joined by "_".
 */

#include <map>
#include <string>
#include <utility>
#include <vector>

namespace suturesim::study
{
  struct Case
  {
    std::string              name;
    std::vector<std::string> settings; ///< "Path/Key=value", applied in order
    /// The axis values that made it, by axis path ({} for listed cases).
    std::vector<std::pair<std::string, std::string>> axis_values;
    std::size_t reference = 0; ///< index of its reference in StudyDefinition::references
    unsigned    processes = 1; ///< MPI processes of its run (the references' Reference/Processes)
  };

  /// What is measured of every case against the reference (study/case_metrics.h).
  struct MetricsSpec
  {
    std::vector<std::string> scalars; ///< keys of summary.json "metrics" (dotted for nested)
    std::vector<std::string> probes;  ///< probe names: <p>_displacement_{x,y,z}
    std::vector<std::string> curves;  ///< forces.csv columns, by name without unit
    bool                     surface = false; ///< the surface displacement error (study/surface_error.h)
    std::string              alignment = "time"; ///< "time" or "events"
    std::vector<std::string> events;  ///< event kinds that bound the phases (alignment = events)

    /// The error columns these metrics give every case, in cases.csv order: each
    /// scalar by its name; "probe.<p>" and "probes.max"; "<curve>.l2", ".linf", ".peak"
    /// and, aligned on events, "<curve>.phase<k>.l2" (k = 1 …) and "events.time";
    /// "surface.l2", "surface.max", "surface.distance".
    std::vector<std::string>
    error_columns() const;
  };

  /// What "good enough" and "cheap" mean for the Pareto chart and best.prm.
  struct ObjectiveSpec
  {
    std::string                                  error; ///< a metric column, e.g. "probes.max"
    std::string                                  cost = "step_time_median";
    std::vector<std::pair<std::string, double>> tolerances; ///< metric column: bound on |error|
    /// summary.json metric of the case itself: bound on |value| (a suture's stretch)
    std::vector<std::pair<std::string, double>> limits;
  };

  struct FiguresSpec
  {
    std::string stability_x, stability_y; ///< axis paths of the stability map (empty: none)
    std::string convergence_metric;       ///< a summary metric for the convergence table (empty: none)
    std::vector<std::pair<std::string, double>> convergence_sizes; ///< case name: h (m)
    std::string convergence_series; ///< a parameter path whose value in a case names its series (e.g. Model)
    /// The map (a heat map per metric over two axes, e.g. tear onset over bite × spacing):
    std::string              map_x, map_y;  ///< axis paths (empty: none)
    /// summary.json metrics drawn on the map: the case's, and the one its reference is
    /// read for (the same unless the entry says "case metric: reference metric", as when
    /// the two paths name their tear onsets differently)
    std::vector<std::pair<std::string, std::string>> map_metrics;
    std::vector<std::string> map_flags;     ///< summary.json metrics that mark a cell when > 0
  };

  /// A scene parameter that a calibration fits (Calibration/Parameters), within bounds.
  struct CalibrationParameter
  {
    std::string path;                   ///< "Path/Key", as a setting names it
    double      initial = 0, lower = 0, upper = 0;
  };

  /// A calibration (issue 28; `suturesim calibrate`, docs/calibration.md): the
  /// parameters that minimise Σ_m w_m e_m² over the study's error columns e_m of one
  /// case against the reference, found by SciPy's bounded least squares
  /// (postprocess/calibrate.py), then run at the fitted values on the validation cases.
  struct CalibrationSpec
  {
    std::vector<CalibrationParameter>           parameters; ///< empty: not a calibration
    std::vector<std::pair<std::string, double>> weights;    ///< error column: w (> 0)
    /// held-out cases, run at the fitted values, their settings over Cases/Settings
    std::vector<Case> validation;
    unsigned          max_evaluations = 60;   ///< runs of the objective (not the Jacobian's)
    double            difference_step = 1e-3; ///< forward-difference step, of ln p (or of p / |bounds|)
  };

  struct StudyDefinition
  {
    std::string       name;
    std::string       file;       ///< the study file, for messages
    std::string       base_scene; ///< resolved against the study file's folder
    /// "reference", or one per value combination of Reference/Per axis, or the runs of
    /// a resolution series (Reference/Series, "reference_<name>")
    std::vector<Case> references;
    bool              reference_series = false; ///< the references are one series, every case against all of them
    /// Reference/Per axis names axes: each case has the reference of its own values
    /// there (even when --only leaves one)
    bool references_per_axis = false;
    /// Reference/On failure = report (only with Per axis): a reference run that failed
    /// (exit 3: its solver could not go on) does not stop the study; its cases are not
    /// compared with it (status "no reference") and the map marks its cells. Default:
    /// the study stops at its report, naming the run.
    bool report_failed_references = false;
    std::vector<Case> cases;      ///< the product of the axes, then the listed ones
    MetricsSpec       metrics;
    ObjectiveSpec     objective;
    FiguresSpec       figures;
    CalibrationSpec   calibration;

    /// Reads and checks @p study_file: every case's settings are applied to the base
    /// scene as the run would apply them, so an unknown path or a bad value is found
    /// now; errors are InputErrors "study_file:line: key: problem". @p extra settings
    /// (the command line's --set) go after every case's own, the reference's too: the
    /// same study at another size, e.g. a shorter end time.
    /// With @p case_list ("name: settings; …", as Cases/List), those cases replace the
    /// study's axes and list (a calibration's runs at the parameter values it tries).
    static StudyDefinition
    read(const std::string &study_file, const std::vector<std::string> &extra = {},
         const std::string *case_list = nullptr);

    /// An InputError "study_file:line: key: problem" for what is found after the runs
    /// (a metric no case produces, a failed reference); @p key as "Metrics/Scalars".
    [[noreturn]] void
    fail(const std::string &key, const std::string &problem) const;

    /// The cost metric names Objective/Cost accepts, with their units.
    static const std::map<std::string, std::string> &
    cost_units();

  private:
    std::map<std::string, int> lines; ///< key path -> line in the study file
  };
} // namespace suturesim::study
