#include <suturesim/study/case_metrics.h>
#include <suturesim/study/curve_metrics.h>
#include <suturesim/study/surface_error.h>

#include <algorithm>
#include <array>
#include <optional>
#include <stdexcept>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace suturesim::study
{
  namespace fs = std::filesystem;

  namespace
  {
    constexpr double nan = std::numeric_limits<double>::quiet_NaN();

    /// forces.csv: a header "name [unit],..." and rows of numbers.
    void
    read_columns(const fs::path &file, RunData &data)
    {
      std::ifstream in(file);
      if (!in)
        return;
      std::string line, cell;
      std::getline(in, line);
      std::vector<std::string> names;
      std::istringstream       header(line);
      while (std::getline(header, cell, ','))
        names.push_back(cell.substr(0, cell.find(" [")));
      while (std::getline(in, line))
        {
          std::istringstream row(line);
          for (std::size_t k = 0; k < names.size() && std::getline(row, cell, ','); ++k)
            data.columns[names[k]].push_back(std::strtod(cell.c_str(), nullptr));
        }
    }

    /// "reference" or "case", for messages
    const char *
    which(const bool reference)
    {
      return reference ? "reference" : "case";
    }

    Curve
    curve(const RunData &run, const std::string &name, const bool reference)
    {
      const auto y = run.columns.find(name);
      const auto t = run.columns.find("time");
      if (y == run.columns.end() || t == run.columns.end())
        throw MissingMetric("Metrics/Curves",
                            std::string("the ") + which(reference) + " has no forces.csv column '" + name + "'",
                            reference);
      // keep strictly increasing times (a restarted row repeats its time)
      Curve c;
      for (std::size_t k = 0; k < t->second.size() && k < y->second.size(); ++k)
        if (c.x.empty() || t->second[k] > c.x.back())
          c.x.push_back(t->second[k]), c.y.push_back(y->second[k]);
      return c;
    }

    /// The times of @p kinds matched in order, each to the next event of its kind.
    std::vector<double>
    event_times(const RunData &run, const std::vector<std::string> &kinds, const bool reference)
    {
      std::vector<std::pair<double, std::string>> events;
      for (const auto &e : run.summary.value("events", nlohmann::json::array()))
        events.emplace_back(e.at("time").get<double>(), e.at("kind").get<std::string>());
      std::stable_sort(events.begin(), events.end(),
                       [](const auto &a, const auto &b) { return a.first < b.first; });
      std::vector<double> times;
      std::size_t         next = 0;
      for (const auto &kind : kinds)
        {
          while (next < events.size() && events[next].second != kind)
            ++next;
          if (next == events.size())
            throw MissingMetric("Metrics/Alignment events",
                                std::string("the ") + which(reference) + " has no event '" + kind + "' after " +
                                  std::to_string(times.size()) + " matched ones",
                                reference);
          times.push_back(events[next++].first);
        }
      return times;
    }

    std::array<double, 3>
    probe(const RunData &run, const std::string &name, const bool reference)
    {
      std::array<double, 3> u{};
      for (int d = 0; d < 3; ++d)
        {
          const auto v = run.metric(name + "_displacement_" + "xyz"[d]);
          if (!v)
            throw MissingMetric("Metrics/Probes",
                                std::string("the ") + which(reference) + " has no probe '" + name + "' (metrics." +
                                  name + "_displacement_" + "xyz"[d] + ")",
                                reference);
          u[d] = *v;
        }
      return u;
    }

    /// The errors, or NaN ones where they have no meaning (the reference vanishes).
    template <typename F>
    CurveErrors
    guarded(const F &errors)
    {
      try
        {
          return errors();
        }
      catch (const std::invalid_argument &)
        {
          return {nan, nan, nan};
        }
    }

    /// The event times of both runs (aligned on events), or why the case has none.
    struct Alignment
    {
      std::vector<double>          ce, re; ///< the case's and the reference's
      std::optional<MissingMetric> missing;
    };

    /// The columns of curve @p name: e₂, e∞, e_p over the whole overlap, then (aligned on
    /// events @p a) e₂ per phase.
    void
    curve_columns(const MetricsSpec &spec, const std::string &name, const RunData &run, const RunData &ref,
                  const Alignment &a, std::vector<double> &out)
    {
      const Curve r = curve(ref, name, true), c = curve(run, name, false);
      if (spec.alignment == "time")
        {
          const auto e =
            guarded([&] { return curve_errors(c, r, std::max(c.front(), r.front()), std::min(c.back(), r.back())); });
          out.insert(out.end(), {e.relative_l2, e.relative_linf, e.peak});
          return;
        }
      // over the whole overlap after the warp (past the last event: shifted by its offset),
      // then phase by phase; NaN where the reference vanishes (a tension before the thread
      // is in)
      if (a.missing)
        throw *a.missing;
      const auto &ce = a.ce, &re = a.re;
      // events at one time in either run (two pierce points taken in one step) bound no
      // phase: the warp uses the strictly increasing ones, their phases are NaN
      std::vector<double> cw, rw;
      std::vector<bool>   bounded(re.size(), false);
      for (std::size_t k = 0; k < re.size(); ++k)
        if (cw.empty() || (ce[k] > cw.back() && re[k] > rw.back()))
          {
            bounded[k] = !cw.empty() && ce[k - 1] == cw.back() && re[k - 1] == rw.back();
            cw.push_back(ce[k]), rw.push_back(re[k]);
          }
      const Curve warped = cw.size() >= 2 ? warp_to_events(c, cw, rw) : c;
      const auto  e      = guarded([&] {
        return curve_errors(warped, r, std::max(warped.front(), r.front()), std::min(warped.back(), r.back()));
      });
      out.insert(out.end(), {e.relative_l2, e.relative_linf, e.peak});
      for (std::size_t k = 0; k + 1 < re.size(); ++k)
        out.push_back(bounded[k + 1] ? guarded([&] { return curve_errors(warped, r, re[k], re[k + 1]); }).relative_l2
                                     : nan);
    }

    /// Appends what @p columns appends, or @p n NaNs when the case lacks the metric (its
    /// message then goes to @p missing); a metric the reference lacks is thrown on.
    template <typename F>
    void
    measure(std::vector<double> &out, const std::size_t n, std::vector<std::string> &missing, const F &columns)
    {
      const std::size_t before = out.size();
      try
        {
          columns();
        }
      catch (const MissingMetric &e)
        {
          if (e.in_reference)
            throw;
          out.resize(before);
          out.insert(out.end(), n, nan);
          missing.push_back(e.what());
        }
    }

    /// (s − s_ref)/|s_ref| of summary metric @p s.
    double
    scalar_error(const std::string &s, const RunData &run, const RunData &reference)
    {
      const auto r = reference.metric(s), c = run.metric(s);
      if (!r || !c)
        throw MissingMetric("Metrics/Scalars",
                            std::string("the ") + which(!r) + " has no metric '" + s + "' in summary.json", !r);
      if (*r == 0)
        throw MissingMetric("Metrics/Scalars", "the reference's '" + s + "' is 0: it has no relative error", true);
      return relative_error(*c, *r);
    }

    /// A column per probe, |u − u_ref|/|u_ref|, then their largest (NaN if one is missing).
    void
    probe_columns(const MetricsSpec &spec, const RunData &run, const RunData &reference, std::vector<double> &out,
                  std::vector<std::string> &missing)
    {
      double            worst          = 0;
      const std::size_t missing_before = missing.size();
      for (const auto &p : spec.probes)
        measure(out, 1, missing, [&] {
          const auto r = probe(reference, p, true), c = probe(run, p, false);
          double     diff = 0, norm = 0;
          for (int d = 0; d < 3; ++d)
            diff += (c[d] - r[d]) * (c[d] - r[d]), norm += r[d] * r[d];
          if (norm == 0)
            throw MissingMetric("Metrics/Probes", "the reference's probe '" + p + "' does not move", true);
          out.push_back(std::sqrt(diff / norm));
          worst = std::max(worst, out.back());
        });
      if (!spec.probes.empty())
        out.push_back(missing.size() == missing_before ? worst : nan);
    }

    /// The events matched once, for every curve and the event-time error.
    Alignment
    align(const MetricsSpec &spec, const RunData &run, const RunData &reference)
    {
      Alignment a;
      if (spec.alignment != "events")
        return a;
      try
        {
          a.re = event_times(reference, spec.events, true);
          a.ce = event_times(run, spec.events, false);
        }
      catch (const MissingMetric &e)
        {
          if (e.in_reference)
            throw;
          a.missing = e;
        }
      return a;
    }

    SurfaceErrors
    surface_error(const RunData &run, const RunData &reference)
    {
      if (!reference.surface || !run.surface)
        throw MissingMetric("Metrics/Surface",
                            std::string("the ") + which(!reference.surface) +
                              " wrote no surface_displacement.json (a tissue on an unrefined mesh writes it)",
                            !reference.surface);
      try
        {
          return surface_errors(*run.surface, *reference.surface);
        }
      catch (const std::invalid_argument &e)
        {
          throw MissingMetric("Metrics/Surface", e.what(), true);
        }
    }
  } // namespace

  RunData
  RunData::read(const std::string &folder)
  {
    RunData       data;
    std::ifstream in(fs::path(folder) / "summary.json");
    if (!in)
      throw std::runtime_error(folder + "/summary.json: cannot be read");
    try
      {
        data.summary = nlohmann::json::parse(in);
      }
    catch (const nlohmann::json::exception &e)
      {
        throw std::runtime_error(folder + "/summary.json: " + e.what());
      }
    read_columns(fs::path(folder) / "forces.csv", data);
    if (fs::exists(fs::path(folder) / "surface_displacement.json"))
      data.surface = io::SurfaceField::read((fs::path(folder) / "surface_displacement.json").string());
    return data;
  }

  std::optional<double>
  RunData::metric(const std::string &path) const
  {
    const nlohmann::json *node = &summary;
    std::string           part;
    std::istringstream    parts("metrics." + path);
    while (std::getline(parts, part, '.'))
      {
        // objects by key, arrays by index (tip_position.2)
        if (node->is_array() && !part.empty() && part.find_first_not_of("0123456789") == std::string::npos &&
            std::stoul(part) < node->size())
          node = &node->at(std::stoul(part));
        else if (node->is_object() && node->contains(part))
          node = &node->at(part);
        else
          return std::nullopt;
      }
    if (!node->is_number())
      return std::nullopt;
    return node->get<double>();
  }

  std::vector<double>
  case_errors(const MetricsSpec &spec, const RunData &run, const RunData &reference, std::vector<std::string> &missing)
  {
    std::vector<double> out;
    for (const auto &s : spec.scalars)
      measure(out, 1, missing, [&] { out.push_back(scalar_error(s, run, reference)); });
    probe_columns(spec, run, reference, out, missing);
    const Alignment   a      = align(spec, run, reference);
    const std::size_t phases = spec.alignment == "events" ? spec.events.size() - 1 : 0;
    for (const auto &c : spec.curves)
      measure(out, 3 + phases, missing, [&] { curve_columns(spec, c, run, reference, a, out); });
    if (spec.alignment == "events")
      measure(out, 1, missing, [&] {
        if (a.missing)
          throw *a.missing;
        double worst_time = 0;
        for (std::size_t k = 0; k < a.ce.size(); ++k)
          worst_time = std::max(worst_time, std::abs(a.ce[k] - a.re[k]));
        out.push_back(worst_time);
      });
    if (spec.surface)
      measure(out, 3, missing, [&] {
        const auto e = surface_error(run, reference);
        out.insert(out.end(), {e.relative_l2, e.relative_max, e.distance});
      });
    return out;
  }

  std::string
  error_unit(const std::string &column)
  {
    return column == "events.time" ? "s" : column == "surface.distance" ? "m" : "1";
  }

  const std::vector<std::pair<std::string, std::string>> &
  cost_columns()
  {
    static const std::vector<std::pair<std::string, std::string>> columns{
      {"step_time_median", "s"}, {"step_time_p99", "s"}, {"wall_time", "s"}, {"core_seconds", "s"},
      {"peak_memory", "B"}, {"newton_per_step_max", "1"}, {"failed_attempts", "1"}};
    return columns;
  }

  namespace
  {
    /// The most Newton iterations of one step (accurate runs: summary.json's "steps"),
    /// NaN for a run without them.
    double
    newton_per_step_max(const nlohmann::json &summary)
    {
      double most = nan;
      if (summary.contains("steps") && summary["steps"].is_array())
        for (const auto &step : summary["steps"])
          if (step.is_object() && step.contains("newton_iterations") && step["newton_iterations"].is_number())
            most = std::isnan(most) ? step["newton_iterations"].get<double>()
                                    : std::max(most, step["newton_iterations"].get<double>());
      return most;
    }

    /// Steps whose first attempt failed and were cut back (summary.json's
    /// "solver.failed_attempts"), NaN for a run without a cut-back stepper.
    double
    failed_attempts(const nlohmann::json &summary)
    {
      if (summary.contains("solver") && summary["solver"].is_object() && summary["solver"].contains("failed_attempts") &&
          summary["solver"]["failed_attempts"].is_number())
        return summary["solver"]["failed_attempts"].get<double>();
      return nan;
    }
  } // namespace

  std::vector<double>
  case_costs(const RunData &run, const CaseOutcome &outcome)
  {
    const auto us = [&](const char *key) {
      const auto v = run.metric(key);
      return v ? 1e-6 * *v : nan;
    };
    return {us("step_time_median_us"), us("step_time_p99_us"), outcome.wall_seconds, outcome.cpu_seconds,
            outcome.peak_memory_bytes,   newton_per_step_max(run.summary), failed_attempts(run.summary)};
  }
} // namespace suturesim::study
