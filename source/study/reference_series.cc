#include <suturesim/study/convergence.h>
#include <suturesim/study/reference_series.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <stdexcept>

namespace suturesim::study
{
  namespace
  {
    /// Sets "metrics.<dotted path>" of @p summary to @p value (the path exists: it was read).
    void
    set_metric(nlohmann::json &summary, const std::string &path, const double value)
    {
      nlohmann::json    *node = &summary["metrics"];
      std::string        part;
      std::istringstream parts(path);
      while (std::getline(parts, part, '.'))
        node = node->is_array() ? &node->at(std::stoul(part)) : &(*node)[part];
      *node = value;
    }

    /// The metric paths the study compares as numbers: its scalars and its probes' components.
    std::vector<std::string>
    extrapolated_paths(const MetricsSpec &spec)
    {
      std::vector<std::string> paths = spec.scalars;
      for (const auto &p : spec.probes)
        for (const char *c : {"_displacement_x", "_displacement_y", "_displacement_z"})
          paths.push_back(p + c);
      return paths;
    }

    /// The account of one metric over the series (sizes coarse to fine in @p h).
    nlohmann::json
    account_of(const std::vector<double> &h, const std::vector<double> &f)
    {
      nlohmann::json a{{"h", h}, {"values", f}, {"used", "finest"}};
      if (h.size() < 3)
        {
          a["why"] = "fewer than three sizes";
          return a;
        }
      if (std::all_of(f.begin(), f.end(), [&](const double v) { return v == f.back(); }))
        {
          a["why"] = "the same value at every size";
          return a;
        }
      const auto e       = estimate_convergence(h, f);
      a["observed_order"] = e.order;
      a["extrapolated"]  = e.extrapolated;
      a["gci_fine"]      = e.gci_fine;
      if (e.oscillatory)
        a["why"] = "oscillatory: no asymptotic range";
      else if (e.diverging)
        a["why"] = "the differences grow under refinement: no asymptotic range";
      else if (!e.converged || !(e.order > 0) || !std::isfinite(e.extrapolated))
        a["why"] = "the observed order did not settle";
      else
        a["used"] = "extrapolated";
      return a;
    }
  } // namespace

  SeriesReference
  series_reference(const MetricsSpec &spec, const std::vector<RunData> &runs, const std::vector<std::string> &names,
                   const std::vector<std::pair<std::string, double>> &sizes)
  {
    std::vector<double> size;
    for (std::size_t k = 0; k < runs.size(); ++k)
      {
        const auto given = std::find_if(sizes.begin(), sizes.end(), [&](const auto &s) { return s.first == names[k]; });
        if (given != sizes.end())
          {
            size.push_back(given->second);
            continue;
          }
        const auto &mesh = runs[k].summary.value("mesh", nlohmann::json::object());
        if (!mesh.contains("representative_size") || !(mesh.at("representative_size").get<double>() > 0))
          throw std::invalid_argument("the run '" + names[k] + "' records no mesh size (summary.json "
                                      "mesh.representative_size)");
        size.push_back(mesh.at("representative_size").get<double>());
      }
    // coarse to fine
    std::vector<std::size_t> order(runs.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](auto a, auto b) { return size[a] > size[b]; });
    for (std::size_t k = 1; k < order.size(); ++k)
      if (!(size[order[k]] < size[order[k - 1]]))
        throw std::invalid_argument("the runs '" + names[order[k - 1]] + "' and '" + names[order[k]] +
                                    "' have the same mesh size");

    SeriesReference out{runs[order.back()], {{"runs", nlohmann::json::array()}, {"metrics", nlohmann::json::object()}}};
    for (const auto k : order)
      out.account["runs"].push_back({{"name", names[k]}, {"h", size[k]}});
    for (const auto &path : extrapolated_paths(spec))
      {
        std::vector<double> h, f;
        for (const auto k : order)
          {
            const auto v = runs[k].metric(path);
            if (!v)
              throw MissingMetric(std::find(spec.scalars.begin(), spec.scalars.end(), path) != spec.scalars.end()
                                    ? "Metrics/Scalars"
                                    : "Metrics/Probes",
                                  "the reference run '" + names[k] + "' has no metric '" + path + "' in summary.json",
                                  true);
            h.push_back(size[k]);
            f.push_back(*v);
          }
        auto a = account_of(h, f);
        if (a["used"] == "extrapolated")
          set_metric(out.data.summary, path, a["extrapolated"].get<double>());
        out.account["metrics"][path] = a;
      }
    return out;
  }
} // namespace suturesim::study
