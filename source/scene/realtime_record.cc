#include <suturesim/collision/volume_penetration.h>
#include <suturesim/io/polyline_writer.h>
#include <suturesim/io/simplex_writer.h>
#include <suturesim/io/surface_field.h>
#include <suturesim/scene/realtime_record.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <limits>
#include <sstream>

namespace suturesim::scene
{
  namespace rt = realtime;

  namespace
  {
    /// Appends @p more (a JSON array of events, each with a time) to summary.json's
    /// events, which stay in time order (the needle's, RunSummary::needle(), start them).
    void
    add_events(nlohmann::json &events, const nlohmann::json &more)
    {
      for (const auto &e : more)
        events.push_back(e);
      std::stable_sort(events.begin(), events.end(), [](const auto &a, const auto &b) { return a["time"] < b["time"]; });
    }

    std::string
    processor_name()
    {
      std::ifstream in("/proc/cpuinfo");
      for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0)
          return line.substr(line.find(':') + 2);
      return "unknown";
    }

    void
    add_xyz(std::vector<std::string> &columns, const std::string &stem, const std::string &unit)
    {
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(stem + std::string(1, c) + " [" + unit + "]");
    }
  } // namespace

  RealtimeRecord::RealtimeRecord(RealtimeWorld &w, const RealtimeSettings &settings, io::Recorder &r)
    : world(w)
    , recorder(r)
    , summary(r.summary())
  {
    const auto &scene = world.scene;
    const auto &rw    = *world.world;
    const auto &sys   = rw.system();
    summary.begin(scene);
    summary.whole()["machine"] = processor_name() + ", one core";
    const std::string settings_text = rw.integrator().settings();
    auto             &realtime      = summary.realtime();
    realtime = {{"integrator", settings_text.empty() ? settings.integrator : settings.integrator + " (" + settings_text + ")"},
                {"rate_hz", settings.rate},
                {"substeps", settings.substeps},
                {"dt_s", rw.dt()},
                {"dt_crit_s",
                 std::isfinite(rw.stability_limit()) ? nlohmann::json(rw.stability_limit()) : nlohmann::json("none")},
                {"stability_limit", rw.stability_description()},
                {"nodes", sys.nodes.size()}};
    if (!rw.warning().empty())
      summary.whole()["warnings"].push_back(rw.warning());
    if (scene.has_tissue())
      {
        realtime["tissue_model"] = settings.tissue_model;
        summary.simplex_mesh(world.tissue_mesh.description, world.tissue_mesh.vertices.cols(),
                             world.tissue_mesh.tetrahedra.size(), world.tissue_mesh.total_volume(),
                             world.surface.triangles.size());
      }
    if (scene.has_suture())
      {
        realtime["suture_model"]   = settings.suture_model;
        realtime["self_collision"] = settings.self_collision;
        realtime["contact"]        = scene.has_tissue() && settings.contact;
        summary.realtime_suture(sys.suture.size(), scene.suture.section.radius, rw.suture()->geometry().EA,
                                rw.suture()->geometry().EI);
      }
    for (const auto &i : sys.interactions)
      realtime["interactions"][i->name()] = i->size();

    std::vector<std::string> columns{"time [s]"};
    for (const auto &t : world.tool_ends)
      add_xyz(columns, t.name + "_force_", "N");
    if (world.needle)
      world.needle->add_columns(columns);
    if (world.probe_tool)
      add_xyz(columns, "probe_force_", "N");
    for (const auto &b : world.boundaries)
      {
        add_xyz(columns, b.name + "_reaction_", "N");
        reactions.push_back(rw.reaction_set(b.nodes));
      }
    for (const auto &[name, index] : world.probes)
      add_xyz(columns, name + "_displacement_", "m");
    if (world.closure)
      for (const auto &pair : scene.closure.pairs)
        columns.push_back("gap_" + pair.name + " [m]");
    columns.push_back("kinetic_energy [J]");
    columns.push_back("elastic_energy [J]");
    recorder.set_columns(columns);
    values.resize(columns.size());

    // 16 s of rows at 1 kHz before one is dropped; two state slots (one written while the
    // next is filled), sized by the state they will hold
    RecordState prototype;
    capture(prototype);
    const std::size_t width = values.size();
    writer = std::make_unique<BackgroundWriter<RecordState>>(
      width, 16384, prototype, 2,
      BackgroundWriter<RecordState>::Sinks{[this, width](const double *row) { recorder.add_row(row, width, false); },
                                           [this](const RecordState &state) { write(state); },
                                           [this] { recorder.flush_rows(); }});
  }

  void
  RealtimeRecord::row(const bool output)
  {
    const auto &rw  = *world.world;
    const auto &sys = rw.system();
    std::size_t c   = 0;
    values[c++]     = rw.time();
    for (std::size_t k = 0; k < world.tool_ends.size(); ++k)
      for (int d = 0; d < 3; ++d)
        values[c++] = rw.tool_forces()[world.first_end_tool + k].force[d];
    if (world.needle)
      world.needle->fill_row(rw, values, c);
    if (world.probe_tool)
      {
        for (int d = 0; d < 3; ++d)
          values[c++] = rw.tool_forces()[*world.probe_tool].force[d];
        const auto &contact = *rw.probe_contact().front();
        for (const auto &k : contact.list())
          probe_least_gap = std::min(probe_least_gap, contact.gap(k, sys.nodes.x));
      }
    for (auto &set : reactions)
      {
        const auto r = rw.reaction(set);
        for (int d = 0; d < 3; ++d)
          values[c++] = r[d];
      }
    for (const auto &[name, index] : world.probes)
      {
        const auto u = rw.probe_displacement(index);
        for (int d = 0; d < 3; ++d)
          values[c++] = u[d];
      }
    for (const double g : world.gaps)
      values[c++] = g;
    values[c++] = sys.kinetic_energy();
    values[c++] = output ? sys.elastic_energy(sys.nodes.x) : std::numeric_limits<double>::quiet_NaN();
    writer->push_row(values.data());
    // the suture's longest link so far, squared (one vectorised pass per step; the stretch
    // |x_i+1 - x_i|/l - 1 is formed once, in finish())
    if (world.scene.has_suture())
      {
        const auto n    = sys.suture.end - sys.suture.begin;
        const auto link = (sys.nodes.x.middleCols(sys.suture.begin + 1, n - 1) -
                           sys.nodes.x.middleCols(sys.suture.begin, n - 1))
                            .colwise()
                            .squaredNorm();
        // an interrupted series' cut links are no links any more
        longest_link_squared = std::max(longest_link_squared, world.uncut.size() > 0
                                                                ? link.cwiseProduct(world.uncut).maxCoeff()
                                                                : link.maxCoeff());
      }
  }

  void
  RealtimeRecord::capture(RecordState &s) const
  {
    const auto &rw  = *world.world;
    const auto &sys = rw.system();
    s.time          = rw.time();
    if (world.scene.has_tissue())
      {
        // assignments of equal sizes into a slot's matrices and vectors allocate nothing;
        // a surface grown by seed 002's subdivision reallocates each slot's triangles once
        const auto n = sys.tissue.end;
        s.x          = sys.nodes.x.leftCols(n);
        s.X          = sys.nodes.reference.leftCols(n);
        s.v          = sys.nodes.v.leftCols(n);
        s.tetrahedra = rw.tissue()->volume_cells();
        if (s.tetrahedra.empty())
          s.triangles = rw.tissue()->surface();
      }
    if (world.scene.has_suture())
      {
        s.suture = sys.nodes.x.middleCols(sys.suture.begin, sys.suture.size());
        rw.suture()->segment_tension(sys, s.tension);
      }
  }

  void
  RealtimeRecord::write_state(const bool wait)
  {
    const std::size_t index = n_outputs++;
    if (RecordState *slot = wait ? writer->wait_for_state() : writer->acquire_state())
      {
        capture(*slot);
        slot->index = index;
        writer->publish(slot);
        last_written = world.world->time();
      }
  }

  void
  RealtimeRecord::write(const RecordState &s)
  {
    std::ostringstream number;
    number << "_" << std::setw(5) << std::setfill('0') << s.index << ".vtu";
    if (world.scene.has_tissue())
      {
        const auto name = "tissue" + number.str();
        const auto file = recorder.directory() + "/" + name;
        if (!s.tetrahedra.empty())
          io::write_simplex_vtu(file, io::SimplexData<4>{s.x, s.tetrahedra, {{"displacement", s.x - s.X}, {"velocity", s.v}}, {}},
                                s.time);
        else
          io::write_simplex_vtu(file, io::SimplexData<3>{s.x, s.triangles, {{"displacement", s.x - s.X}, {"velocity", s.v}}, {}},
                                s.time);
        recorder.add_vtu("tissue", s.time, name);
      }
    if (world.scene.has_suture())
      {
        io::PolylineData data;
        for (Eigen::Index i = 0; i < s.suture.cols(); ++i)
          data.points.push_back(s.suture.col(i));
        data.point_fields   = {{"radius", std::vector<double>(data.points.size(), world.scene.suture.section.radius)}};
        data.segment_fields = {{"tension", s.tension}};
        const auto name     = "suture" + number.str();
        io::write_polyline_vtu(recorder.directory() + "/" + name, data, s.time);
        recorder.add_vtu("suture", s.time, name);
      }
  }

  void
  RealtimeRecord::finish(const rt::LoopStatistics &stats, const rt::LoopStatistics &tick,
                         const rt::PhaseStatistics &phases, const double wall_time)
  {
    const auto &scene                = world.scene;
    const auto &rw                   = *world.world;
    const auto &sys                  = rw.system();
    writer->finish();
    auto       &metrics              = summary.metrics();
    metrics["steps"]                 = stats.steps;
    metrics["step_time_median_us"]   = stats.median_us;
    metrics["step_time_p99_us"]      = stats.p99_us;
    metrics["step_time_max_us"]      = stats.max_us;
    metrics["step_time_mean_us"]     = stats.mean_us;
    metrics["deadline_us"]           = stats.deadline_us;
    metrics["deadline_misses"]       = stats.deadline_misses;
    metrics["tick_time_median_us"]   = tick.median_us;
    metrics["tick_time_p99_us"]      = tick.p99_us;
    metrics["tick_time_max_us"]      = tick.max_us;
    metrics["tick_time_mean_us"]     = tick.mean_us;
    metrics["tick_deadline_misses"]  = tick.deadline_misses;
    const auto phase = [](const rt::LoopStatistics &p) { return nlohmann::json{{"median", p.median_us}, {"p99", p.p99_us}}; };
    metrics["tick_phases_us"] = {{"collision", phase(phases.collision)},
                                 {"solve", phase(phases.solve)},
                                 {"coupling", phase(phases.coupling)},
                                 {"recording", phase(phases.recording)}};
    // what the writer thread could not take (a disk slower than the output rate), and
    // its time in formatting, compressing and writing, off the haptic thread
    metrics["recording"]             = {{"rows_dropped", writer->rows_dropped()},
                                        {"states_dropped", writer->states_dropped()},
                                        {"writer_busy_s", writer->busy_seconds()}};
    metrics["final_time"]            = rw.time();
    metrics["simulated_time"]        = rw.time();
    metrics["wall_time"]             = wall_time;
    if (const auto *self = rw.self_collision())
      {
        // pair-steps with a response, most pairs at once, least distances (null: no pair
        // came within the reach), as counted by the response (realtime/self_collision.h)
        const auto &c     = self->counts();
        const auto  least = [](const double d) { return std::isfinite(d) ? nlohmann::json(d) : nlohmann::json(); };
        metrics["self_collision"] = {{"pair_steps", c.pair_steps},
                                     {"max_pairs", c.max_pairs},
                                     {"min_distance", least(c.min_distance)},
                                     {"min_distance_detected", least(c.min_distance_detected)},
                                     {"reach", c.reach}};
      }
    if (world.probe_tool)
      {
        // the probe's push at the end and how far into its radius the tissue came (null:
        // it never came within reach)
        const auto f      = rw.tool_forces()[*world.probe_tool].force;
        metrics["probe"] = {{"force", {f[0], f[1], f[2]}},
                            {"least_gap", std::isfinite(probe_least_gap) ? nlohmann::json(probe_least_gap)
                                                                         : nlohmann::json()}};
      }
    if (const auto *access = rw.access())
      {
        // each access point's link at the end and the tension through it, k C (N)
        auto &list = metrics["access"] = nlohmann::json::array();
        for (std::size_t a = 0; a < access->list().size(); ++a)
          list.push_back({{"name", world.access_names[a]},
                          {"link", access->list()[a].segment},
                          {"tension", access->tension(a, sys.nodes.x)}});
      }
    if (world.closure)
      world.closure->write(metrics);
    world.write_series(metrics);
    if (scene.has_suture())
      {
        const auto tip             = sys.nodes.x.col(sys.suture.end - 1);
        metrics["suture_stretch_max"] = std::max(0.0, std::sqrt(longest_link_squared) / rw.suture()->link_length() - 1);
        metrics["tip_position"]       = {tip[0], tip[1], tip[2]};
      }
    // no suture node may end inside the tissue, deeper than its radius below the
    // surface, but those the thread carries between two pierce points
    if (scene.has_tissue() && scene.has_suture() && !rw.tissue()->volume_cells().empty())
      {
        const rt::Matrix3Xd nodes = sys.nodes.x.middleCols(sys.suture.begin, sys.suture.size());
        std::vector<char>   pierced;
        if (rw.needle())
          pierced = rw.needle()->suture_inside();
        const auto inside = collision::volume_penetration(sys.nodes.x.leftCols(sys.tissue.end),
                                                          rw.tissue()->volume_cells(), rw.tissue()->surface(), nodes,
                                                          scene.suture.section.radius);
        const auto split  = collision::split_by_tracts(inside, pierced);
        metrics["suture_nodes_inside_tissue"] = split.outside_tracts;
        metrics["suture_penetration_depth"]   = split.depth;
        metrics["suture_nodes_in_tracts"]     = split.in_tracts;
      }
    for (std::size_t k = 0; k < world.tool_ends.size(); ++k)
      metrics[world.tool_ends[k].name + "_force_magnitude"] = rw.tool_forces()[world.first_end_tool + k].force.norm();
    if (world.needle)
      {
        const auto events = world.needle->events(rw);
        summary.needle(scene.needle, events, world.needle->peak_pull_force(), rw.needle()->pierce_model());
        // the pierce points at the end in the order the needle made them (the coupling
        // keeps the newest first): where each was born, and its spread's share on the
        // tissue beyond the wound's faces (Pierce points/Load across the wound)
        auto &points = summary.whole()["pierce_points"];
        points       = nlohmann::json::array();
        for (auto p = rw.needle()->pierce_points().rbegin(); p != rw.needle()->pierce_points().rend(); ++p)
          points.push_back({{"reference", {p->reference[0], p->reference[1], p->reference[2]}},
                            {"exit", p->exit},
                            {"on_suture", p->on_suture},
                            {"load_across_wound", p->across_wound}});
        if (const auto free = world.needle->free_record(rw); !free.empty())
          metrics["free_needle"] = free;
        // seed 003's evaluation measures a curved needle's pass from entry to exit across
        // a wound; an Endo Stitch's passes each go straight through one piece
        if (scene.needle.shape != "double-pointed")
          recorder.write_file("stitches.csv", tearing::stitches_csv(summary.stitch_evaluation(
                                                scene.needle, events, world.wound, scene.stitch_evaluation)));
        summary.pass_outcome(scene.needle, events, rw.time(), scene.needle.attach_suture && rw.suture() != nullptr);
        if (world.tearing)
          {
            add_events(summary.whole()["events"], world.tearing->events());
            const auto &tears           = world.tearing->tears();
            metrics["realtime_tearing"] = {{"ligament_strength", world.tearing->parameters().strength},
                                           {"tears", tears.size()}};
            // the onset (the first tear's tension and time), what a bite x spacing map draws;
            // absent without a tear, so that a study finds it missing rather than zero
            if (!tears.empty())
              {
                metrics["realtime_tearing"]["onset_tension"] = tears.front().suture_tension;
                metrics["realtime_tearing"]["onset_force"]   = tears.front().tension;
                metrics["realtime_tearing"]["onset_time"]    = tears.front().time;
              }
          }
      }
    // after the needle's events (RunSummary::needle() starts the list)
    if (world.planner)
      {
        metrics["knot"] = knot::knot_metrics(*world.planner, sys.nodes.x.middleCols(sys.suture.begin, sys.suture.size()));
        add_events(summary.whole()["events"], knot::knot_events(*world.planner));
      }
    for (const auto &[name, index] : world.probes)
      {
        const auto u = rw.probe_displacement(index);
        for (int d = 0; d < 3; ++d)
          metrics[name + "_displacement_" + std::string(1, char('x' + d))] = u[d];
      }
    if (scene.has_tissue())
      io::SurfaceField::of(rw.time(), sys.nodes.reference.leftCols(sys.tissue.end),
                           sys.nodes.x.leftCols(sys.tissue.end) - sys.nodes.reference.leftCols(sys.tissue.end),
                           rw.tissue()->surface())
        .write(recorder.directory() + "/surface_displacement.json");
  }
} // namespace suturesim::scene
