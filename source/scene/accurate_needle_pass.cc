#include <suturesim/core/error.h>
#include <suturesim/coupling/accurate/tissue_needle.h>
#include <suturesim/scene/accurate_needle_pass.h>

#include <deal.II/distributed/tria.h>

#include <algorithm>
#include <iomanip>
#include <sstream>

namespace suturesim::scene
{
  using namespace dealii;

  void
  run_accurate_needle_pass(const AccurateNeedleInputs &in, io::Recorder &recorder, TimerOutput &timer,
                           ConditionalOStream &pcout)
  {
    MPI_Comm                                 comm = MPI_COMM_WORLD;
    parallel::distributed::Triangulation<3> tria(comm);
    mesh::MeshInfo                           mesh_info;
    {
      TimerOutput::Scope scope(timer, "mesh");
      mesh_info = mesh::create_mesh(*in.mesh, recorder.directory(), tria);
    }
    in.boundary_conditions->resolve(mesh_info);
    tissue::TissueModel model(comm, *in.tissue, *in.material, *in.boundary_conditions, tria, timer);
    model.setup();

    const NeedleParameters &np      = *in.needle;
    const auto              surface = model.boundary_surface();
    coupling::TissueNeedleParameters parameters;
    parameters.puncture             = np.puncture;
    parameters.friction             = np.friction;
    parameters.transverse_stiffness = np.transverse_stiffness;
    parameters.spacing              = np.spacing;
    const tools::CurvedNeedle geometry = np.needle();
    coupling::TissueNeedle    needle(geometry, parameters, surface.triangles, surface.reference);
    const tools::Trajectory   path       = np.trajectory();
    const double              pull_start = np.motion == "pass" ? np.planned_pass().t_turn_end : 0;

    auto &summary      = recorder.summary();
    summary["scene"]      = in.scene_name;
    summary["scene_file"] = in.scene_file;
    summary["model"]      = "accurate";
    summary["mesh"]       = {{"description", mesh_info.description},
                             {"cells", tria.n_global_active_cells()},
                             {"dofs", model.n_dofs()},
                             {"element_degree", in.tissue->degree},
                             {"formulation", in.tissue->formulation},
                             {"surface_triangles", surface.triangles.size()}};
    summary["metrics"]    = nlohmann::json::object();
    summary["steps"]      = nlohmann::json::array();
    pcout << "suturesim: scene '" << in.scene_name << "', " << mesh_info.description << ", "
          << tria.n_global_active_cells() << " cells, " << model.n_dofs() << " DoFs, needle "
          << np.shape << " R = " << np.radius << " m, " << np.enforcement << " pierce points\n";

    std::vector<std::string> columns{"time [s]"};
    for (const auto &d : in.boundary_conditions->dirichlet)
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(d.name + "_reaction_" + std::string(1, c) + " [N]");
    for (const auto &[name, point] : model.probes())
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(name + "_displacement_" + std::string(1, c) + " [m]");
    np.add_columns(columns);
    recorder.set_columns(columns);

    const auto positions = [&]() {
      std::vector<Point<3>> x(needle.points().size());
      for (std::size_t k = 0; k < x.size(); ++k)
        x[k] = model.point_position(k);
      return x;
    };
    double      peak_pull = 0, last_output = -1;
    unsigned    output_index = 0;
    std::string last_file;
    // the needle's load of the converged state is taken before the step is accepted (a
    // puncture changes the set of points)
    std::pair<Tensor<1, 3>, Tensor<1, 3>> load;
    const auto  record = [&](const double t, nlohmann::json statistics) {
      std::vector<double> row{t};
      auto               &metrics = summary["metrics"];
      for (const auto &r : model.reactions(t))
        {
          for (unsigned d = 0; d < 3; ++d)
            row.push_back(r.force[d]);
          metrics["reaction_force"][r.boundary] = {r.force[0], r.force[1], r.force[2]};
        }
      const auto probes = model.probe_displacements();
      for (std::size_t p = 0; p < probes.size(); ++p)
        for (unsigned d = 0; d < 3; ++d)
          {
            row.push_back(probes[p][d]);
            metrics[model.probes()[p].first + "_displacement_" + std::string(1, char('x' + d))] = probes[p][d];
          }
      const auto &[force, torque] = load;
      for (unsigned d = 0; d < 3; ++d)
        row.push_back(force[d]);
      for (unsigned d = 0; d < 3; ++d)
        row.push_back(torque[d]);
      for (unsigned d = 0; d < 3; ++d)
        row.push_back(needle.pose().position[d]);
      if (t >= pull_start)
        peak_pull = std::max(peak_pull, force.norm());
      const auto &points = needle.pierce_points();
      for (unsigned k = 0; k < np.recorded; ++k)
        if (k < points.size())
          for (const double v : {points[k].slipping ? 2.0 : 1.0, points[k].anchor, points[k].slip_speed,
                                 points[k].normal, points[k].friction})
            row.push_back(v);
        else
          for (int j = 0; j < 5; ++j)
            row.push_back(0);
      recorder.add_row(row);
      const auto &time = *in.time;
      if (time.output_interval <= 0 || last_output < 0 ||
          t >= last_output + time.output_interval * (1 - 1e-9) || t >= time.end_time * (1 - 1e-12))
        {
          last_file = model.write_vtu(recorder.directory(), output_index++, t);
          recorder.add_vtu("tissue", t, last_file);
          last_output = t;
        }
      statistics["time"] = t;
      summary["steps"].push_back(statistics);
    };

    const auto fail = [&](const double t, const std::string &reason) {
      std::ostringstream s;
      s << "Newton failed at t = " << t << " s after " << in.time->max_cutbacks
        << " step halvings: " << reason << "; last converged state t = " << last_output << " s"
        << (last_file.empty() ? "" : " in " + recorder.directory() + "/" + last_file);
      throw SolverError(s.str());
    };

    // equilibrium at t = 0, the needle away
    needle.begin_step(0, path.pose(0), surface.reference);
    {
      const auto report = model.solve_static(0);
      if (!report.converged)
        fail(0, report.failure);
      record(0, {{"newton_iterations", report.iterations}});
    }
    Eigen::Matrix3Xd x_surface;
    model.surface_positions(surface, x_surface);

    const double T  = in.time->end_time, h = in.time->step_size;
    double       t  = 0, dt = h;
    unsigned     cutbacks = 0, steps = 0, total_iterations = 0;
    while (t < T * (1 - 1e-12))
      {
        const double step_dt = std::min(dt, T - t), tn = t + step_dt;
        needle.save();
        model.save_state();
        if (needle.begin_step(tn, path.pose(tn), x_surface))
          model.set_point_loads(needle.points().empty() ? nullptr : &needle);
        const tissue::NewtonReport report = model.solve_static(tn);
        const auto cut = [&](const std::string &reason) {
          model.restore_state();
          needle.restore();
          model.set_point_loads(needle.points().empty() ? nullptr : &needle);
          if (cutbacks == in.time->max_cutbacks)
            fail(tn, reason);
          ++cutbacks;
          dt = 0.5 * step_dt;
        };
        if (!report.converged)
          {
            cut(report.failure);
            continue;
          }
        const auto x = positions();
        // land the puncture within 4 % above the threshold: cut a step that overshoots
        if (needle.touch_force(x) > 1.04 * np.puncture.threshold && cutbacks < in.time->max_cutbacks + 8)
          {
            model.restore_state();
            needle.restore();
            model.set_point_loads(needle.points().empty() ? nullptr : &needle);
            ++cutbacks;
            dt = 0.5 * step_dt;
            continue;
          }
        load               = needle.needle_load(x);
        const bool changed = needle.accept_step(x);
        t                  = tn;
        ++steps;
        total_iterations += report.iterations;
        record(t, {{"dt", step_dt},
                   {"newton_iterations", report.iterations},
                   {"cutbacks", cutbacks},
                   {"residual_norms", report.residual_norms}});
        if (changed)
          model.set_point_loads(needle.points().empty() ? nullptr : &needle);
        model.surface_positions(surface, x_surface);
        if (steps % 20 == 0)
          pcout << "step " << steps << "  t = " << std::setprecision(4) << t << " s  Newton "
                << report.iterations << " it  pierce points " << needle.pierce_points().size() << "\n";
        cutbacks = 0;
        dt       = std::min(2 * dt, h);
      }

    np.write_summary(summary, needle.all_events(), peak_pull);
    summary["solver"]["steps"]                   = steps;
    summary["solver"]["newton_iterations_total"] = total_iterations;
  }
} // namespace suturesim::scene
