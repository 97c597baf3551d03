#include <suturesim/core/error.h>
#include <suturesim/core/model_parameters.h>
#include <suturesim/scene/interrupted_series.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace suturesim::scene
{
  namespace
  {
    /// A time or force of the record: null where it is not finite (not reached yet).
    nlohmann::json
    finite_or_null(const double v)
    {
      return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
    }

    /// finite_or_null() back, @p absent for null.
    double
    number_or(const nlohmann::json &j, const double absent)
    {
      return j.is_null() ? absent : j.get<double>();
    }
  } // namespace

  InterruptedSeries::InterruptedSeries(const NeedleParameters &needle, std::vector<double> s, const double L)
    : arc(std::move(s))
    , tail_length(needle.tail_length)
    , needle_length(L)
    , lay_duration(needle.tail_lay_duration)
    , draw(needle.tail_draw)
  {
    for (const auto &pass : needle.planned_series().passes)
      stitches.push_back({pass.t_end, 0, 0, 0, {}, pass.exit + needle.tail_lay, Eigen::Vector3d::Zero(),
                          pass.t_tightened, std::numeric_limits<double>::quiet_NaN()});
    stops.assign(stitches.size(), std::numeric_limits<double>::infinity());
  }

  std::vector<ClosureMonitor::StitchWindow>
  InterruptedSeries::windows(const tools::SurgicalSeries &planned)
  {
    std::vector<ClosureMonitor::StitchWindow> w;
    for (const auto &pass : planned.passes)
      w.push_back({pass.t_turn_end, pass.t_end, pass.t_tightened});
    return w;
  }

  std::size_t
  InterruptedSeries::node_at_or_beyond(const double s) const
  {
    const auto i = static_cast<std::size_t>(std::lower_bound(arc.begin(), arc.end(), s) - arc.begin());
    return std::min(i, arc.size() - 1);
  }

  std::size_t
  InterruptedSeries::node_at_or_before(const double s) const
  {
    const auto i = static_cast<std::size_t>(std::upper_bound(arc.begin(), arc.end(), s) - arc.begin());
    return i == 0 ? 0 : i - 1;
  }

  InterruptedSeries::Actions
  InterruptedSeries::advance(const double t, const std::vector<Hole> &holes, ClosureMonitor &closure,
                             const ParameterScope &pass, const std::function<Eigen::Vector3d(std::size_t)> &node)
  {
    Actions act;
    // the stitch under way: the first not tied off
    std::size_t k = 0;
    while (k < stitches.size() && stitches[k].points > 0)
      ++k;
    if (k == stitches.size())
      return act;
    act.stitch               = k;
    auto             &stitch = stitches[k];
    const std::size_t before = k == 0 ? 0 : stitches[k - 1].points; // earlier stitches' holes
    const std::size_t mine   = holes.size() > before ? holes.size() - before : 0;
    // the tail: the suture's last end, or the cut end the stitch before left
    const std::size_t end = k == 0 ? arc.size() - 1 : stitches[k - 1].cut - 1;
    if (!std::isfinite(stops[k]) && mine > 0 && holes[mine - 1].on_suture)
      {
        const double tail = arc[end] - (holes[mine - 1].zeta - needle_length);
        if (tail <= tail_length || t >= stitch.pull_end)
          {
            act.tail     = end;
            stitch.tail  = end;
            stitch.taken = node(end);
            stops[k]     = t;
            closure.start_stitch(k, t); // drawn tight from now on: it may be tied off
          }
      }
    const double tied = closure.stitch_ties().at(k);
    if (!std::isfinite(tied))
      return act;
    const auto fail = [&](const std::string &why) {
      pass.fail("Pull", "stitch " + std::to_string(k + 1) + " tied off at " + default_text(tied) + " s: " + why);
    };
    if (mine == 0 || !std::isfinite(stops[k]))
      fail("its tail is not held: its pass made no hole on the suture");
    // its holes: the pierce points its pass added, nearest the needle
    const double s_exit  = holes.front().zeta - needle_length;
    const double s_entry = holes[mine - 1].zeta - needle_length;
    // each strand held one stitch width (entry to exit) beyond its hole
    const double      reach = (holes[mine - 1].position - holes.front().position).norm();
    const std::size_t tail  = std::min(node_at_or_beyond(s_entry + reach), end);
    const std::size_t lead  = s_exit - reach < 0 ? 0 : node_at_or_before(s_exit - reach);
    if (lead < 3 || s_exit < 0)
      fail("its exit hole is at the needle's swage: too little thread is drawn through to tie it there");
    // (a tail shorter than the reach: its hand, holding the end, is the tail strand's hold)
    act.tie = tail < end ? std::vector<std::size_t>{lead, tail} : std::vector<std::size_t>{lead};
    act.cut = lead - 1; // the thread cut next to the needle strand's hold
    stitch.tie    = act.tie;
    stitch.points = holes.size();
    stitch.cut    = lead;
    return act;
  }

  Eigen::Vector3d
  InterruptedSeries::tail_displacement(const std::size_t k, const double t, const std::vector<double> &ties) const
  {
    const double taken = stops.at(k);
    if (!std::isfinite(taken) || lay_duration <= 0)
      return Eigen::Vector3d::Zero();
    const auto  &s   = stitches[k];
    const double now = std::min(t, ties.at(k));
    const double f   = std::clamp((now - taken) / lay_duration, 0.0, 1.0);
    // laid, then drawn on until the tightening's planned end
    const double laid = taken + lay_duration;
    const double g    = s.tightened > laid ? std::clamp((now - laid) / (s.tightened - laid), 0.0, 1.0) : 0.0;
    return f * (s.lay - s.taken) + g * draw;
  }

  std::vector<std::size_t>
  InterruptedSeries::held_nodes() const
  {
    std::vector<std::size_t> held;
    for (std::size_t k = 0; k < stitches.size(); ++k)
      {
        if (std::isfinite(stops[k]))
          held.push_back(stitches[k].tail);
        held.insert(held.end(), stitches[k].tie.begin(), stitches[k].tie.end());
      }
    return held;
  }

  std::vector<std::size_t>
  InterruptedSeries::cut_elements() const
  {
    std::vector<std::size_t> cuts;
    for (const auto &s : stitches)
      if (s.points > 0)
        cuts.push_back(s.cut - 1);
    return cuts;
  }

  void
  InterruptedSeries::write(nlohmann::json &metrics) const
  {
    auto &list = metrics["interrupted_series"] = nlohmann::json::array();
    for (std::size_t k = 0; k < stitches.size(); ++k)
      {
        const auto  &s    = stitches[k];
        const double stop = stops[k];
        const bool   held = std::isfinite(stop);
        list.push_back({{"stitch", k + 1},
                        {"tail_taken_at", finite_or_null(stop)},
                        {"pull_stopped", held && stop < s.pull_end},
                        {"cut_node", s.points > 0 ? nlohmann::json(s.cut - 1) : nlohmann::json(nullptr)},
                        {"tail_force_at_tie_off", finite_or_null(s.tail_force)}});
      }
  }

  nlohmann::json
  InterruptedSeries::snapshot() const
  {
    auto list = nlohmann::json::array();
    for (std::size_t k = 0; k < stitches.size(); ++k)
      {
        const auto &s = stitches[k];
        list.push_back({{"stop", finite_or_null(stops[k])},
                        {"points", s.points},
                        {"cut", s.cut},
                        {"tail", s.tail},
                        {"tie", s.tie},
                        {"taken", {s.taken[0], s.taken[1], s.taken[2]}},
                        {"tail_force", finite_or_null(s.tail_force)}});
      }
    return list;
  }

  void
  InterruptedSeries::restore(const nlohmann::json &j)
  {
    if (!j.is_array() || j.size() != stitches.size())
      throw std::invalid_argument("the checkpoint's interrupted series has another number of stitches");
    for (std::size_t k = 0; k < stitches.size(); ++k)
      {
        auto       &s = stitches[k];
        const auto &r = j.at(k);
        stops[k]      = number_or(r.at("stop"), std::numeric_limits<double>::infinity());
        s.points      = r.at("points").get<std::size_t>();
        s.cut         = r.at("cut").get<std::size_t>();
        s.tail        = r.at("tail").get<std::size_t>();
        s.tie         = r.at("tie").get<std::vector<std::size_t>>();
        const auto x  = r.at("taken").get<std::vector<double>>();
        if (x.size() != 3)
          throw std::invalid_argument("the checkpoint's interrupted series has a tail position that is not a point");
        s.taken = Eigen::Vector3d(x[0], x[1], x[2]);
        s.tail_force  = number_or(r.at("tail_force"), std::numeric_limits<double>::quiet_NaN());
        for (const std::size_t node : s.tie)
          if (node >= arc.size())
            throw std::invalid_argument("the checkpoint's interrupted series holds a node the suture does not have");
        if (s.tail >= arc.size() || (s.points > 0 && (s.cut == 0 || s.cut >= arc.size())))
          throw std::invalid_argument("the checkpoint's interrupted series names a node the suture does not have");
      }
  }
} // namespace suturesim::scene
