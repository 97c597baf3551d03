#include <suturesim/knot/planner.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

namespace suturesim::knot
{
  namespace
  {
    /// @p rope read from its last node when the first end moves: the moving end last.
    Eigen::Matrix3Xd
    read_from_held_end(const Eigen::Matrix3Xd &rope, const bool first_moves)
    {
      return first_moves ? Eigen::Matrix3Xd(rope.rowwise().reverse()) : rope;
    }
  } // namespace

  std::vector<Instruction>
  instructions(const std::string &name)
  {
    if (name == "overhand")
      return {{false, 0}, {true, 1}, {false, 2}};
    if (name == "figure-eight")
      return {{true, 0, 0.3}, {false, 0, 0.7}, {true, 2, 0.5}, {false, 2, 0.5}};
    // the overhand's end taken round once more (over 3, under 4); its first target at
    // 0.3 of the span for a larger loop, as the figure-eight's (docs/knots.md)
    if (name == "cinquefoil")
      return {{false, 0, 0.3}, {true, 1}, {false, 2}, {true, 3}, {false, 4}};
    // in a rope laid as a U: the last end's half knot round the first end's strand, its
    // first target on that strand (0.2 of the rope), the second just past the first
    // crossing, the third on the end's own standing part below it. The half knot is then
    // drawn down, its end 15 mm out: a tail for the first end's half knot to go round,
    // over the middle of that tail, under it between there and the knot, and over its
    // own standing part (the span before its first crossing, 8: the 2 × 5 occurrences
    // read from the held end). Without the draw the tail is shorter than a link and the
    // fifth crossing misses it (docs/knots.md)
    const bool   first = true;
    const double draw  = 15e-3;
    if (name == "square")
      return {{true, 0, 0.2}, {false, 1, 0.2}, {true, 2, 0.8, false, draw},
              {true, 0, 0.5, first}, {false, 1, 0.5, first}, {true, 8, 0.8, first}};
    if (name == "granny")
      return {{true, 0, 0.2}, {false, 1, 0.2}, {true, 2, 0.8, false, draw},
              {false, 0, 0.5, first}, {true, 1, 0.5, first}, {false, 8, 0.8, first}};
    // the surgeon's knot: the square knot with its first half knot doubled, the last end
    // taken round the first end's strand twice (five crossings, read closed the (2, 5)
    // torus knot, as the cinquefoil) before it is drawn; then the first end's half knot
    // as in the square knot, over its own standing part (span 12: 2 × 7 occurrences,
    // less its own two). The targets of the third and fourth crossings (0.4, 0.3) are
    // from a sweep of custom plans (docs/knots.md)
    if (name == "surgeon")
      return {{true, 0, 0.2},         {false, 1, 0.2},         {true, 2, 0.4},
              {false, 3, 0.3},        {true, 4, 0.5, false, draw}, {true, 0, 0.5, first},
              {false, 1, 0.5, first}, {true, 12, 0.8, first}};
    std::string known;
    for (const auto &k : planned_knots())
      known += (known.empty() ? "" : ", ") + k;
    throw std::invalid_argument("no knot planner instructions for '" + name + "' (" + known + ")");
  }

  const std::vector<std::string> &
  planned_knots()
  {
    static const std::vector<std::string> names{"overhand", "figure-eight", "cinquefoil", "square", "granny",
                                                 "surgeon"};
    return names;
  }

  std::vector<Instruction>
  plan_of(const PlannerSettings &settings)
  {
    return settings.knot == "custom" ? settings.instructions : instructions(settings.knot);
  }

  std::vector<Instruction>
  parse_plan(const std::string &text)
  {
    constexpr std::size_t    most = 32;
    std::vector<Instruction> plan;
    std::istringstream       all(text);
    std::string              item;
    while (std::getline(all, item, ';'))
      {
        std::istringstream words(item);
        std::string        word;
        if (!(words >> word))
          continue; // an empty item: "a; b;" ends with one
        const std::string where = "instruction " + std::to_string(plan.size() + 1) + " ('" + item + "'): ";
        if (plan.size() == most)
          throw std::invalid_argument("more than " + std::to_string(most) + " instructions");
        Instruction i;
        if (word == "first" || word == "last")
          {
            i.first_end = word == "first";
            if (!(words >> word))
              word.clear();
          }
        if (word != "over" && word != "under")
          throw std::invalid_argument(where + "expected 'over' or 'under', not '" + word + "'");
        i.over = word == "over";
        // the span as a whole number (a stream would read "-1" into a huge size_t)
        if (!(words >> word) || word.find_first_not_of("0123456789") != std::string::npos || word.size() > 3)
          throw std::invalid_argument(where + "the span must be a whole number 0-999, not '" + word + "'");
        i.span = std::stoul(word);
        while (words >> word)
          {
            double value = 0;
            if ((word != "at" && word != "draw") || !(words >> value) || !std::isfinite(value))
              throw std::invalid_argument(where + "expected 'at <fraction>' or 'draw <metres>' after the span");
            if (word == "at" && (value < 0 || value > 1))
              throw std::invalid_argument(where + "'at' must be within [0, 1] (a fraction of the span)");
            if (word == "draw" && (value < 0 || value > 1))
              throw std::invalid_argument(where + "'draw' must be within [0, 1] m");
            (word == "at" ? i.at : i.draw) = value;
          }
        plan.push_back(i);
        try
          {
            tied_code(plan);
          }
        catch (const std::invalid_argument &)
          {
            throw std::invalid_argument(where + "span " + std::to_string(i.span) +
                                        " is past the rope's spans then (0 to " +
                                        std::to_string(2 * (plan.size() - 1)) + ")");
          }
      }
    if (plan.empty())
      throw std::invalid_argument("no instruction (e.g. 'under 0; over 1; under 2', the overhand)");
    const GaussCode code = tied_code(plan);
    if (const std::size_t kept = code.reduced().crossings(); kept < plan.size())
      throw std::invalid_argument("the plan ties '" + code.text() + "', which Reidemeister moves reduce to " +
                                  std::to_string(kept) + " of its " + std::to_string(plan.size()) +
                                  " crossings: every instruction must add a crossing the knot keeps");
    return plan;
  }

  std::string
  plan_text(const std::vector<Instruction> &plan)
  {
    std::ostringstream out;
    // 15 digits: what a scene gives reads back as given, and 0.2 is still written "0.2"
    out << std::setprecision(15);
    for (std::size_t k = 0; k < plan.size(); ++k)
      out << (k ? "; " : "") << (plan[k].first_end ? "first " : "last ") << (plan[k].over ? "over " : "under ")
          << plan[k].span << " at " << plan[k].at << " draw " << plan[k].draw;
    return out.str();
  }

  bool
  moves_first_end(const std::vector<Instruction> &plan)
  {
    return std::any_of(plan.begin(), plan.end(), [](const Instruction &i) { return i.first_end; });
  }

  GaussCode
  tied_code(const std::vector<Instruction> &plan)
  {
    std::vector<GaussEntry> entries; // read from the first end
    unsigned                label = 0;
    for (const auto &step : plan)
      {
        // span m lies between occurrences m − 1 and m read from the held end; the moving
        // end's own occurrence is the last so far read from there
        if (step.span > entries.size())
          throw std::invalid_argument("a knot instruction's span is past the rope's spans");
        ++label;
        if (step.first_end)
          std::reverse(entries.begin(), entries.end());
        entries.insert(entries.begin() + static_cast<long>(step.span), GaussEntry{label, !step.over});
        entries.push_back({label, step.over});
        if (step.first_end)
          std::reverse(entries.begin(), entries.end());
      }
    return GaussCode(std::move(entries));
  }

  std::string
  KnotPlanner::name(const Phase phase)
  {
    switch (phase)
      {
        case Phase::waiting:
          return "waiting";
        case Phase::tying:
          return "tying";
        case Phase::tightening:
          return "tightening";
        case Phase::done:
          return "done";
        case Phase::failed:
          return "failed";
      }
    return "";
  }

  KnotPlanner::KnotPlanner(const PlannerSettings &settings)
    : settings_(settings)
    , projection_(settings.normal)
    , plan_(plan_of(settings))
  {
    if (plan_.empty())
      throw std::invalid_argument("the knot planner needs at least one instruction");
    if (!(settings.speed > 0) || !(settings.clearance > 0) || !(settings.inertia >= 0) ||
        !(settings.instruction_time > 0))
      throw std::invalid_argument("the knot planner needs a speed, clearance and instruction time > 0");
  }

  void
  KnotPlanner::set_normal(const Eigen::Vector3d &normal)
  {
    // the diagram's spans and crossings are read in one plane from the start on
    if (phase_ != Phase::waiting)
      throw std::logic_error("the knot planner's projection plane is set before it starts");
    projection_      = Projection(normal);
    settings_.normal = projection_.n;
  }

  void
  KnotPlanner::fail(const std::string &why, const double t)
  {
    phase_   = Phase::failed;
    failure_ = why;
    failed_at = t;
  }

  void
  KnotPlanner::check(const KnotDiagram &d, const double t)
  {
    const std::size_t n = d.crossings().size();
    if (n == stage)
      {
        if (t - stage_start > settings_.instruction_time)
          fail("instruction " + std::to_string(stage + 1) + " was not done within " +
               std::to_string(settings_.instruction_time) + " s (Knot/Instruction time)",
             t);
        return;
      }
    std::ostringstream why;
    why << "instruction " << stage + 1 << " (" << (plan_[stage].over ? "over" : "under") << " span "
        << plan_[stage].span << "): ";
    if (n != stage + 1)
      return fail(why.str() + "the diagram went from " + std::to_string(stage) + " to " + std::to_string(n) +
                  " crossings (" + d.gauss_code().text() + ")",
                  t);
    // the new crossing is the moving end's: its occurrence nearest the end
    const auto  &c        = *std::max_element(d.crossings().begin(), d.crossings().end(),
                                              [](const Crossing &l, const Crossing &r) { return l.b < r.b; });
    const bool   end_over = !c.a_over;
    const double lo = bounds[plan_[stage].span], hi = bounds[plan_[stage].span + 1];
    if (end_over != plan_[stage].over)
      return fail(why.str() + "the end crossed " + (end_over ? "over" : "under"), t);
    if (c.a < lo || c.a > hi)
      {
        why << "the end crossed the strand at arc index " << c.a << ", outside the target span [" << lo << ", "
            << hi << "]";
        return fail(why.str(), t);
      }
    ++stage;
    stage_start = t;
    events_.push_back({t, stage, d.gauss_code().text()});
    if (stage == plan_.size())
      phase_ = Phase::tightening;
    else
      drawing = plan_[stage - 1].draw;
  }

  Eigen::Vector3d
  KnotPlanner::tying_direction(const KnotDiagram &d, const Eigen::Matrix3Xd &rope) const
  {
    const Instruction &step = plan_[stage];
    const auto        &b    = d.span_bounds();
    const double       mid  = b[step.span] + step.at * (b[step.span + 1] - b[step.span]);
    const auto         in_plane = [&](const Eigen::Vector3d &w) -> Eigen::Vector3d {
      return w - projection_.n * projection_.n.dot(w);
    };
    const auto unit = [](const Eigen::Vector3d &w) -> Eigen::Vector3d {
      return w.norm() > 0 ? Eigen::Vector3d(w.normalized()) : Eigen::Vector3d::Zero();
    };
    const Eigen::Vector3d end     = moving_first_end() ? ends.first : ends.last;
    const Eigen::Vector3d T       = d.point(mid);
    const Eigen::Vector3d tangent = unit(in_plane(d.point(mid + 0.5) - d.point(mid - 0.5)));
    const Eigen::Vector3d across  = projection_.n.cross(tangent); // in the plane, normal to the span
    const Eigen::Vector3d w       = in_plane(end - T);
    // the point aimed at: beside the span on the end's side until the end is within the
    // clearance of the perpendicular through T and at its height (within half the
    // clearance), then as far on the other side, so that the end crosses at right angles
    // and over (or under) rather than along the span or through it
    const double          goal  = projection_.height(T) + (step.over ? 1 : -1) * settings_.clearance;
    const bool            ready = std::abs(w.dot(tangent)) <= settings_.clearance &&
                                  std::abs(projection_.height(end) - goal) < 0.5 * settings_.clearance;
    const double          side  = w.dot(across) >= 0 ? 1 : -1;
    const Eigen::Vector3d aim   = T + (ready ? -side : side) * settings_.clearance * across;
    const Eigen::Vector3d to_target = unit(in_plane(aim - end));          // (1)
    const Eigen::Vector3d to_normal = unit(-w.dot(tangent) * tangent);    // (2)
    const Eigen::Vector3d rise =
      projection_.n * std::clamp((goal - projection_.height(end)) / settings_.clearance, -1.0, 1.0); // (3)
    const Eigen::Index    last  = rope.cols() - 1;
    const Eigen::Vector3d along = unit(rope.col(last) - rope.col(last - 1)); // (4)
    const double W = moving_first_end() && settings_.first_end_inertia >= 0 ? settings_.first_end_inertia
                                                                              : settings_.inertia;
    return unit(to_target + to_normal + rise + W * along);
  }

  bool
  KnotPlanner::moving_first_end() const
  {
    // drawn after its crossing, or pulled once tied: the last instruction's end
    const bool last_done = drawing > 0 || stage == plan_.size();
    return plan_[last_done ? stage - 1 : std::min(stage, plan_.size() - 1)].first_end;
  }

  Ends
  KnotPlanner::move(const Eigen::Matrix3Xd &rope, const double t, const double dt, const double end_force)
  {
    if (rope.cols() < 3)
      throw std::invalid_argument("the knot planner needs a rope of at least three nodes");
    const Eigen::Index last = rope.cols() - 1;
    if (phase_ == Phase::waiting)
      {
        ends = {rope.col(0), rope.col(last)};
        if (t < settings_.start_time)
          return ends;
        phase_      = Phase::tying;
        stage_start = t;
        links[0]    = (rope.col(1) - rope.col(0)).norm();
        links[1]    = (rope.col(last) - rope.col(last - 1)).norm();
      }
    // a finished or failed plan holds the ends: no diagram to read any more
    if (phase_ == Phase::done || phase_ == Phase::failed)
      return ends;
    const bool first = moving_first_end();
    // the rope read from the held end, its last column the moving end: copied backwards
    // only when the first end moves
    const Eigen::Matrix3Xd  reversed = first ? read_from_held_end(rope, true) : Eigen::Matrix3Xd();
    const Eigen::Matrix3Xd &held     = first ? reversed : rope;
    const KnotDiagram       d(held, projection_);
    // a rope held behind its end (a node in a collision constraint every step) lets its
    // end link stretch rather than follow: what the end then crosses is not the rope
    const double stretch = (held.col(last) - held.col(last - 1)).norm() / links[first ? 0 : 1] - 1;
    if (stretch > 0.1)
      fail("the end's link is stretched by " + std::to_string(100 * stretch) +
             " % (over 10 %): the rope behind the end does not follow it (held by collision constraints, or "
             "dragged)",
           t);
    if (phase_ == Phase::tying && drawing > 0)
      draw(d, held, t, dt);
    else if (phase_ == Phase::tying)
      {
        if (!bounds.empty())
          check(d, t);
        // an instruction for the other end reads the rope from its other end, and a draw
        // starts: from the next step
        if (phase_ == Phase::tying && drawing == 0 && moving_first_end() == first)
          moving() += settings_.speed * dt * tying_direction(d, held);
      }
    // a knot pulled tight in a rope that cannot hold it (a geometric suture has no
    // contact force, only corrections after each step) has its strands pass through each
    // other. Its diagram may also change while the knot turns in the plane's view (the
    // knot seen from its other side, or a Reidemeister III move, neither of which
    // reduced() undoes), so only what no diagram of the knot can read is taken as
    // undone: fewer crossings, after the reductions, than the knot's crossing number
    // (Reidemeister moves keep the knot, and no diagram of it has fewer). The plans of
    // instructions() are minimal, one crossing each: 3 for the trefoil, 4 for the
    // figure-eight, 6 for the square and granny knots, 8 for the surgeon's (KnotPlanner.PlansTie…)
    if (phase_ == Phase::tightening)
      if (const GaussCode now = d.gauss_code().reduced(); now.crossings() < plan_.size())
        {
          std::ostringstream why;
          why << "the knot came undone while tightening, after " << 1e3 * pulled << " mm: its diagram reads '"
              << now.text() << "', fewer crossings than the knot's " << plan_.size();
          fail(why.str(), t);
        }
    if (phase_ == Phase::tightening)
      tighten(d, held, dt, end_force);
    bounds = moving_first_end() == first ? d.span_bounds()
                                         : KnotDiagram(read_from_held_end(rope, !first), projection_).span_bounds();
    return ends;
  }

  Eigen::Vector3d
  KnotPlanner::away_from_knot(const KnotDiagram &d, const Eigen::Matrix3Xd &rope) const
  {
    const Eigen::Index last   = rope.cols() - 1;
    Eigen::Vector3d    centre = Eigen::Vector3d::Zero();
    for (const auto &c : d.crossings())
      centre += 0.5 * (d.point(c.a) + d.point(c.b)) / static_cast<double>(d.crossings().size());
    // away from the knot in the plane; along the end's link if the end is over it
    Eigen::Vector3d w = (moving_first_end() ? ends.first : ends.last) - centre;
    if ((w - projection_.n * projection_.n.dot(w)).norm() == 0)
      w = rope.col(last) - rope.col(last - 1);
    return (w - projection_.n * projection_.n.dot(w)).normalized();
  }

  void
  KnotPlanner::draw(const KnotDiagram &d, const Eigen::Matrix3Xd &rope, const double t, const double dt)
  {
    if (d.crossings().size() != stage)
      return fail("while the end was drawn from the knot after instruction " + std::to_string(stage) +
                    ", the diagram went from " + std::to_string(stage) + " to " +
                    std::to_string(d.crossings().size()) + " crossings (" + d.gauss_code().text() + ")",
                  t);
    if (pull.isZero())
      pull = away_from_knot(d, rope);
    const double step = std::min(drawing, settings_.speed * dt);
    moving() += step * pull;
    drawing -= step;
    if (drawing <= 0)
      {
        drawing = 0;
        pull.setZero();
        stage_start = t; // the next instruction's time starts now
      }
  }

  void
  KnotPlanner::tighten(const KnotDiagram &d, const Eigen::Matrix3Xd &rope, const double dt, const double end_force)
  {
    Eigen::Vector3d &end = moving();
    if (pull.isZero())
      pull = away_from_knot(d, rope);
    const bool far    = pulled >= settings_.tighten_distance;
    const bool strong = settings_.tighten_force > 0 && end_force >= settings_.tighten_force;
    if (far || strong)
      phase_ = Phase::done;
    else
      {
        end += settings_.speed * dt * pull;
        pulled += settings_.speed * dt;
      }
  }

  nlohmann::json
  diagram_metrics(const Eigen::Matrix3Xd &rope, const Projection &projection)
  {
    const KnotDiagram diagram(rope, projection);
    const GaussCode   raw = diagram.gauss_code(), code = raw.reduced();
    const auto       &n   = projection.n;
    nlohmann::json    m   = {{"crossings", code.crossings()},
                             {"gauss_code", code.text()},
                             {"raw_crossings", raw.crossings()},
                             {"raw_gauss_code", raw.text()},
                             {"determinant", raw.determinant()},
                             {"writhe", code.writhe()},
                             {"projection_normal", {n[0], n[1], n[2]}}};
    // where the raw code's crossings lie (on their first strand, m), in the order of their
    // labels: their first occurrences along the rope
    std::vector<Crossing> crossings(diagram.crossings());
    std::sort(crossings.begin(), crossings.end(), [](const Crossing &l, const Crossing &r) { return l.a < r.a; });
    m["crossing_points"] = nlohmann::json::array();
    for (const auto &c : crossings)
      {
        const Eigen::Vector3d p = diagram.point(c.a);
        m["crossing_points"].push_back({p[0], p[1], p[2]});
      }
    return m;
  }

  nlohmann::json
  knot_metrics(const KnotPlanner &planner, const Eigen::Matrix3Xd &rope)
  {
    nlohmann::json  m       = diagram_metrics(rope, planner.projection());
    const GaussCode planned = tied_code(planner.plan());
    m["knot"]               = planner.settings().knot;
    m["phase"]              = KnotPlanner::name(planner.phase());
    m["instructions"]       = planner.plan().size();
    m["instructions_done"]  = planner.instructions_done();
    m["moves_first_end"]    = planner.moves_first_end();
    m["plan"]               = plan_text(planner.plan());
    m["planned_gauss_code"] = planned.text();
    m["tied"]               = m["gauss_code"] == planned.text();
    m["shortening"]         = planner.shortening();
    if (!planner.failure().empty())
      {
        m["failure"]      = planner.failure();
        m["failure_time"] = planner.failure_time();
      }
    return m;
  }

  nlohmann::json
  knot_events(const KnotPlanner &planner)
  {
    nlohmann::json list = nlohmann::json::array();
    for (const auto &e : planner.events())
      list.push_back({{"kind", "knot_crossing"}, {"time", e.time}, {"instruction", e.instruction}, {"gauss_code", e.code}});
    return list;
  }
} // namespace suturesim::knot
