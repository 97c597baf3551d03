#include <suturesim/core/error.h>
#include <suturesim/core/model_parameters.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/scene/simulation.h>
#include <suturesim/study/study_definition.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/utilities.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>
#include <optional>
#include <set>

namespace suturesim::study
{
  using dealii::ParameterHandler;
  using dealii::Patterns::Anything;

  namespace
  {
    using dealii::Utilities::trim;

    /// The non-empty trimmed parts of @p text between @p separator; a separator inside
    /// double quotes does not split (the quotes stay, for unquote()).
    std::vector<std::string>
    split(const std::string &text, const char separator)
    {
      std::vector<std::string> parts;
      std::string              part;
      bool                     quoted = false;
      for (const char c : text + separator)
        if (c == '"')
          quoted = !quoted, part += c;
        else if (c == separator && !quoted)
          {
            if (!trim(part).empty())
              parts.push_back(trim(part));
            part.clear();
          }
        else
          part += c;
      return parts;
    }

    std::string
    unquote(const std::string &s)
    {
      std::string out;
      for (const char c : s)
        if (c != '"')
          out += c;
      return trim(out);
    }

    /// The items of @p text separated by @p separator, unquoted: names, or
    /// "Path/Key=value" settings.
    std::vector<std::string>
    names(const std::string &text, const char separator = ',')
    {
      std::vector<std::string> out;
      for (const auto &s : split(text, separator))
        out.push_back(unquote(s));
      return out;
    }

    /// "name: number" pairs separated by ","; errors at @p key of @p scope.
    std::vector<std::pair<std::string, double>>
    named_numbers(const std::string &text, const ParameterScope &scope, const std::string &key)
    {
      std::vector<std::pair<std::string, double>> out;
      for (const auto &item : split(text, ','))
        {
          const auto colon = item.rfind(':');
          scope.require(colon != std::string::npos && colon > 0, key, "'" + item + "' is not 'name: number'");
          const std::string number = trim(item.substr(colon + 1));
          char             *end    = nullptr;
          const double      value  = std::strtod(number.c_str(), &end);
          scope.require(!number.empty() && *end == '\0' && std::isfinite(value), key,
                        "'" + number + "' in '" + item + "' is not a number");
          out.emplace_back(trim(item.substr(0, colon)), value);
        }
      return out;
    }

    /// A bound on a study's size: each case is a run and a folder.
    constexpr std::size_t max_cases = 10000;

    std::string
    file_name_part(const std::string &value)
    {
      // other characters become '_', runs of them one '_' ("h: 0.004, hexahedra: 0" -> h_0.004_hexahedra_0)
      std::string name;
      for (const char c : value)
        {
          const bool keep = std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-';
          if (keep)
            name += c;
          else if (!name.empty() && name.back() != '_')
            name += '_';
        }
      if (!name.empty() && name.back() == '_')
        name.pop_back();
      return name;
    }

    void
    declare(ParameterHandler &prm)
    {
      prm.declare_entry("Name", "", Anything(), "The study's name (its output folder by default). Unit: none.");
      prm.declare_entry("Base scene", "", Anything(),
                        "The scene every case starts from; relative to the study file's folder. Unit: none.");
      prm.declare_entry("Settings", "", Anything(),
                        "Settings every run of the study shares, the references' and the cases', applied "
                        "over the base scene before their own: \"Path/Key=value\", separated by commas (a "
                        "part in double quotes keeps its commas). Unit: none.");
      prm.enter_subsection("Reference");
      prm.declare_entry("Settings", "", Anything(),
                        "Settings of the reference case over the base scene: \"Path/Key=value\", "
                        "separated by commas (a part in double quotes keeps its commas). Unit: none.");
      prm.declare_entry("Per axis", "", Anything(),
                        "Parameter paths, separated by semicolons, whose value changes the physics (a "
                        "modulus, a load) rather than the approximation: one reference per combination "
                        "of the values the cases give them, each case measured against its own. Every "
                        "case must set them (an axis of Cases/Axes, or its listed settings). Empty: one "
                        "reference. Unit: none.");
      prm.declare_entry("Series", "", Anything(),
                        "A resolution series in place of one reference: \"name: settings; ...\" (each "
                        "over 'Settings'), three or more; each scalar and probe is extrapolated to h -> 0 "
                        "where the series converges monotonically, else the finest run's value is used "
                        "(study/reference_series.h). Not with 'Per axis'. Unit: none.");
      prm.declare_entry("On failure", "stop", dealii::Patterns::Selection("stop|report"),
                        "What a reference run that fails (exit 3: its solver could not go on) does: "
                        "stop the study at its report, naming the run; or, with 'Per axis' only, "
                        "report it: the study goes on, the cases of that reference are not compared "
                        "with it (status 'no reference', its reason in theirs) and its map cells show "
                        "the reference's status beside the values it reached before it stopped. A "
                        "reference refused or crashed stops the study either way. Unit: none.");
      prm.declare_entry("Processes", "1", dealii::Patterns::Integer(1, 1024),
                        "MPI processes of each reference run (mpirun -np; the accurate path "
                        "distributes its tissue solve). A run of k processes takes k of the "
                        "study's --jobs. Unit: 1. Range: 1-1024.");
      prm.leave_subsection();
      prm.enter_subsection("Cases");
      prm.declare_entry("Settings", "", Anything(),
                        "Settings every case shares, as for the reference. Unit: none.");
      prm.declare_entry("Axes", "", Anything(),
                        "Axes whose product gives the cases: \"Path/Key = v1 | v2 | ...\", separated by "
                        "semicolons. Unit: none.");
      prm.declare_entry("List", "", Anything(),
                        "Further cases: \"name: Path/Key=value, ...\", separated by semicolons. Unit: none.");
      prm.leave_subsection();
    }

    void
    declare_metrics(ParameterHandler &prm)
    {
      prm.enter_subsection("Metrics");
      prm.declare_entry("Scalars", "", Anything(),
                        "summary.json metrics compared by relative error (v - v_ref)/|v_ref|, separated by "
                        "commas; nested ones with dots (gaps.mid.final). Unit: none.");
      prm.declare_entry("Probes", "", Anything(),
                        "Tissue probes compared by |u - u_ref|/|u_ref| of their displacement "
                        "(<probe>_displacement_x,y,z); also their maximum, probes.max. Unit: none.");
      prm.declare_entry("Curves", "", Anything(),
                        "forces.csv columns (name without unit) compared by relative L2 and L-infinity "
                        "error and peak error (study/curve_metrics.h). Unit: none.");
      prm.declare_entry("Surface", "false", dealii::Patterns::Bool(),
                        "Compare the tissue's surface displacement at the end of the run "
                        "(surface_displacement.json of both runs): relative L2 and max error at the "
                        "case's surface vertices, and the largest distance between the two surfaces "
                        "(study/surface_error.h). Unit: none.");
      prm.declare_entry("Curve alignment", "time", dealii::Patterns::Selection("time|events"),
                        "Compare curves at equal time, or phase by phase between the events listed in "
                        "'Alignment events' (each phase mapped onto the reference's). Unit: none.");
      prm.declare_entry("Alignment events", "", Anything(),
                        "Event kinds of summary.json bounding the phases, in the order they happen "
                        "(e.g. puncture_entry, puncture_exit, onto_suture); each matches the next event "
                        "of its kind. Unit: none.");
      prm.leave_subsection();
    }

    void
    declare_objective_and_figures(ParameterHandler &prm)
    {
      prm.enter_subsection("Objective");
      prm.declare_entry("Error", "", Anything(),
                        "The error metric of the Pareto chart (a cases.csv error column, e.g. "
                        "closure_tension or probes.max); its magnitude is used. Unit: none.");
      prm.declare_entry("Cost", "step_time_median",
                        dealii::Patterns::Selection("step_time_median|step_time_p99|wall_time|core_seconds"),
                        "The cost of the Pareto chart and of 'cheapest within tolerance': realtime step "
                        "time median or 99th percentile (s), wall time (s) or processor time (s) of "
                        "the run. Unit: none.");
      prm.declare_entry("Tolerances", "", Anything(),
                        "Bounds on |error|: \"metric: bound\" separated by commas (e.g. probes.max: 0.2); "
                        "a case within all of them is adequate (best.prm, the stability map's "
                        "'inaccurate'). Unit: 1 (relative errors).");
      prm.declare_entry("Limits", "", Anything(),
                        "Bounds on a case's own summary.json metrics, not on errors: \"metric: bound\" "
                        "separated by commas (e.g. suture_stretch_max: 0.01); a case beyond one is not "
                        "adequate (best.prm) and is 'inaccurate' on the stability map. Unit: the metric's.");
      prm.leave_subsection();
      prm.enter_subsection("Figures");
      prm.declare_entry("Stability axes", "", Anything(),
                        "Two axis paths of Cases/Axes, \"x; y\", for the stability map (stable, diverged, "
                        "inaccurate, with dt_crit); empty for none. Unit: none.");
      prm.declare_entry("Map axes", "", Anything(),
                        "Two axis paths of Cases/Axes, \"x; y\", for a heat map of each Map metric "
                        "(a vector value is placed at its length); empty for none. Unit: none.");
      prm.declare_entry("Map metrics", "", Anything(),
                        "summary.json metrics of each case drawn on the map, comma separated (the case's "
                        "own values, and its reference's when the reference is per axis), e.g. "
                        "realtime_tearing.onset_tension; \"case metric: reference metric\" reads the "
                        "reference for another (the accurate path's onset of a criterion). A case "
                        "without one is drawn as 'none'. Unit: none.");
      prm.declare_entry("Map flags", "", Anything(),
                        "summary.json metrics, comma separated, that mark a map cell when > 0 (e.g. "
                        "stitch_evaluation.too_close_to_edge: seed 003's limits, as each run found them). "
                        "Unit: none.");
      prm.declare_entry("Convergence metric", "", Anything(),
                        "A summary.json metric tabulated against the mesh size h of the cases "
                        "(observed order, Richardson extrapolation, GCI): each run's representative "
                        "size (V/N)^(1/3) of its tissue mesh (summary.json mesh.representative_size; "
                        "Celik et al. 2008), unless 'Convergence sizes' gives them. Unit: none.");
      prm.declare_entry("Convergence sizes", "", Anything(),
                        "\"case: h\" separated by commas, h the cases' mesh size, in place of the "
                        "measured sizes: only these cases are tabulated. The runs of a Reference/Series "
                        "(named reference_<name>) take their sizes from here too, e.g. the refined "
                        "cells' size of a locally refined series. Unit: m.");
      prm.declare_entry("Convergence series", "", Anything(),
                        "A parameter path (e.g. Model) whose value in each case's settings names its "
                        "series: one table, order and extrapolation per series (per model path). "
                        "Empty: one series. Unit: none.");
      prm.leave_subsection();
      prm.enter_subsection("Calibration");
      prm.declare_entry("Parameters", "", Anything(),
                        "Scene parameters to fit (suturesim calibrate, docs/calibration.md): "
                        "\"Path/Key: initial, lower, upper\" separated by semicolons; fitted in ln p "
                        "when lower > 0, else in p. Empty: the study is not a calibration. Unit: the "
                        "parameter's.");
      prm.declare_entry("Weights", "", Anything(),
                        "\"column: weight\" separated by commas: the objective is the sum of w e^2 over "
                        "these error columns e of cases.csv. Empty: weight 1 on every probe.<p>, scalar, "
                        "<curve>.l2 and surface.l2. Unit: 1.");
      prm.declare_entry("Validation", "", Anything(),
                        "Held-out cases run at the fitted values and measured against the same "
                        "reference: \"name: settings; ...\" over Cases/Settings (another mesh size, "
                        "another integrator). Unit: none.");
      prm.declare_entry("Max evaluations", "60", dealii::Patterns::Integer(2, 1000),
                        "Runs of the objective the optimiser may make (the Jacobian's runs not "
                        "counted). Unit: 1. Range: 2-1000.");
      prm.declare_entry("Difference step", "1e-3", dealii::Patterns::Double(1e-8, 0.5),
                        "Forward-difference step of the Jacobian: of ln p, or of p relative to "
                        "upper - lower for a parameter fitted in p. Unit: 1. Range: [1e-8, 0.5].");
      prm.leave_subsection();
    }

    /// What every case starts from: the study's shared Settings, then Cases/Settings.
    /// Called at the file's top level.
    std::vector<std::string>
    case_settings(ParameterHandler &prm)
    {
      auto common = names(prm.get("Settings"));
      prm.enter_subsection("Cases");
      const auto own = names(prm.get("Settings"));
      prm.leave_subsection();
      common.insert(common.end(), own.begin(), own.end());
      return common;
    }

    /// The product of @p axes (each "Path/Key = v1 | v2"), after @p common.
    std::vector<Case>
    product(const std::vector<std::string> &axes, const std::vector<std::string> &common,
            const ParameterScope &scope)
    {
      std::vector<Case> cases{{"", common, {}}};
      for (const auto &axis : axes)
        {
          const auto equals = axis.find('=');
          scope.require(equals != std::string::npos, "Axes", "'" + axis + "' is not 'Path/Key = v1 | v2'");
          const std::string path   = unquote(axis.substr(0, equals));
          const auto        values = split(axis.substr(equals + 1), '|');
          scope.require(!path.empty() && !values.empty(), "Axes", "the axis '" + axis + "' has no values");
          scope.require(cases.size() * values.size() <= max_cases, "Axes",
                        "the axes give more than " + std::to_string(max_cases) +
                          " cases (split the study, or use fewer values)");
          std::vector<Case> next;
          for (const auto &c : cases)
            for (const auto &quoted : values)
              {
                const std::string v = unquote(quoted);
                Case              n = c;
                n.name += (n.name.empty() ? "" : "_") + file_name_part(v);
                n.settings.push_back(path + "=" + v);
                n.axis_values.emplace_back(path, v);
                next.push_back(n);
              }
          cases = next;
        }
      return axes.empty() ? std::vector<Case>{} : cases;
    }

    std::vector<Case>
    listed(const std::string &text, const std::vector<std::string> &common, const ParameterScope &scope,
           const std::string &key = "List")
    {
      std::vector<Case> cases;
      for (const auto &item : split(text, ';'))
        {
          const auto colon = item.find(':');
          scope.require(colon != std::string::npos && colon > 0, key, "'" + item + "' is not 'name: settings'");
          Case c{file_name_part(unquote(item.substr(0, colon))), common, {}};
          for (const auto &s : names(item.substr(colon + 1)))
            c.settings.push_back(s);
          cases.push_back(c);
        }
      return cases;
    }

    /// Applies @p c to the base scene as the run will, and checks the scene as
    /// `suturesim --validate` does (the parameters together, and a scenario that runs
    /// them): a bad setting is an error at the study file's @p key before any run, not
    /// a refused run after the others have spent their time.
    void
    check(const Case &c, const std::string &scene, const ParameterScope &scope, const std::string &key)
    {
      ParameterHandler prm;
      scene::Simulation::declare_parameters(prm);
      try
        {
          const ParameterFile file = ParameterFile::from_file(prm, scene, c.settings);
          const scene::Simulation checked(prm, file);
        }
      catch (const InputError &e)
        {
          scope.fail(key, "case '" + c.name + "': " + e.what());
        }
    }

    /// The value @p c gives the parameter @p path (its last "path=value" setting), if any.
    std::optional<std::string>
    setting_of(const Case &c, const std::string &path)
    {
      std::optional<std::string> value;
      for (const auto &s : c.settings)
        if (s.size() > path.size() && s.compare(0, path.size() + 1, path + "=") == 0)
          value = s.substr(path.size() + 1);
      return value;
    }

    /// The study's references, after @p settings: one, or one per combination of the
    /// values the cases give the @p per_axis paths (in order of first appearance), each
    /// case pointed at its own.
    void
    match_references(StudyDefinition &d, const std::vector<std::string> &per_axis,
                     const std::vector<std::string> &settings, const ParameterScope &scope)
    {
      d.references.clear();
      if (per_axis.empty())
        d.references.push_back({"reference", settings, {}, 0});
      std::map<std::vector<std::string>, std::size_t> index;
      for (auto &c : d.cases)
        {
          if (per_axis.empty())
            break;
          std::vector<std::string> values;
          for (const auto &path : per_axis)
            {
              const auto v = setting_of(c, path);
              scope.require(v.has_value(), "Per axis",
                            "case '" + c.name + "' does not set '" + path + "', so it has no reference");
              values.push_back(*v);
            }
          const auto [entry, added] = index.emplace(values, d.references.size());
          if (added)
            {
              Case r{"reference", settings, {}, d.references.size()};
              for (std::size_t k = 0; k < values.size(); ++k)
                {
                  r.name += "_" + file_name_part(values[k]);
                  r.settings.push_back(per_axis[k] + "=" + values[k]);
                  r.axis_values.emplace_back(per_axis[k], values[k]);
                }
              d.references.push_back(r);
            }
          c.reference = entry->second;
        }
    }

    /// The references of a resolution series (Reference/Series), every case measured
    /// against the series as a whole (study/reference_series.h).
    void
    series_references(StudyDefinition &d, const std::string &text, const std::vector<std::string> &per_axis,
                      const std::vector<std::string> &settings, const ParameterScope &scope)
    {
      scope.require(per_axis.empty(), "Series", "a resolution series cannot be combined with 'Per axis'");
      d.references = listed(text, settings, scope, "Series");
      scope.require(d.references.size() >= 3, "Series", "a resolution series needs three runs or more");
      for (std::size_t k = 0; k < d.references.size(); ++k)
        {
          d.references[k].name      = "reference_" + d.references[k].name;
          d.references[k].reference = k;
        }
      d.reference_series = true;
      for (auto &c : d.cases)
        c.reference = d.references.size() - 1;
    }

    /// The references and the cases, each checked against the base scene with @p extra
    /// (--set) after its own settings; the axis paths of Cases/Axes.
    std::vector<std::string>
    read_cases(ParameterHandler &prm, StudyDefinition &d, const ParameterScope &top,
               const std::vector<std::string> &extra, const std::string *case_list)
    {
      const auto shared = names(prm.get("Settings"));
      {
        Case all{"shared", shared, {}, 0};
        check(all, d.base_scene, top, "Settings");
      }
      prm.enter_subsection("Reference");
      auto reference_settings = shared;
      for (const auto &setting : names(prm.get("Settings")))
        reference_settings.push_back(setting);
      const auto per_axis           = names(prm.get("Per axis"), ';');
      const auto series             = prm.get("Series");
      d.references_per_axis         = !per_axis.empty();
      d.report_failed_references    = prm.get("On failure") == "report";
      top.subsection("Reference").require(!d.report_failed_references || d.references_per_axis, "On failure",
                                          "'report' needs 'Per axis': without a reference per cell, a "
                                          "failed one leaves no case anything to be compared with");
      const auto processes          = static_cast<unsigned>(prm.get_integer("Processes"));
      prm.leave_subsection();
      {
        Case reference{"reference", reference_settings, {}, 0};
        reference.settings.insert(reference.settings.end(), extra.begin(), extra.end());
        check(reference, d.base_scene, top.subsection("Reference"), "Settings");
      }

      const auto common = case_settings(prm);
      prm.enter_subsection("Cases");
      const ParameterScope cases      = top.subsection("Cases");
      const auto           axis_texts = case_list ? std::vector<std::string>{} : split(prm.get("Axes"), ';');
      d.cases                         = product(axis_texts, common, cases);
      const std::size_t from_axes     = d.cases.size();
      for (auto &c : listed(case_list ? *case_list : prm.get("List"), common, cases))
        d.cases.push_back(c);
      prm.leave_subsection();
      if (d.cases.empty() && !d.calibration.parameters.empty())
        {
          // a calibration's one case, its starting point
          Case start{"initial", common, {}};
          for (const auto &p : d.calibration.parameters)
            start.settings.push_back(p.path + "=" + shortest_text(p.initial));
          d.cases.push_back(start);
        }
      cases.require(!d.cases.empty(), "Axes", "the study has no cases (no axes and no list)");
      if (series.empty())
        match_references(d, per_axis, reference_settings, top.subsection("Reference"));
      else
        series_references(d, series, per_axis, reference_settings, top.subsection("Reference"));

      std::set<std::string> used;
      for (auto &r : d.references)
        {
          r.processes = processes;
          r.settings.insert(r.settings.end(), extra.begin(), extra.end());
          used.insert(r.name);
          if (d.references.size() > 1) // with its value of each physical axis, or its resolution
            check(r, d.base_scene, top.subsection("Reference"), d.reference_series ? "Series" : "Settings");
        }
      for (std::size_t k = 0; k < d.cases.size(); ++k)
        {
          d.cases[k].settings.insert(d.cases[k].settings.end(), extra.begin(), extra.end());
          const std::string key = k < from_axes ? "Axes" : "List";
          cases.require(!d.cases[k].name.empty(), key, "a case's name has no letter or digit");
          cases.require(used.insert(d.cases[k].name).second, key,
                        "two cases are named '" + d.cases[k].name + "'");
          check(d.cases[k], d.base_scene, cases, key);
        }
      std::vector<std::string> axes;
      for (const auto &a : axis_texts)
        axes.push_back(unquote(a.substr(0, a.find('='))));
      return axes;
    }

    void
    read_metrics_and_objective(ParameterHandler &prm, StudyDefinition &d, const ParameterScope &top)
    {
      prm.enter_subsection("Metrics");
      d.metrics.scalars   = names(prm.get("Scalars"));
      d.metrics.probes    = names(prm.get("Probes"));
      d.metrics.curves    = names(prm.get("Curves"));
      d.metrics.surface   = prm.get_bool("Surface");
      d.metrics.alignment = prm.get("Curve alignment");
      d.metrics.events    = names(prm.get("Alignment events"));
      prm.leave_subsection();
      const auto metrics = top.subsection("Metrics");
      metrics.require(d.metrics.alignment == "time" || d.metrics.events.size() >= 2, "Alignment events",
                      "event alignment needs at least two events (the ends of one phase)");

      prm.enter_subsection("Objective");
      const auto objective = top.subsection("Objective");
      d.objective.error    = unquote(prm.get("Error"));
      d.objective.cost     = prm.get("Cost");
      d.objective.tolerances = named_numbers(prm.get("Tolerances"), objective, "Tolerances");
      d.objective.limits     = named_numbers(prm.get("Limits"), objective, "Limits");
      prm.leave_subsection();
      const auto columns = d.metrics.error_columns();
      const auto known   = [&](const std::string &c) {
        return std::find(columns.begin(), columns.end(), c) != columns.end();
      };
      const std::string choices = columns.empty() ? "none: Metrics names no metric" : "one of the Metrics' "
                                                                                      "columns";
      objective.require(d.objective.error.empty() || known(d.objective.error), "Error",
                        "'" + d.objective.error + "' is not " + choices);
      for (const auto &[name, bound] : d.objective.tolerances)
        {
          objective.require(known(name), "Tolerances", "'" + name + "' is not " + choices);
          objective.require(bound > 0, "Tolerances", "the bound of '" + name + "' must be > 0");
        }
      for (const auto &[name, bound] : d.objective.limits)
        objective.require(bound > 0, "Limits", "the bound of '" + name + "' must be > 0");
    }

    void
    read_figures(ParameterHandler &prm, StudyDefinition &d, const std::vector<std::string> &axes,
                 const ParameterScope &top)
    {
      prm.enter_subsection("Figures");
      const auto figures   = top.subsection("Figures");
      // "x; y": two axes of Cases/Axes, or none
      const auto two_axes = [&](const char *key, std::string &x, std::string &y) {
        const auto pair = split(prm.get(key), ';');
        figures.require(pair.empty() || pair.size() == 2, key, "needs two axes, 'x; y'");
        for (const auto &a : pair)
          figures.require(std::find(axes.begin(), axes.end(), unquote(a)) != axes.end(), key,
                          "'" + unquote(a) + "' is not an axis of Cases/Axes");
        if (pair.size() == 2)
          x = unquote(pair[0]), y = unquote(pair[1]);
      };
      two_axes("Stability axes", d.figures.stability_x, d.figures.stability_y);
      two_axes("Map axes", d.figures.map_x, d.figures.map_y);
      for (const auto &entry : names(prm.get("Map metrics")))
        {
          const auto colon = entry.find(':');
          const auto own   = unquote(entry.substr(0, colon));
          const auto other = colon == std::string::npos ? own : unquote(entry.substr(colon + 1));
          figures.require(!own.empty() && !other.empty(), "Map metrics", "'" + entry + "' names no metric");
          d.figures.map_metrics.emplace_back(own, other);
        }
      d.figures.map_flags   = names(prm.get("Map flags"));
      figures.require(d.figures.map_x.empty() == d.figures.map_metrics.empty(),
                      d.figures.map_x.empty() ? "Map axes" : "Map metrics",
                      "a map needs both its two axes and at least one metric");
      figures.require(!d.figures.map_x.empty() || d.figures.map_flags.empty(), "Map flags",
                      "flags need a map (Map axes)");
      d.figures.convergence_metric = unquote(prm.get("Convergence metric"));
      d.figures.convergence_sizes  = named_numbers(prm.get("Convergence sizes"), figures, "Convergence sizes");
      d.figures.convergence_series = unquote(prm.get("Convergence series"));
      prm.leave_subsection();
      figures.require(d.figures.convergence_metric.empty() || d.figures.convergence_sizes.empty() ||
                        d.figures.convergence_sizes.size() >= 3,
                      "Convergence sizes", "a convergence table needs three sizes or more (per series)");
      for (const auto &[name, h] : d.figures.convergence_sizes)
        {
          const auto named = [&](const Case &c) { return c.name == name; };
          figures.require(std::any_of(d.references.begin(), d.references.end(), named) ||
                            std::any_of(d.cases.begin(), d.cases.end(), named),
                          "Convergence sizes", "'" + name + "' is not a case of the study");
          figures.require(h > 0, "Convergence sizes", "the size of '" + name + "' must be > 0 m");
        }
    }

    /// Calibration/Parameters: "Path/Key: initial, lower, upper" separated by ";".
    std::vector<CalibrationParameter>
    calibration_parameters(const std::string &text, const ParameterScope &scope)
    {
      std::vector<CalibrationParameter> out;
      for (const auto &item : split(text, ';'))
        {
          const auto colon = item.rfind(':');
          scope.require(colon != std::string::npos && colon > 0, "Parameters",
                        "'" + item + "' is not 'Path/Key: initial, lower, upper'");
          CalibrationParameter p{unquote(item.substr(0, colon))};
          std::vector<double>  v;
          for (const auto &n : split(item.substr(colon + 1), ','))
            {
              char        *end   = nullptr;
              const double value = std::strtod(n.c_str(), &end);
              scope.require(*end == '\0' && std::isfinite(value), "Parameters",
                            "'" + n + "' of '" + p.path + "' is not a number");
              v.push_back(value);
            }
          scope.require(v.size() == 3, "Parameters", "'" + p.path + "' needs three numbers: initial, lower, upper");
          p.initial = v[0], p.lower = v[1], p.upper = v[2];
          scope.require(p.lower < p.upper && p.lower <= p.initial && p.initial <= p.upper, "Parameters",
                        "'" + p.path + "': needs lower < upper and the initial value within them");
          for (const auto &q : out)
            scope.require(q.path != p.path, "Parameters", "'" + p.path + "' is fitted twice");
          out.push_back(p);
        }
      scope.require(out.size() <= 20, "Parameters", "at most 20 parameters");
      return out;
    }

    /// The rest of subsection Calibration, once the cases and metrics are read: every
    /// parameter's bounds and every validation case applied to the base scene as the
    /// runs will, the weights' columns known.
    void
    read_calibration(ParameterHandler &prm, StudyDefinition &d, const ParameterScope &top,
                     const std::vector<std::string> &extra)
    {
      auto      &c     = d.calibration;
      const auto scope = top.subsection("Calibration");
      const auto common = case_settings(prm);
      prm.enter_subsection("Calibration");
      const auto weights    = named_numbers(prm.get("Weights"), scope, "Weights");
      const auto validation = listed(prm.get("Validation"), {}, scope, "Validation");
      c.max_evaluations     = static_cast<unsigned>(prm.get_integer("Max evaluations"));
      c.difference_step     = prm.get_double("Difference step");
      prm.leave_subsection();
      if (c.parameters.empty())
        {
          scope.require(weights.empty(), "Weights", "needs Calibration/Parameters to fit");
          scope.require(validation.empty(), "Validation", "needs Calibration/Parameters to fit");
          return;
        }
      scope.require(d.references.size() == 1 && !d.reference_series, "Parameters",
                    "a calibration has one reference (no Reference/Per axis or Series)");
      for (const auto &p : c.parameters)
        for (const double v : {p.lower, p.upper})
          {
            Case at{"bound", common, {}};
            at.settings.push_back(p.path + "=" + shortest_text(v));
            at.settings.insert(at.settings.end(), extra.begin(), extra.end());
            check(at, d.base_scene, scope, "Parameters");
          }
      const auto columns = d.metrics.error_columns();
      for (const auto &[column, w] : weights)
        {
          scope.require(std::find(columns.begin(), columns.end(), column) != columns.end(), "Weights",
                        "'" + column + "' is not one of the Metrics' error columns");
          scope.require(w > 0, "Weights", "the weight of '" + column + "' must be > 0");
        }
      c.weights = weights;
      if (c.weights.empty())
        for (const auto &column : columns)
          if (column.rfind("probe.", 0) == 0 || column == "surface.l2" ||
              std::find(d.metrics.scalars.begin(), d.metrics.scalars.end(), column) != d.metrics.scalars.end() ||
              (column.size() > 3 && column.compare(column.size() - 3, 3, ".l2") == 0 &&
               column.find(".phase") == std::string::npos))
            c.weights.emplace_back(column, 1.0);
      scope.require(!c.weights.empty(), "Weights", "Metrics names no error to fit");
      for (const auto &v : validation) // kept with their own settings, checked with all
        {
          scope.require(!v.name.empty() && v.name != "reference", "Validation", "a case needs a name");
          Case all{v.name, common, {}};
          all.settings.insert(all.settings.end(), v.settings.begin(), v.settings.end());
          for (const auto &p : c.parameters)
            all.settings.push_back(p.path + "=" + shortest_text(p.initial));
          all.settings.insert(all.settings.end(), extra.begin(), extra.end());
          check(all, d.base_scene, scope, "Validation");
          c.validation.push_back(v);
        }
    }
  } // namespace

  std::vector<std::string>
  MetricsSpec::error_columns() const
  {
    std::vector<std::string> out = scalars;
    for (const auto &p : probes)
      out.push_back("probe." + p);
    if (!probes.empty())
      out.push_back("probes.max");
    for (const auto &c : curves)
      {
        for (const char *e : {".l2", ".linf", ".peak"})
          out.push_back(c + e);
        if (alignment == "events")
          for (std::size_t k = 1; k < events.size(); ++k)
            out.push_back(c + ".phase" + std::to_string(k) + ".l2");
      }
    if (alignment == "events")
      out.push_back("events.time");
    if (surface)
      out.insert(out.end(), {"surface.l2", "surface.max", "surface.distance"});
    return out;
  }

  StudyDefinition
  StudyDefinition::read(const std::string &study_file, const std::vector<std::string> &extra,
                        const std::string *case_list)
  {
    ParameterHandler prm;
    declare(prm);
    declare_metrics(prm);
    declare_objective_and_figures(prm);
    const auto           file = ParameterFile::from_file(prm, study_file);
    const ParameterScope top(file, "");
    StudyDefinition      d;
    d.file = study_file;
    for (const char *key : {"Name", "Base scene", "Settings", "Reference/Settings", "Reference/Per axis", "Reference/Series", "Reference/On failure", "Cases/Settings", "Cases/Axes", "Cases/List",
                            "Metrics/Scalars", "Metrics/Probes", "Metrics/Curves", "Metrics/Surface", "Metrics/Alignment events",
                            "Objective/Error", "Objective/Tolerances", "Objective/Limits", "Figures/Stability axes",
                            "Figures/Map axes", "Figures/Map metrics", "Figures/Map flags",
                            "Figures/Convergence metric", "Figures/Convergence sizes", "Calibration/Parameters",
                            "Calibration/Weights", "Calibration/Validation"})
      d.lines[key] = file.line_of(key);
    d.name = prm.get("Name");
    top.require(!d.name.empty() && file_name_part(d.name) == d.name, "Name",
                "a study needs a name of letters, digits, '.', '-' and '_'");
    const std::string base = prm.get("Base scene");
    top.require(!base.empty(), "Base scene", "a study needs a base scene");
    d.base_scene = file.resolve(base);

    prm.enter_subsection("Calibration");
    d.calibration.parameters = calibration_parameters(prm.get("Parameters"), top.subsection("Calibration"));
    prm.leave_subsection();
    const auto axes = read_cases(prm, d, top, extra, case_list);
    read_metrics_and_objective(prm, d, top);
    read_figures(prm, d, axes, top);
    read_calibration(prm, d, top, extra);
    return d;
  }

  void
  StudyDefinition::fail(const std::string &key, const std::string &problem) const
  {
    const auto line = lines.find(key);
    const bool set  = line != lines.end() && line->second > 0;
    throw InputError(file + (set ? ":" + std::to_string(line->second) : "") + ": " + key +
                     (set ? "" : " (default)") + ": " + one_line(problem));
  }

  const std::map<std::string, std::string> &
  StudyDefinition::cost_units()
  {
    static const std::map<std::string, std::string> units{
      {"step_time_median", "s"}, {"step_time_p99", "s"}, {"wall_time", "s"}, {"core_seconds", "s"}};
    return units;
  }
} // namespace suturesim::study
