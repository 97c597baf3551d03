#include <suturesim/scene/tear_monitor.h>

#include <suturesim/core/level_crossing.h>

#include <algorithm>
#include <cmath>

namespace suturesim::scene
{
  TearMonitor::TearMonitor(const tearing::TearCriteria &criteria, const tearing::Wound &wound)
    : criteria(criteria)
    , wound(wound)
  {}

  TearMonitor::TractState::TractState(const tearing::Tract &tract, const std::size_t n_criteria)
    : tract(tract)
    , largest_ratio(n_criteria, 0.0)
    , last_ratio(n_criteria, std::nan(""))
    , onset(n_criteria)
  {}

  namespace
  {
    tearing::Point3
    point3(const dealii::Point<3> &X)
    {
      return {{X[0], X[1], X[2]}};
    }
  } // namespace

  void
  TearMonitor::update(const double t, const double tension, tissue::TissueModel &model,
                      const std::vector<coupling::AccuratePiercePoint> &pierce, const std::vector<double> &forces)
  {
    // Newest first: an exit followed by an entry is one pass's tract, the entry made
    // first. A tract is known by its entry point, which never moves (material point).
    // Its force on its holes: the larger of its entry's and its exit's (NaN for a tract
    // whose holes are gone).
    std::vector<double> tract_force(tract_states.size(), std::nan(""));
    for (std::size_t k = 0; k + 1 < pierce.size(); ++k)
      if (pierce[k].exit && !pierce[k + 1].exit)
        {
          const tearing::Tract tract{point3(pierce[k + 1].X), point3(pierce[k].X)};
          const auto           known = std::find_if(tract_states.begin(), tract_states.end(),
                                                    [&](const TractState &s) { return s.tract.entry == tract.entry; });
          const auto           z     = static_cast<std::size_t>(known - tract_states.begin());
          if (known == tract_states.end())
            {
              tract_states.emplace_back(tract, criteria.criteria.size());
              tract_force.push_back(std::nan(""));
            }
          if (k + 1 < forces.size())
            tract_force[z] = std::max(forces[k], forces[k + 1]);
        }

    std::vector<tearing::Tract> tracts;
    for (const auto &s : tract_states)
      tracts.push_back(s.tract);
    // Evaluated with no tract too: the VTU's cell ratios show where the tissue stands.
    tearing::ProcessZones::Separates cut;
    if (wound.present())
      cut = [this](const tearing::Point3 &a, const tearing::Point3 &b) {
        return wound.separates(Eigen::Vector3d(a[0], a[1], a[2]), Eigen::Vector3d(b[0], b[1], b[2]));
      };
    const tearing::ProcessZones zones(tracts, criteria.process_zone_radius, cut);
    const auto                  samples = model.evaluate_tearing(criteria, zones);
    for (std::size_t c = 0; c < criteria.criteria.size(); ++c)
      {
        const double critical = criteria.criteria[c].second->critical_value(criteria.process_zone_radius);
        for (std::size_t z = 0; z < tract_states.size(); ++z)
          {
            auto        &state  = tract_states[z];
            const auto  &sample = samples[c][z];
            const double ratio  = sample.mean() / critical;
            if (std::isnan(ratio)) // an empty zone (radius below the cells' size): nothing to record,
              {                    // and no crossing to interpolate across it
                state.last_ratio[c] = ratio;
                continue;
              }
            state.largest_ratio[c] = std::max(state.largest_ratio[c], ratio);
            if (ratio >= 1 && !state.onset[c])
              {
                // at the crossing of 1 within the last step; at this state when the last
                // one has no mean (the tract's first state)
                Onset onset{t, tension, tract_force[z], sample.mean(), sample.peak_location, sample.peak_direction};
                if (const double s = level_crossing(state.last_ratio[c], ratio, 1.0); s < 1)
                  {
                    onset.time    = at_fraction(last_time, t, s);
                    onset.tension = at_fraction(last_tension, tension, s);
                    if (std::isfinite(state.last_force))
                      onset.force = at_fraction(state.last_force, tract_force[z], s);
                  }
                state.onset[c] = onset;
              }
            state.last_ratio[c] = ratio;
          }
      }
    for (std::size_t z = 0; z < tract_states.size(); ++z)
      tract_states[z].last_force = tract_force[z];
    last_time    = t;
    last_tension = tension;
  }

  std::vector<double>
  TearMonitor::current_forces() const
  {
    std::vector<double> forces(criteria.criteria.size(), std::nan(""));
    for (std::size_t c = 0; c < forces.size(); ++c)
      {
        double largest = std::nan("");
        for (const auto &s : tract_states)
          if (!std::isnan(s.last_ratio[c]) && !(s.last_ratio[c] <= largest))
            {
              largest   = s.last_ratio[c];
              forces[c] = s.last_force;
            }
      }
    return forces;
  }

  std::vector<double>
  TearMonitor::current() const
  {
    std::vector<double> ratios(criteria.criteria.size(), std::nan(""));
    for (std::size_t c = 0; c < ratios.size(); ++c)
      for (const auto &s : tract_states)
        ratios[c] = std::fmax(ratios[c], s.last_ratio[c]); // NaN only where both are
    return ratios;
  }

  nlohmann::json
  TearMonitor::summary() const
  {
    nlohmann::json result         = nlohmann::json::object();
    result["process_zone_radius"] = criteria.process_zone_radius;
    if (std::isfinite(last_time))
      result["last_state"] = {{"time", last_time}, {"suture_tension", last_tension}};
    for (std::size_t c = 0; c < criteria.criteria.size(); ++c)
      {
        const auto &[name, criterion] = criteria.criteria[c];
        nlohmann::json per_tract      = nlohmann::json::array();
        const Onset   *first          = nullptr; // the stitch's onset: its earliest tract's
        double         largest        = 0;
        for (const auto &s : tract_states)
          {
            largest = std::max(largest, s.largest_ratio[c]);
            if (s.onset[c] && (!first || s.onset[c]->time < first->time))
              first = &*s.onset[c];
            nlohmann::json onset = nullptr;
            if (const auto &o = s.onset[c])
              onset = {{"time", o->time},
                       {"suture_tension", o->tension},
                       {"force", std::isnan(o->force) ? nlohmann::json() : nlohmann::json(o->force)},
                       {"mean", o->mean},
                       {"location", o->location},
                       {"direction", o->direction}};
            per_tract.push_back({{"entry", s.tract.entry},
                                 {"exit", s.tract.exit},
                                 {"largest_mean_over_critical", s.largest_ratio[c]},
                                 {"mean_over_critical", std::isnan(s.last_ratio[c]) ? nlohmann::json()
                                                                                    : nlohmann::json(s.last_ratio[c])},
                                 {"force", std::isnan(s.last_force) ? nlohmann::json() : nlohmann::json(s.last_force)},
                                 {"onset", onset}});
          }
        result["criteria"][name] = {{"unit", criterion->unit()},
                                    {"critical_value", criterion->critical_value(criteria.process_zone_radius)},
                                    {"tracts", per_tract}};
        if (!tract_states.empty())
          result["criteria"][name]["largest_mean_over_critical"] = largest;
        // absent without an onset, so that a study finds it missing rather than zero
        if (first)
          {
            result["criteria"][name]["onset_tension"] = first->tension;
            if (std::isfinite(first->force))
              result["criteria"][name]["onset_force"] = first->force;
            result["criteria"][name]["onset_time"]    = first->time;
          }
      }
    return result;
  }

  void
  TearMonitor::restore(const nlohmann::json &summary)
  {
    tract_states.clear();
    if (const auto last = summary.find("last_state"); last != summary.end())
      {
        last_time    = last->at("time").get<double>();
        last_tension = last->at("suture_tension").get<double>();
      }
    for (std::size_t c = 0; c < criteria.criteria.size(); ++c)
      {
        const auto &per_tract = summary.at("criteria").at(criteria.criteria[c].first).at("tracts");
        for (std::size_t z = 0; z < per_tract.size(); ++z)
          {
            const auto &j = per_tract[z];
            if (z == tract_states.size())
              tract_states.emplace_back(
                tearing::Tract{j.at("entry").get<tearing::Point3>(), j.at("exit").get<tearing::Point3>()},
                criteria.criteria.size());
            tract_states[z].largest_ratio[c] = j.at("largest_mean_over_critical").get<double>();
            if (const auto &r = j.value("mean_over_critical", nlohmann::json()); r.is_number())
              tract_states[z].last_ratio[c] = r.get<double>();
            // a force is null where a hole was gone (NaN)
            const auto force = [](const nlohmann::json &f) { return f.is_number() ? f.get<double>() : std::nan(""); };
            tract_states[z].last_force = force(j.at("force"));
            if (const auto &o = j.at("onset"); !o.is_null())
              tract_states[z].onset[c]
                  = Onset{o.at("time").get<double>(),          o.at("suture_tension").get<double>(),
                          force(o.at("force")),                o.at("mean").get<double>(),
                          o.at("location").get<tearing::Point3>(), o.at("direction").get<tearing::Point3>()};
          }
      }
  }
} // namespace suturesim::scene
