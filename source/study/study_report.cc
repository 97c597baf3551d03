#include <suturesim/core/error.h>
#include <suturesim/io/checked_output.h>
#include <suturesim/scene/simulation.h>
#include <suturesim/study/case_metrics.h>
#include <suturesim/study/convergence.h>
#include <suturesim/study/pareto.h>
#include <suturesim/study/study_report.h>

#include <deal.II/base/parameter_handler.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace suturesim::study
{
  namespace fs = std::filesystem;

  namespace
  {
    std::string
    number(const double v)
    {
      if (!std::isfinite(v))
        return "";
      char text[32];
      std::snprintf(text, sizeof text, "%.10g", v);
      return text;
    }

    /// A CSV field, quoted when it holds a separator or a quote.
    std::string
    field(const std::string &s)
    {
      if (s.find_first_of(",\"\n") == std::string::npos)
        return s;
      std::string q = "\"";
      for (const char c : s)
        q += c == '"' ? std::string("\"\"") : std::string(1, c);
      return q + "\"";
    }

    nlohmann::json
    json_number(const double v)
    {
      return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
    }

    std::size_t
    index_of(const std::vector<std::string> &names, const std::string &name)
    {
      return std::find(names.begin(), names.end(), name) - names.begin();
    }

    /// The axis paths of the study's cases in order of first appearance.
    std::vector<std::string>
    axis_paths(const StudyDefinition &study)
    {
      std::vector<std::string> paths;
      for (const auto &c : study.cases)
        for (const auto &[path, value] : c.axis_values)
          if (std::find(paths.begin(), paths.end(), path) == paths.end())
            paths.push_back(path);
      return paths;
    }

    std::string
    axis_value(const Case &c, const std::string &path)
    {
      for (const auto &[p, v] : c.axis_values)
        if (p == path)
          return v;
      return "";
    }
  } // namespace

  std::string
  parameter_unit(const std::string &path)
  {
    static std::map<std::string, std::string> units;
    if (units.empty())
      {
        dealii::ParameterHandler prm;
        scene::Simulation::declare_parameters(prm);
        std::ostringstream text;
        prm.print_parameters(text, dealii::ParameterHandler::Text);
        std::istringstream       lines(text.str());
        std::vector<std::string> sections;
        std::string              line, comment;
        while (std::getline(lines, line))
          {
            const auto        start   = line.find_first_not_of(' ');
            const std::string content = start == std::string::npos ? "" : line.substr(start);
            if (content.rfind("# ", 0) == 0)
              comment += " " + content.substr(2);
            else if (content.rfind("subsection ", 0) == 0)
              sections.push_back(content.substr(11)), comment.clear();
            else if (content == "end" && !sections.empty())
              sections.pop_back(), comment.clear();
            else if (content.rfind("set ", 0) == 0)
              {
                std::string key = content.substr(4, content.find('=') - 4);
                key.erase(key.find_last_not_of(' ') + 1);
                std::string full;
                for (const auto &s : sections)
                  full += s + "/";
                const auto unit = comment.find("Unit: ");
                if (unit != std::string::npos)
                  {
                    // "Unit: N/m. Range: ..." -> N/m; a phrase ("as the .geo file defines") is no unit
                    std::string u = comment.substr(unit + 6, comment.find(". ", unit + 6) - unit - 6);
                    if (!u.empty() && u.back() == '.')
                      u.pop_back();
                    units[full + key] = (u.find(' ') != std::string::npos || u == "none") ? "" : u;
                  }
                comment.clear();
              }
          }
      }
    const auto u = units.find(path);
    return u == units.end() ? "" : u->second;
  }

  std::string
  StudyReport::against(const std::size_t k) const
  {
    if (study.reference_series)
      return "series";
    return study.references[k < study.references.size() ? k : rows[k].definition->reference].name;
  }

  StudyReport::StudyReport(const StudyDefinition &study, std::vector<CaseRow> rows, nlohmann::json series)
    : study(study)
    , rows(std::move(rows))
    , series(std::move(series))
    , error_index(index_of(study.metrics.error_columns(), study.objective.error))
    , cost_index(std::find_if(cost_columns().begin(), cost_columns().end(),
                              [&](const auto &c) { return c.first == study.objective.cost; }) -
                 cost_columns().begin())
  {
    const auto columns = study.metrics.error_columns();
    for (auto &row : this->rows)
      {
        const bool bounded = !(study.objective.tolerances.empty() && study.objective.limits.empty());
        if (row.outcome.status != "completed" || !bounded)
          continue;
        // a missing value (NaN) makes the ratio NaN: not within
        double     ratio = 0;
        const auto worse = [&](const double r) { ratio = std::isnan(r) || std::isnan(ratio) ? NAN : std::max(ratio, r); };
        for (std::size_t k = 0; k < study.objective.limits.size(); ++k)
          worse(k < row.limit_values.size() ? std::abs(row.limit_values[k]) / study.objective.limits[k].second : NAN);
        for (const auto &[name, bound] : study.objective.tolerances)
          worse(row.errors.empty() ? NAN : std::abs(row.errors[index_of(columns, name)]) / bound);
        row.bound_ratio      = ratio;
        row.within_tolerance = ratio <= 1;
      }
  }

  double
  StudyReport::cost(const CaseRow &row) const
  {
    return row.costs.empty() ? NAN : row.costs[cost_index];
  }

  double
  StudyReport::error(const CaseRow &row) const
  {
    if (study.objective.error.empty() || row.errors.empty())
      return NAN;
    return std::abs(row.errors[error_index]);
  }

  std::vector<std::optional<std::size_t>>
  StudyReport::best() const
  {
    // per reference; the error of "cheapest within tolerance" is the bound ratio, its tolerance 1
    // (a resolution series is one reference: its cases point at its finest run)
    std::vector<std::optional<std::size_t>> chosen;
    const std::size_t first = study.reference_series ? study.references.size() - 1 : 0;
    for (std::size_t group = first; group < study.references.size(); ++group)
      {
        std::vector<TradeOff>    cases;
        std::vector<std::size_t> index;
        for (std::size_t k = study.references.size(); k < rows.size(); ++k)
          if (rows[k].definition->reference == group)
            {
              cases.push_back({cost(rows[k]), rows[k].bound_ratio,
                               std::isfinite(rows[k].bound_ratio) && std::isfinite(cost(rows[k]))});
              index.push_back(k);
            }
        const auto pick = cheapest_within(cases, 1.0);
        chosen.push_back(pick ? std::optional<std::size_t>(index[*pick]) : std::nullopt);
      }
    return chosen;
  }

  namespace
  {
    /// A stability-map cell's state: stable, diverged, inaccurate (completed beyond a
    /// bound, or without a measured metric: a wound that never closed), else the status.
    std::string
    cell_state(const CaseRow &r, const bool bounded)
    {
      if (r.outcome.status == "completed")
        return bounded && !r.within_tolerance ? "inaccurate" : "stable";
      if (r.outcome.status == "failed")
        return "diverged";
      return r.outcome.status == "incomplete" ? "inaccurate" : r.outcome.status;
    }

    /// Per row of a map (cases of one panel and one y): the measured boundary in dt
    /// against the median of the rows' predicted dt_crit.
    nlohmann::json
    measured_boundary(const std::vector<const CaseRow *> &row)
    {
      double              stable = 0, diverged = INFINITY;
      std::vector<double> crit;
      for (const auto *r : row)
        {
          if (r->outcome.status == "failed")
            diverged = std::min(diverged, r->dt);
          else if (r->outcome.status == "completed")
            stable = std::max(stable, r->dt);
          if (std::isfinite(r->dt_crit))
            crit.push_back(r->dt_crit);
        }
      std::sort(crit.begin(), crit.end());
      return {{"dt_crit", json_number(crit.empty() ? NAN : crit[crit.size() / 2])},
              {"largest_stable_dt", stable > 0 ? json_number(stable) : nullptr},
              {"smallest_diverged_dt", json_number(diverged)}};
    }
  } // namespace

  std::string
  StudyReport::panel_of(const Case &c, const std::string &x, const std::string &y) const
  {
    // the axes other than the map's two: one map (panel) per combination of their values
    std::string panel;
    for (const auto &[path, value] : c.axis_values)
      if (path != x && path != y)
        panel += (panel.empty() ? "" : ", ") + path + " = " + value;
    return panel;
  }

  nlohmann::json
  StudyReport::map() const
  {
    const auto &f = study.figures;
    if (f.map_x.empty())
      return nullptr;
    // values by metric name: the cases' by their own, the references' by theirs
    const auto named = [](const std::vector<std::string> &names, const std::vector<double> &values) {
      nlohmann::json out = nlohmann::json::object();
      for (std::size_t k = 0; k < names.size(); ++k)
        out[names[k]] = k < values.size() ? json_number(values[k]) : nullptr;
      return out;
    };
    std::vector<std::string> own, other;
    nlohmann::json           metrics = nlohmann::json::array();
    for (const auto &[a, b] : f.map_metrics)
      {
        own.push_back(a), other.push_back(b);
        metrics.push_back({{"case", a}, {"reference", b}});
      }
    nlohmann::json cells = nlohmann::json::array();
    for (std::size_t k = study.references.size(); k < rows.size(); ++k)
      {
        const auto &r = rows[k];
        const auto &c = *r.definition;
        // a resolution series has no one reference row per case
        const auto *reference = study.reference_series ? nullptr : &rows[c.reference];
        cells.push_back({{"case", c.name},
                         {"panel", panel_of(c, f.map_x, f.map_y)},
                         {"x", axis_value(c, f.map_x)},
                         {"y", axis_value(c, f.map_y)},
                         {"status", r.outcome.status},
                         {"reference", reference ? reference->definition->name : ""},
                         {"reference_status", reference ? reference->outcome.status : ""},
                         {"values", named(own, r.map_values)},
                         {"reference_values", named(other, reference ? reference->map_values : std::vector<double>{})},
                         {"flags", named(f.map_flags, r.map_flags)}});
      }
    // the references' values are the case's own physics (per axis) or one number (a single reference)
    const bool per_cell = study.references_per_axis;
    return {{"x", f.map_x},         {"y", f.map_y},          {"x_unit", parameter_unit(f.map_x)},
            {"y_unit", parameter_unit(f.map_y)}, {"metrics", metrics}, {"flags", f.map_flags},
            {"references_per_cell", per_cell}, {"cells", cells}};
  }

  nlohmann::json
  StudyReport::stability() const
  {
    const auto &x = study.figures.stability_x, &y = study.figures.stability_y;
    if (x.empty())
      return nullptr;
    const bool     bounded = !(study.objective.tolerances.empty() && study.objective.limits.empty());
    nlohmann::json cells   = nlohmann::json::array();
    // the map's rows (panel, y) in the order of the axes
    std::vector<std::pair<std::pair<std::string, std::string>, std::vector<const CaseRow *>>> rows_of_map;
    for (std::size_t k = study.references.size(); k < rows.size(); ++k)
      {
        const auto &r     = rows[k];
        const auto  key   = std::make_pair(panel_of(*r.definition, x, y), axis_value(*r.definition, y));
        cells.push_back({{"case", r.definition->name}, {"panel", key.first}, {"x", axis_value(*r.definition, x)},
                         {"y", key.second}, {"state", cell_state(r, bounded)}, {"dt", json_number(r.dt)},
                         {"dt_crit", json_number(r.dt_crit)}});
        auto row = std::find_if(rows_of_map.begin(), rows_of_map.end(), [&](const auto &b) { return b.first == key; });
        if (row == rows_of_map.end())
          row = rows_of_map.insert(rows_of_map.end(), {key, {}});
        row->second.push_back(&r);
      }
    nlohmann::json boundary = nlohmann::json::array();
    for (const auto &[key, row] : rows_of_map)
      {
        auto b     = measured_boundary(row);
        b["panel"] = key.first;
        b["y"]     = key.second;
        boundary.push_back(b);
      }
    return {{"x", x}, {"y", y}, {"x_unit", parameter_unit(x)}, {"y_unit", parameter_unit(y)}, {"cells", cells},
            {"boundary", boundary}};
  }

  nlohmann::json
  StudyReport::to_json(const nlohmann::json &timing) const
  {
    const auto     columns = study.metrics.error_columns();
    nlohmann::json out{{"name", study.name}, {"study_file", study.file}, {"base_scene", study.base_scene}};
    out["objective"] = {{"error", study.objective.error}, {"cost", study.objective.cost},
                        {"tolerances", nlohmann::json::object()}};
    for (const auto &[name, bound] : study.objective.tolerances)
      out["objective"]["tolerances"][name] = bound;
    for (const auto &[name, bound] : study.objective.limits)
      out["objective"]["limits"][name] = bound;
    out["timing"] = timing;
    out["cases"]  = nlohmann::json::array();
    std::vector<TradeOff> trade;
    for (std::size_t k = 0; k < rows.size(); ++k)
      {
        const auto    &r = rows[k];
        const bool     is_reference = k < study.references.size();
        nlohmann::json c{{"name", r.definition->name},     {"status", r.outcome.status},
                         {"is_reference", is_reference},
                         {"reference", against(k)},
                         {"reason", r.outcome.reason},     {"reused", r.outcome.reused},
                         {"settings", r.definition->settings}, {"within_tolerance", r.within_tolerance},
                         {"dt", json_number(r.dt)},        {"dt_crit", json_number(r.dt_crit)}};
        for (const auto &[path, value] : r.definition->axis_values)
          c["axes"][path] = value;
        for (std::size_t e = 0; e < columns.size(); ++e)
          c["errors"][columns[e]] = r.errors.empty() ? nullptr : json_number(r.errors[e]);
        for (std::size_t e = 0; e < cost_columns().size(); ++e)
          c["costs"][cost_columns()[e].first] = r.costs.empty() ? nullptr : json_number(r.costs[e]);
        for (std::size_t e = 0; e < study.objective.limits.size(); ++e)
          c["limits"][study.objective.limits[e].first] =
            e < r.limit_values.size() ? json_number(r.limit_values[e]) : nullptr;
        c["cost"]  = json_number(cost(r));
        c["error"] = json_number(error(r));
        out["cases"].push_back(c);
        if (!is_reference)
          trade.push_back({cost(r), error(r),
                           r.outcome.status == "completed" && std::isfinite(cost(r)) && std::isfinite(error(r))});
      }
    out["front"] = nlohmann::json::array();
    for (const auto k : pareto_front(trade))
      out["front"].push_back(rows[k + study.references.size()].definition->name);
    // the cheapest adequate case: its name, or per reference {reference: name}
    const auto chosen = best();
    const auto name   = [&](const std::optional<std::size_t> &k) {
      return k ? nlohmann::json(rows[*k].definition->name) : nlohmann::json(nullptr);
    };
    out["best"] = chosen.size() == 1 ? name(chosen[0]) : nlohmann::json::object();
    for (std::size_t g = 0; chosen.size() > 1 && g < chosen.size(); ++g)
      out["best"][study.references[g].name] = name(chosen[g]);
    out["reference_series"] = series;
    out["stability"]  = stability();
    out["map"]        = map();
    out["convergence"] = convergence();
    return out;
  }

  nlohmann::json
  StudyReport::convergence() const
  {
    if (study.figures.convergence_metric.empty())
      return nullptr;
    // one series per value of Figures/Convergence series in the cases (e.g. per model path)
    const auto series_of = [&](const Case &c) {
      const std::string &path = study.figures.convergence_series;
      std::string        value = path.empty() ? "all" : "(base scene)";
      for (const auto &s : c.settings)
        if (!path.empty() && s.rfind(path + "=", 0) == 0)
          value = s.substr(path.size() + 1);
      return value;
    };
    // the sizes the study gives its cases, else every run's own representative size
    // (a run without one, by a suturesim before it was recorded, is listed without h)
    auto sizes = study.figures.convergence_sizes;
    if (sizes.empty())
      for (const auto &r : rows)
        if ((std::isfinite(r.mesh_size) && r.mesh_size > 0) || std::isfinite(r.convergence_value))
          sizes.emplace_back(r.definition->name, r.mesh_size);
    std::vector<std::pair<std::string, nlohmann::json>> series;
    for (const auto &[name, size] : sizes)
      for (const auto &r : rows)
        if (r.definition->name == name)
          {
            const std::string s  = series_of(*r.definition);
            auto              it = std::find_if(series.begin(), series.end(), [&](const auto &e) { return e.first == s; });
            if (it == series.end())
              it = series.insert(series.end(), {s, {{"series", s}, {"table", nlohmann::json::array()}}});
            it->second["table"].push_back({{"case", name}, {"h", json_number(size)}, {"value", json_number(r.convergence_value)},
                                           {"status", r.outcome.status}});
          }
    nlohmann::json out{{"metric", study.figures.convergence_metric},
                       {"h", study.figures.convergence_sizes.empty() ? "measured: (V/N)^(1/3)" : "given"},
                       {"series_parameter", study.figures.convergence_series},
                       {"series", nlohmann::json::array()}};
    for (auto &[name, s] : series)
      {
        // coarse to fine
        const auto h_of = [](const nlohmann::json &row) { return row["h"].is_null() ? 0.0 : row["h"].get<double>(); };
        std::stable_sort(s["table"].begin(), s["table"].end(),
                         [&](const auto &a, const auto &b) { return h_of(a) > h_of(b); });
        // one value per size (the first case of a size that two cases share)
        std::vector<double> h, f;
        for (const auto &row : s["table"])
          if (!row["value"].is_null() && !row["h"].is_null() &&
              std::find(h.begin(), h.end(), row["h"].get<double>()) == h.end())
            h.push_back(row["h"].get<double>()), f.push_back(row["value"].get<double>());
        if (h.size() >= 3)
          {
            const auto e        = estimate_convergence(h, f);
            s["observed_order"] = json_number(e.order);
            s["extrapolated"]   = json_number(e.extrapolated);
            s["gci_fine"]       = json_number(e.gci_fine);
            s["oscillatory"]    = e.oscillatory;
            s["diverging"]      = e.diverging;
            s["settled"]        = e.converged;
          }
        out["series"].push_back(s);
      }
    return out;
  }

  void
  StudyReport::write_cases_csv(const std::string &file) const
  {
    std::ofstream out(file);
    const auto    axes    = axis_paths(study);
    const auto    columns = study.metrics.error_columns();
    out << "case,status,reason,reference";
    for (const auto &a : axes)
      out << ',' << field(a + " [" + (parameter_unit(a).empty() ? "-" : parameter_unit(a)) + "]");
    for (const auto &c : columns)
      out << ',' << field(c + " error [" + error_unit(c) + "]");
    for (const auto &[name, unit] : cost_columns())
      out << ',' << name << " [" << unit << "]";
    for (const auto &[name, bound] : study.objective.limits)
      out << ',' << field(name + " value [-]");
    out << ",dt [s],dt_crit [s],within_tolerance [0|1]\n";
    for (std::size_t k = 0; k < rows.size(); ++k)
      {
        const auto &r = rows[k];
        out << field(r.definition->name) << ',' << r.outcome.status << ',' << field(r.outcome.reason) << ','
            << against(k);
        for (const auto &a : axes)
          out << ',' << field(axis_value(*r.definition, a));
        for (std::size_t e = 0; e < columns.size(); ++e)
          out << ',' << (r.errors.empty() ? "" : number(r.errors[e]));
        for (std::size_t e = 0; e < cost_columns().size(); ++e)
          out << ',' << (r.costs.empty() ? "" : number(r.costs[e]));
        for (std::size_t e = 0; e < study.objective.limits.size(); ++e)
          out << ',' << (e < r.limit_values.size() ? number(r.limit_values[e]) : "");
        out << ',' << number(r.dt) << ',' << number(r.dt_crit) << ',' << r.within_tolerance << '\n';
      }
    io::check_written(out, file);
  }

  void
  StudyReport::write_best(const std::string &folder) const
  {
    // a best.prm of an earlier run of the study must not outlive a changed choice
    for (const auto &entry : fs::directory_iterator(folder))
      {
        const std::string name = entry.path().filename().string();
        if (name.rfind("best", 0) == 0 && entry.path().extension() == ".prm")
          fs::remove(entry.path());
      }
    const auto               chosen = best();
    for (std::size_t g = 0; g < chosen.size(); ++g)
      if (chosen[g])
        {
          // best.prm, or per reference best_<its values>.prm
          const auto reference = study.reference_series ? std::string("the resolution series") : study.references[g].name;
          // "reference_1e9" -> best_1e9.prm
          const std::string name = chosen.size() == 1 ? "best.prm" : "best" + study.references[g].name.substr(std::string("reference").size()) + ".prm";
          write_best(folder, rows[*chosen[g]], name, reference);
        }
  }

  void
  StudyReport::write_best(const std::string &folder, const CaseRow &r, const std::string &name,
                          const std::string &reference) const
  {
    std::ifstream in(fs::path(folder) / "cases" / r.definition->name / "parameters.prm");
    std::ostringstream parameters;
    parameters << in.rdbuf();
    const std::string file = (fs::path(folder) / name).string();
    std::ofstream     out(file);
    out << "# The cheapest case of study '" << study.name << "' (" << study.file << ") within every tolerance"
        << (study.references.size() > 1 ? " against " + reference : std::string()) << ":\n"
        << "#   case " << r.definition->name << ", " << study.objective.cost << " = " << number(cost(r)) << " s\n";
    const auto columns = study.metrics.error_columns();
    for (const auto &[name, bound] : study.objective.tolerances)
      out << "#   |" << name << "| = " << number(std::abs(r.errors[index_of(columns, name)])) << " <= " << number(bound)
          << '\n';
    for (std::size_t k = 0; k < study.objective.limits.size(); ++k)
      out << "#   |" << study.objective.limits[k].first << "| = " << number(std::abs(r.limit_values[k]))
          << " <= " << number(study.objective.limits[k].second) << " (its own value)\n";
    out << "# It is " << study.base_scene << " with\n";
    for (const auto &s : r.definition->settings)
      out << "#   --set \"" << s << "\"\n";
    out << "# and reads as a scene by itself: suturesim " << name << " (every parameter below).\n\n" << parameters.str();
    io::check_written(out, file);
  }

  void
  StudyReport::write_map_csv(const std::string &file, const nlohmann::json &map) const
  {
    const auto   &f = study.figures;
    std::ofstream csv(file);
    const auto    value = [](const nlohmann::json &v) { return v.is_null() ? std::string() : number(v.get<double>()); };
    csv << "case,panel," << field(f.map_x + " [" + parameter_unit(f.map_x) + "]") << ','
        << field(f.map_y + " [" + parameter_unit(f.map_y) + "]") << ",status,reference,reference status";
    for (const auto &[own, other] : f.map_metrics)
      csv << ',' << field(own) << ',' << field("reference " + other);
    for (const auto &flag : f.map_flags)
      csv << ',' << field(flag);
    csv << '\n';
    for (const auto &c : map["cells"])
      {
        csv << field(c["case"].get<std::string>()) << ',' << field(c["panel"].get<std::string>()) << ','
            << field(c["x"].get<std::string>()) << ',' << field(c["y"].get<std::string>()) << ','
            << field(c["status"].get<std::string>()) << ',' << field(c["reference"].get<std::string>()) << ','
            << field(c["reference_status"].get<std::string>());
        for (const auto &[own, other] : f.map_metrics)
          csv << ',' << value(c["values"][own]) << ',' << value(c["reference_values"][other]);
        for (const auto &flag : f.map_flags)
          csv << ',' << value(c["flags"][flag]);
        csv << '\n';
      }
    io::check_written(csv, file);
  }

  void
  StudyReport::write(const std::string &folder, const nlohmann::json &timing) const
  {
    write_cases_csv((fs::path(folder) / "cases.csv").string());
    const auto    json = to_json(timing);
    const auto    file = (fs::path(folder) / "study.json").string();
    std::ofstream out(file);
    out << json.dump(1) << '\n';
    io::check_written(out, file);
    write_best(folder);
    if (!json["stability"].is_null())
      {
        const auto    name = (fs::path(folder) / "stability.csv").string();
        std::ofstream csv(name);
        csv << "case,panel," << field(study.figures.stability_x + " [" + parameter_unit(study.figures.stability_x) + "]")
            << ',' << field(study.figures.stability_y + " [" + parameter_unit(study.figures.stability_y) + "]")
            << ",state,dt [s],dt_crit [s]\n";
        for (const auto &c : json["stability"]["cells"])
          csv << field(c["case"].get<std::string>()) << ',' << field(c["panel"].get<std::string>()) << ','
              << field(c["x"].get<std::string>()) << ','
              << field(c["y"].get<std::string>()) << ',' << c["state"].get<std::string>() << ','
              << (c["dt"].is_null() ? "" : number(c["dt"].get<double>())) << ','
              << (c["dt_crit"].is_null() ? "" : number(c["dt_crit"].get<double>())) << '\n';
        io::check_written(csv, name);
      }
    if (!json["map"].is_null())
      write_map_csv((fs::path(folder) / "map.csv").string(), json["map"]);
    if (!json["convergence"].is_null())
      {
        const auto    name = (fs::path(folder) / "convergence.csv").string();
        std::ofstream csv(name);
        const auto   &c = json["convergence"];
        csv << "series,case,h [m]," << field(study.figures.convergence_metric) << ",status\n";
        for (const auto &series : c["series"])
          {
            const std::string name_of = series["series"];
            for (const auto &row : series["table"])
              csv << field(name_of) << ',' << row["case"].get<std::string>() << ','
                  << (row["h"].is_null() ? "" : number(row["h"].get<double>())) << ','
                  << (row["value"].is_null() ? "" : number(row["value"].get<double>())) << ','
                  << row["status"].get<std::string>() << '\n';
            if (series.contains("observed_order"))
              csv << "# " << name_of << ": observed order p = " << series["observed_order"].dump()
                  << ", Richardson extrapolation " << series["extrapolated"].dump() << ", GCI (fine) "
                  << series["gci_fine"].dump() << (series["oscillatory"].get<bool>() ? " (oscillatory)" : "")
                  << (series["diverging"].get<bool>() ? " (diverging: the differences grow)" : "") << '\n';
          }
        io::check_written(csv, name);
      }
  }
} // namespace suturesim::study
