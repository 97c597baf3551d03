#include <suturesim/scene/run_summary.h>
#include <suturesim/scene/scene_parameters.h>
#include <suturesim/scene/suture_recorder.h>

#include <algorithm>
#include <cstdio>
#include <iomanip>
#include <iostream>

namespace suturesim::scene
{
  io::PolylineData
  polyline_data(const rod::RodModel &model, const double radius)
  {
    io::PolylineData data;
    data.points         = model.positions();
    const std::size_t n = model.n_nodes();
    data.point_fields.emplace_back("radius", std::vector<double>(n, radius));
    data.point_fields.emplace_back("contact_force", model.contact_forces());
    std::vector<double> axial, shear, bending, twisting, twist, curvature;
    const auto          states = model.element_states();
    for (std::size_t e = 0; e < states.size(); ++e)
      {
        const auto     &s = states[e];
        const rod::Vec3 K = s.K + model.references()[e].kappa0;
        axial.push_back(s.N[0]);
        shear.push_back(s.N.tail<2>().norm());
        bending.push_back(s.M.tail<2>().norm());
        twisting.push_back(s.M[0]);
        twist.push_back(K[0]);
        curvature.push_back(K.tail<2>().norm());
      }
    data.segment_fields = {{"axial_force", axial},       {"shear_force", shear}, {"bending_moment", bending},
                           {"twisting_moment", twisting}, {"twist", twist},       {"curvature", curvature}};
    // an interrupted series' thread, cut beside each knot: 1 on the cut elements, which
    // join the pieces' ends only in the picture (ParaView: Threshold cut < 0.5)
    std::vector<double> cut(states.size(), 0.0);
    for (std::size_t e = 0; e < states.size(); ++e)
      cut[e] = model.is_cut(e) ? 1.0 : 0.0;
    if (std::find(cut.begin(), cut.end(), 1.0) != cut.end())
      data.segment_fields.emplace_back("cut", std::move(cut));
    return data;
  }

  void
  write_suture_vtu(const rod::RodModel &model, const double radius, const unsigned index, const double t,
                   io::Recorder &recorder)
  {
    char name[32];
    std::snprintf(name, sizeof(name), "suture_%05u.vtu", index);
    if (recorder.is_root())
      io::write_polyline_vtu(recorder.directory() + "/" + name, polyline_data(model, radius), t);
    recorder.add_vtu("suture", t, name);
  }

  SutureRecorder::SutureRecorder(rod::RodProblem &problem, io::Recorder &recorder)
    : problem(problem)
    , recorder(recorder)
  {
    std::vector<std::string> columns{"time [s]"};
    for (const std::string end : {"start", "last"})
      {
        for (const char c : {'x', 'y', 'z'})
          columns.push_back(end + "_reaction_force_" + std::string(1, c) + " [N]");
        for (const char c : {'x', 'y', 'z'})
          columns.push_back(end + "_reaction_moment_" + std::string(1, c) + " [N m]");
      }
    for (const char c : {'x', 'y', 'z'})
      columns.push_back("tip_" + std::string(1, c) + " [m]");
    columns.push_back("max_axial_force [N]");
    columns.push_back("elastic_energy [J]");
    columns.push_back("contact_nodes [1]");
    recorder.set_columns(columns);
  }

  void
  SutureRecorder::accepted(const double t, const nlohmann::json &statistics, const Eigen::VectorXd *residual)
  {
    auto                 &model  = problem.model;
    const Eigen::VectorXd r      = residual ? *residual : model.residual();
    const auto            states = model.element_states();
    const std::size_t     last   = model.n_nodes() - 1;
    std::vector<double>   row{t};
    // the reaction of a support is the residual of its node (zero for free ends)
    for (const std::size_t node : {std::size_t(0), last})
      for (unsigned d = 0; d < 6; ++d)
        row.push_back(model.is_constrained(node, d) ? r[6 * node + d] : 0.0);
    const rod::Vec3 tip = model.positions()[last];
    for (unsigned d = 0; d < 3; ++d)
      row.push_back(tip[d]);
    double max_axial = 0, energy = 0, stretch = 0;
    for (const auto &s : states)
      {
        max_axial = std::max(max_axial, std::abs(s.N[0]));
        stretch   = std::max(stretch, s.Gamma[0]); // the axial strain
        energy += s.energy;
      }
    row.push_back(max_axial);
    row.push_back(energy);
    std::size_t contact_nodes = 0;
    for (const double f : model.contact_forces())
      contact_nodes += f > 0;
    row.push_back(contact_nodes);
    recorder.add_row(row);

    auto &summary                          = recorder.summary();
    auto &metrics                          = summary["metrics"];
    metrics["tip_position"]                = {tip[0], tip[1], tip[2]};
    metrics["max_axial_force"]             = std::max(metrics.value("max_axial_force", 0.0), max_axial);
    metrics["final_max_axial_force"]       = max_axial;
    metrics["suture_stretch_max"]          = std::max(metrics.value("suture_stretch_max", 0.0), stretch);
    metrics["elastic_energy"]              = energy;
    metrics["start_reaction"]              = std::vector<double>(row.begin() + 1, row.begin() + 7);
    metrics["last_reaction"]               = std::vector<double>(row.begin() + 7, row.begin() + 13);
    metrics["contact_nodes"]               = contact_nodes;
    RunSummary(summary).solver({{"newton_iterations", problem.newton_iterations}});
    RunSummary(summary).step(statistics, t);

    if (problem.time.output_due(t, last_output))
      keep(t);
    if (recorder.is_root())
      {
        const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::cout << "  t = " << std::setw(10) << t << " s, Newton " << statistics.value("newton_iterations", 0)
                  << ", tip (" << tip.transpose() << ") m, max |N| " << max_axial << " N, " << std::setprecision(3)
                  << elapsed << " s elapsed" << std::setprecision(6) << '\n';
      }
  }

  std::string
  SutureRecorder::keep(const double t)
  {
    if (last_output < t)
      {
        write_suture_vtu(problem.model, problem.parameters.section.radius, output_index++, t, recorder);
        last_output = t;
      }
    return recorder.directory() + "/suture.pvd";
  }

  SutureRun::SutureRun(const SceneParameters &scene, io::Recorder &recorder, dealii::ConditionalOStream &banner,
                       const std::string &what)
    : problem(scene.suture, scene.time)
    , observer(problem, recorder)
  {
    RunSummary summary(recorder.summary());
    summary.begin(scene);
    summary.rod(scene.suture, problem.model.n_elements());
    banner << "suturesim: scene '" << scene.name << "', suture of " << problem.model.n_elements()
           << " Cosserat rod elements" << what << "\n";
  }
} // namespace suturesim::scene
