#include <suturesim/scene/realtime_needle.h>

#include <suturesim/collision/volume_penetration.h>
#include <suturesim/core/model_parameters.h>

#include <algorithm>

namespace suturesim::scene
{
  namespace rt = realtime;

  RealtimeNeedle::RealtimeNeedle(const NeedleParameters &parameters, rt::World &world,
                                 const std::string &pierce_model, const double mass_ratio, const tearing::Wound &wound)
    : prm(parameters)
    , path(parameters.trajectory())
  {
    pull_start = prm.motion == "pass" ? prm.planned_pass().t_turn_end : 0;
    if (prm.motion == "pass" && prm.series.interrupted)
      series = prm.planned_series();
    rt::NeedleCouplingParameters c;
    c.puncture             = prm.puncture;
    c.friction             = prm.friction;
    c.transverse_stiffness = prm.transverse_stiffness;
    c.spacing              = prm.spacing;
    c.load_radius          = prm.load_radius;
    c.load_across_wound    = prm.load_across_wound;
    if (wound.present())
      c.hidden = [&wound](const Eigen::Vector3d &a, const Eigen::Vector3d &b) { return wound.hides(a, b); };
    c.mass_ratio           = mass_ratio;
    c.pierce_model         = pierce_model;
    jaws                   = prm.jaw_changes();
    reloads                = prm.reloads();
    jaw_point              = prm.needle().body_point((1 - prm.pass.grip) * prm.needle().length());
    tool_index             = world.add_needle(prm.needle(), c, path.pose(0),
                                              prm.attach_suture && world.suture() != nullptr);
  }

  void
  RealtimeNeedle::place_suture(const NeedleParameters &p, std::vector<Eigen::Vector3d> &points)
  {
    const auto        needle = p.needle();
    const tools::Pose start  = p.trajectory().pose(0);
    double            length = 0;
    for (std::size_t i = 0; i + 1 < points.size(); ++i)
      length += (points[i + 1] - points[i]).norm();
    const Eigen::Vector3d swage = needle.swage(start);
    const Eigen::Vector3d away  = -needle.tangent(start, needle.length());
    for (std::size_t i = 0; i < points.size(); ++i)
      points[i] = swage + length * double(i) / double(points.size() - 1) * away;
  }

  void
  RealtimeNeedle::operate_jaws(rt::World &world, const double t)
  {
    if (const auto *free = world.free_needle())
      largest_move = std::max(largest_move, (free->centroid() - let_go).norm());
    for (; next_jaw < jaws.size() && jaws[next_jaw].first <= t; ++next_jaw)
      {
        const auto [when, opens] = jaws[next_jaw];
        const tools::Pose driver = path.pose(when);
        const Eigen::Vector3d at = driver.apply(jaw_point);
        // the jaws are not a body, but where they open or close must be out of the tissue
        if (collision::winding_number(at, world.system().nodes.x, world.tissue()->surface()) > 0.5)
          throw ParameterError("Jaws", "at " + default_text(when) + " s the jaws " + (opens ? "open" : "close") +
                                         " inside the tissue, at (" + default_text(at[0]) + ", " +
                                         default_text(at[1]) + ", " + default_text(at[2]) + ") m");
        const bool reload = std::any_of(reloads.begin(), reloads.end(), [when = when](const auto &r) {
          return r.first == when;
        });
        if (opens && reload) // the other hand holds the needle where it is
          {
            parked = world.needle()->pose();
            world.hand_needle_over(*parked);
          }
        else if (opens)
          {
            world.release_needle(prm.density, prm.drag);
            let_go      = world.free_needle()->centroid();
            released_at = world.time();
          }
        else
          {
            const auto  &needle = world.needle()->geometry();
            const double gap    = (needle.point(world.needle()->pose(), needle.closest(world.needle()->pose(), at)) - at).norm();
            if (gap > needle.wire_diameter())
              throw ParameterError("Jaws", "at " + default_text(when) + " s the jaws close " + default_text(gap) +
                                             " m from the needle (they take it within its wire diameter, " +
                                             default_text(needle.wire_diameter()) + " m)");
            if (parked) // from the other hand
              {
                world.hand_needle_over(driver);
                parked.reset();
              }
            else
              {
                world.grasp_needle(driver);
                free_time += world.time() - released_at;
                const auto &points = world.needle()->pierce_points(); // those on the suture hold it not
                holding.push_back(std::count_if(points.begin(), points.end(), [](const auto &q) { return !q.on_suture; }));
              }
          }
        coupling::PunctureEvent e;
        e.kind     = !opens ? "needle_grasped" : reload ? "needle_handed_over" : "needle_released";
        e.time     = world.time();
        e.position = at;
        jaw_events.push_back(e);
      }
    for (; next_pass < prm.passes.size() && prm.passes[next_pass] <= t; ++next_pass)
      {
        try
          {
            world.reverse_needle();
          }
        catch (const std::invalid_argument &e)
          {
            throw ParameterError("Passes across", "at " + default_text(prm.passes[next_pass]) +
                                                    " s the needle cannot go to the other jaw: " + e.what());
          }
        coupling::PunctureEvent e;
        e.kind     = "needle_passed_across";
        e.time     = world.time();
        e.position = world.needle()->geometry().swage(world.needle()->pose());
        jaw_events.push_back(e);
      }
  }

  nlohmann::json
  RealtimeNeedle::free_record(const rt::World &world) const
  {
    if (jaws.empty() || next_jaw == 0)
      return {};
    // still free at the end: until now
    const double time = free_time + (world.free_needle() != nullptr ? world.time() - released_at : 0);
    return {{"time_free", time}, {"largest_move", largest_move}, {"pierce_points_at_grasp", holding}};
  }

  void
  RealtimeNeedle::add_columns(std::vector<std::string> &columns) const
  {
    prm.add_columns(columns);
    columns.push_back("suture_tension_swage [N]");
    columns.push_back("suture_tension_free_end [N]");
  }

  void
  RealtimeNeedle::fill_row(const rt::World &world, std::vector<double> &row, std::size_t &c)
  {
    const auto &f = world.tool_forces().at(tool_index);
    for (int d = 0; d < 3; ++d)
      row[c++] = f.force[d];
    for (int d = 0; d < 3; ++d)
      row[c++] = f.torque[d];
    const Eigen::Vector3d centre = world.needle()->pose().position;
    for (int d = 0; d < 3; ++d)
      row[c++] = centre[d];
    if (world.time() >= pull_start)
      peak_pull = std::max(peak_pull, f.force.norm());
    const auto &points = world.needle()->pierce_points();
    for (unsigned k = 0; k < prm.recorded; ++k)
      {
        if (k < points.size())
          {
            const auto &p = points[k];
            row[c++]      = p.slipping ? 2 : 1;
            row[c++]      = p.anchor; // its material point: the order holds on these
            row[c++]      = p.slip_speed;
            row[c++]      = p.normal;
            row[c++]      = p.friction;
          }
        else
          for (int j = 0; j < 5; ++j)
            row[c++] = 0;
      }
    std::vector<double> tension;
    if (world.suture() != nullptr)
      world.suture()->segment_tension(world.system(), tension);
    // at the swage: the first segment the needle does not hold (a curved needle holds
    // the first two nodes, so the first segment carries no tension of its own)
    const std::size_t first = world.needle()->geometry().straight() ? 0 : 1;
    row[c++]                = tension.size() <= first ? 0.0 : tension[first];
    row[c++] = tension.empty() ? 0.0 : tension.back();
  }

  std::vector<coupling::PunctureEvent>
  RealtimeNeedle::events(const rt::World &world) const
  {
    std::vector<coupling::PunctureEvent> events = world.needle()->puncture_state().events();
    const auto &thread                          = world.needle()->thread_events();
    events.insert(events.end(), thread.begin(), thread.end());
    events.insert(events.end(), jaw_events.begin(), jaw_events.end());
    std::stable_sort(events.begin(), events.end(), [](const auto &a, const auto &b) { return a.time < b.time; });
    return events;
  }
} // namespace suturesim::scene
