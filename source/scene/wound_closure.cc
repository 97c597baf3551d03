#include <suturesim/core/level_crossing.h>
#include <suturesim/core/model_parameters.h>
#include <suturesim/scene/wound_closure.h>

#include <deal.II/base/utilities.h>

#include <algorithm>

namespace suturesim::scene
{
  using namespace dealii;

  void
  ClosureParameters::declare(ParameterHandler &prm)
  {
    const ClosureParameters d;
    prm.enter_subsection("Closure");
    prm.declare_entry("Gap probes", "",
                      Patterns::Map(Patterns::Anything(), Patterns::List(Patterns::Double(), 6, 6, ","), 0,
                                    Patterns::Map::max_int_value, ";", ":"),
                      "Pairs of tissue points across the wound, 'name: xa, ya, za, xb, yb, zb; "
                      "...' (reference positions); the gap of a pair is its opening along the "
                      "line from a to b (negative: overlap). The first pair decides closure. "
                      "Empty: no closure measurement. Unit: m.");
    prm.declare_entry("Closure gap", default_text(d.closure_gap), Patterns::Double(0),
                      "The wound counts as closed when the first pair's gap falls below this. "
                      "Unit: m. Range: > 0.");
    prm.declare_entry("Start time", default_text(d.start_time), Patterns::Double(0),
                      "Closure is looked for from this time on (when the suture is drawn "
                      "tight), not while the needle crossing the wound moves its edges. "
                      "Unit: s. Range: >= 0.");
    prm.declare_entry("Tie off", default_text(d.tie_off), Patterns::Bool(),
                      "Once the deciding gap (Tie off when) falls below 'Tie-off gap', every prescribed "
                      "motion (needle, graspers) stops: the suture's ends are held where they "
                      "are. Unit: none.");
    prm.declare_entry("Tie off when", "first pair", Patterns::Selection("first pair|every pair"),
                      "Which gaps decide the tie-off: the first pair's (a single stitch), or "
                      "every pair's at once (a series with a gap pair per stitch: the ends are "
                      "held when the last of them falls below 'Tie-off gap').");
    prm.declare_entry("Tie-off gap", "0", Patterns::Double(0),
                      "The first pair's gap below which the ends are tied off (a surgeon "
                      "draws the throw a little past the edges' meeting); 0: at closure, "
                      "'Closure gap'. Unit: m. Range: 0 to 'Closure gap'.");
    prm.declare_entry("Face contact", "", Patterns::List(Patterns::Anything(), 0, 2, ","),
                      "The incision's two faces as 'A, B' (boundary names or ids of the mesh), "
                      "kept from passing through each other by a penalty between A's vertices "
                      "and B's surface: in the accurate path, and in the realtime path with "
                      "Realtime/Face contact stiffness > 0. Empty: no contact between them. "
                      "Unit: none.");
    prm.declare_entry("Face contact stiffness", default_text(d.face_contact_stiffness), Patterns::Double(0),
                      "Penalty of the face contact per vertex pair, accurate path (the realtime "
                      "path's: Realtime/Face contact stiffness). Unit: N/m. Range: > 0.");
    prm.declare_entry("Face contact margin", default_text(d.face_contact_margin), Patterns::Double(0),
                      "A vertex pair is loaded (costs the coupled Newton iteration three "
                      "linear solves) while its gap is below this. Unit: m. Range: >= 0.");
    prm.leave_subsection();
  }

  void
  ClosureParameters::parse(ParameterHandler &prm, const ParameterScope &root)
  {
    prm.enter_subsection("Closure");
    const ParameterScope scope = root.subsection("Closure");
    pairs.clear();
    for (const auto &[name, v] : get_named_values(prm, "Gap probes"))
      {
        Pair pair;
        pair.name = name;
        pair.a    = {v[0], v[1], v[2]};
        pair.b       = {v[3], v[4], v[5]};
        scope.require((pair.b - pair.a).norm() > 0, "Gap probes", "pair '" + pair.name + "' has a = b");
        scope.require(std::none_of(pairs.begin(), pairs.end(), [&](const Pair &p) { return p.name == pair.name; }),
                      "Gap probes", "the name '" + pair.name + "' appears twice");
        pairs.push_back(pair);
      }
    closure_gap = prm.get_double("Closure gap");
    start_time  = prm.get_double("Start time");
    tie_off     = prm.get_bool("Tie off");
    tie_off_every_pair = prm.get("Tie off when") == "every pair";
    scope.require(closure_gap > 0, "Closure gap", "must be > 0 m");
    tie_off_gap = prm.get_double("Tie-off gap");
    scope.require(tie_off_gap <= closure_gap, "Tie-off gap",
                  "must not exceed 'Closure gap' (" + Utilities::to_string(closure_gap) + " m)");
    if (tie_off_gap == 0)
      tie_off_gap = closure_gap;
    face_contact = Utilities::split_string_list(prm.get("Face contact"), ',');
    scope.require(face_contact.empty() || face_contact.size() == 2, "Face contact", "needs two faces, 'A, B'");
    // the faces are read with the closure only: without gap probes they would be ignored
    scope.require(face_contact.empty() || !pairs.empty(), "Face contact",
                  "acts with the wound closure only: set Closure/Gap probes too");
    face_contact_stiffness = prm.get_double("Face contact stiffness");
    face_contact_margin    = prm.get_double("Face contact margin");
    scope.require(face_contact_stiffness > 0, "Face contact stiffness", "must be > 0 N/m");
    this->scope = std::make_shared<ParameterScope>(scope);
    prm.leave_subsection();
  }

  std::pair<types::boundary_id, types::boundary_id>
  ClosureParameters::face_contact_ids(const mesh::MeshInfo &mesh) const
  {
    return {mesh.boundary_id(face_contact[0], *scope, "Face contact"),
            mesh.boundary_id(face_contact[1], *scope, "Face contact")};
  }

  ClosureMonitor::ClosureMonitor(const ClosureParameters &parameters)
    : prm(parameters)
  {}

  double
  ClosureMonitor::gap(const std::size_t k, const Eigen::Vector3d &xa, const Eigen::Vector3d &xb) const
  {
    const auto &p = prm.pairs[k];
    return (xb - xa).dot((p.b - p.a).normalized());
  }

  void
  ClosureMonitor::update(const double t, const std::vector<double> &gaps, const double tension)
  {
    if (initial.empty())
      {
        initial = gaps;
        least   = gaps;
        closed_at.assign(gaps.size(), std::numeric_limits<double>::infinity());
        closed_tension.assign(gaps.size(), 0);
      }
    last = gaps;
    for (std::size_t k = 0; k < gaps.size(); ++k)
      least[k] = std::min(least[k], gaps[k]);
    if (t < prm.start_time || gaps.empty())
      return;
    for (std::size_t k = 0; k < gaps.size(); ++k)
      // an interrupted series' stitch closes as its own thread is drawn, not as the needle
      // crosses the wound or the stitches before pull its edges, nor after its tie-off
      if (closed_at[k] == std::numeric_limits<double>::infinity() && gaps[k] < prm.closure_gap &&
          (k >= windows.size() || (t >= windows[k].closes_from && !(stitch_tie[k] < t))))
        {
          // the fraction of the last step at which the gap crossed; read at the step's
          // end when there is no counted step before it
          const double p_t   = previous ? previous->t : t;
          const double p_gap = previous ? previous->gaps[k] : gaps[k];
          const double p_T   = previous ? previous->tension : tension;
          const double s     = level_crossing(p_gap, gaps[k], prm.closure_gap);
          closed_at[k]      = at_fraction(p_t, t, s);
          closed_tension[k] = at_fraction(p_T, tension, s);
        }
    previous = Sample{t, tension, gaps};
    if (prm.tie_off_each_stitch)
      {
        for (std::size_t k = 0; k < stitch_tie.size(); ++k)
          if (stitch_ties_off(k, t, gaps))
            {
              stitch_tie[k]     = t;
              stitch_tension[k] = tension;
              stitch_gap[k]     = gaps[k];
            }
        // the series' motions stop with its last stitch's tie-off
        if (!tied() && !stitch_tie.empty() && stitch_tie.back() < std::numeric_limits<double>::infinity())
          {
            tie_time    = t;
            tie_tension = tension;
          }
      }
    else if (ties_off(t, gaps))
      {
        tie_time    = t;
        tie_tension = tension;
      }
  }

  void
  ClosureMonitor::set_stitches(std::vector<StitchWindow> w)
  {
    if (!prm.tie_off_each_stitch || w.size() != prm.pairs.size())
      throw std::logic_error("closure: one tightening window per gap pair, in an interrupted series only");
    windows = std::move(w);
    stitch_tie.assign(windows.size(), std::numeric_limits<double>::infinity());
    stitch_tension.assign(windows.size(), 0);
    stitch_gap.assign(windows.size(), 0);
  }

  void
  ClosureMonitor::write(nlohmann::json &metrics) const
  {
    if (initial.empty())
      return;
    metrics["initial_gap"]     = initial.front();
    metrics["final_gap"]       = last.front();
    metrics["closure_gap"]     = prm.closure_gap;
    // the run's closure is the first pair's
    metrics["closure_tension"] = closed() ? nlohmann::json(closed_tension.front()) : nlohmann::json(nullptr);
    metrics["closure_time"]    = closed() ? nlohmann::json(closed_at.front()) : nlohmann::json(nullptr);
    metrics["tie_off_time"]    = tied() ? nlohmann::json(tie_time) : nlohmann::json(nullptr);
    metrics["tie_off_tension"] = tied() ? nlohmann::json(tie_tension) : nlohmann::json(nullptr);
    for (std::size_t k = 0; k < prm.pairs.size(); ++k)
      {
        const bool pair_closed = closed_at[k] < std::numeric_limits<double>::infinity();
        metrics["gaps"][prm.pairs[k].name] = {
          {"initial", initial[k]},
          {"final", last[k]},
          {"least", least[k]},
          {"closure_time", pair_closed ? nlohmann::json(closed_at[k]) : nlohmann::json(nullptr)},
          {"closure_tension", pair_closed ? nlohmann::json(closed_tension[k]) : nlohmann::json(nullptr)}};
        if (k < stitch_tie.size())
          {
            const bool pair_tied = stitch_tie[k] < std::numeric_limits<double>::infinity();
            auto      &pair      = metrics["gaps"][prm.pairs[k].name];
            pair["tie_off_time"]    = pair_tied ? nlohmann::json(stitch_tie[k]) : nlohmann::json(nullptr);
            pair["tie_off_tension"] = pair_tied ? nlohmann::json(stitch_tension[k]) : nlohmann::json(nullptr);
            pair["tie_off_gap"]     = pair_tied ? nlohmann::json(stitch_gap[k]) : nlohmann::json(nullptr);
          }
      }
  }

  nlohmann::json
  ClosureMonitor::snapshot() const
  {
    nlohmann::json j{{"initial", initial},
                     {"last", last},
                     {"least", least},
                     {"tie_time", tie_time},
                     {"tie_tension", tie_tension},
                     {"closed_at", closed_at},
                     {"closed_tension", closed_tension},
                     {"stitch_tie", stitch_tie},
                     {"stitch_tension", stitch_tension},
                     {"stitch_gap", stitch_gap}};
    if (previous)
      j["previous"] = {{"t", previous->t}, {"tension", previous->tension}, {"gaps", previous->gaps}};
    return j;
  }

  void
  ClosureMonitor::restore(const nlohmann::json &j)
  {
    initial         = j.at("initial").get<std::vector<double>>();
    last            = j.at("last").get<std::vector<double>>();
    least           = j.at("least").get<std::vector<double>>();
    tie_time        = j.at("tie_time").get<double>();
    tie_tension     = j.at("tie_tension").get<double>();
    closed_at       = j.at("closed_at").get<std::vector<double>>();
    closed_tension  = j.at("closed_tension").get<std::vector<double>>();
    if (j.contains("stitch_tie")) // an interrupted series' (checkpoints of earlier versions have none)
      {
        stitch_tie     = j.at("stitch_tie").get<std::vector<double>>();
        stitch_tension = j.at("stitch_tension").get<std::vector<double>>();
        stitch_gap     = j.at("stitch_gap").get<std::vector<double>>();
      }
    previous.reset();
    if (j.contains("previous"))
      previous = Sample{j["previous"].at("t").get<double>(), j["previous"].at("tension").get<double>(),
                        j["previous"].at("gaps").get<std::vector<double>>()};
  }
} // namespace suturesim::scene
