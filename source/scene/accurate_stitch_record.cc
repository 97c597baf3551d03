#include <suturesim/collision/volume_penetration.h>
#include <suturesim/scene/accurate_stitch_record.h>
#include <suturesim/scene/suture_recorder.h>

#include <deal.II/grid/grid_tools.h>

namespace suturesim::scene
{
  using namespace dealii;

  AccurateStitchRecord::AccurateStitchRecord(AccurateStitch &s, io::Recorder &r)
    : stitch(s)
    , recorder(r)
    , summary(r.summary())
  {
    const auto &scene = stitch.scene;
    summary.begin(scene);
    summary.fe_mesh(stitch.mesh_info.description, stitch.tria.n_global_active_cells(), stitch.model->n_dofs(),
                    dealii::GridTools::volume(stitch.tria), scene.tissue, stitch.surface.triangles.size());
    if (stitch.suture)
      summary.coupled_suture(stitch.suture->n_elements(), stitch.needle->curve_length() - stitch.geometry.length(),
                             stitch.np.coupling_tolerance);

    std::vector<std::string> columns{"time [s]"};
    for (const auto &d : scene.boundary_conditions.dirichlet)
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(d.name + "_reaction_" + std::string(1, c) + " [N]");
    for (std::size_t p = 0; p < stitch.first_gap_probe; ++p)
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(stitch.model->probes()[p].first + "_displacement_" + std::string(1, c) + " [m]");
    if (stitch.closure)
      for (const auto &pair : scene.closure.pairs)
        columns.push_back("gap_" + pair.name + " [m]");
    stitch.np.add_columns(columns);
    if (stitch.suture)
      {
        for (const std::string end : {"swage", "free_end"})
          columns.push_back("suture_tension_" + end + " [N]");
        columns.push_back("suture_stabilization_force [N]");
        columns.push_back("suture_tissue_contact_force [N]");
        columns.push_back("suture_tissue_contacts [1]");
      }
    if (stitch.faces)
      {
        columns.push_back("wound_face_contact_force [N]");
        columns.push_back("wound_face_contacts [1]");
      }
    if (!scene.tearing.criteria.empty())
      {
        tears.emplace(scene.tearing, stitch.wound);
        columns.push_back("pull_tension [N]");
        for (const auto &criterion : scene.tearing.criteria)
          columns.push_back("tear_" + criterion.first + " [1]");
        for (const auto &criterion : scene.tearing.criteria)
          columns.push_back("tear_force_" + criterion.first + " [N]");
      }
    recorder.set_columns(columns);
  }

  void
  AccurateStitchRecord::record_gaps(const double t, const std::vector<Tensor<1, 3>> &probes, std::vector<double> &row)
  {
    const std::vector<double> gaps = stitch.gaps(probes);
    row.insert(row.end(), gaps.begin(), gaps.end());
    stitch.closure->update(t, gaps, pull_tension());
  }

  void
  AccurateStitchRecord::record(const double t, const nlohmann::json &statistics)
  {
    auto               &model = *stitch.model;
    std::vector<double> row{t};
    auto               &metrics = summary.metrics();
    for (const auto &r : model.reactions(t))
      {
        for (unsigned d = 0; d < 3; ++d)
          row.push_back(r.force[d]);
        metrics["reaction_force"][r.boundary] = {r.force[0], r.force[1], r.force[2]};
      }
    const auto probes = model.probe_displacements();
    for (std::size_t p = 0; p < stitch.first_gap_probe; ++p)
      for (unsigned d = 0; d < 3; ++d)
        {
          row.push_back(probes[p][d]);
          metrics[model.probes()[p].first + "_displacement_" + std::string(1, char('x' + d))] = probes[p][d];
        }
    if (stitch.closure)
      record_gaps(t, probes, row);
    const auto &[force, torque] = stitch.load;
    for (unsigned d = 0; d < 3; ++d)
      row.push_back(force[d]);
    for (unsigned d = 0; d < 3; ++d)
      row.push_back(torque[d]);
    for (unsigned d = 0; d < 3; ++d)
      row.push_back(stitch.needle->pose().position[d]);
    if (t >= stitch.pull_start)
      peak_pull = std::max(peak_pull, force.norm());
    const auto &points = stitch.needle->pierce_points();
    for (unsigned k = 0; k < stitch.np.recorded; ++k)
      if (k < points.size())
        for (const double v :
             {points[k].slipping ? 2.0 : 1.0, points[k].anchor, points[k].slip_speed, points[k].normal, points[k].friction})
          row.push_back(v);
      else
        for (int j = 0; j < 5; ++j)
          row.push_back(0);
    if (stitch.suture)
      {
        const auto states = stitch.suture->element_states();
        row.push_back(states.front().N[0]);
        row.push_back(states.back().N[0]);
        row.push_back(stitch.stabilization_force);
        row.push_back(stitch.contact ? stitch.contact->total_force(stitch.suture->positions()) : 0.0);
        row.push_back(stitch.contact ? stitch.contact->contacts().size() : 0);
      }
    if (stitch.faces)
      {
        row.push_back(stitch.faces->total_force());
        row.push_back(stitch.faces->n_touching());
      }
    if (tears)
      {
        // before the VTU, which shows the cell ratios of this state
        tears->update(t, pull_tension(), model, stitch.needle->pierce_points(), hole_forces());
        metrics["tearing"] = tears->summary();
        row.push_back(pull_tension());
        for (const double ratio : tears->current())
          row.push_back(ratio);
        for (const double f : tears->current_forces())
          row.push_back(f);
      }
    recorder.add_row(row);
    if (stitch.scene.time.output_due(t, last_output))
      write_state(t);
    summary.step(statistics, t);
  }

  std::vector<double>
  AccurateStitchRecord::hole_forces() const
  {
    const auto         &needle = *stitch.needle;
    const auto          x      = stitch.positions();
    const std::size_t   first  = needle.first_pierce_index();
    std::vector<double> forces;
    for (std::size_t j = 0; j < needle.pierce_points().size(); ++j)
      {
        Tensor<1, 3> f;
        Tensor<2, 3> unused;
        needle.force(first + j, x[first + j], f, unused);
        forces.push_back(f.norm());
      }
    return forces;
  }

  void
  AccurateStitchRecord::write_state(const double t)
  {
    if (stitch.suture)
      write_suture_vtu(*stitch.suture, stitch.scene.suture.section.radius, output_index, t, recorder);
    last_file = stitch.model->write_vtu(recorder.directory(), output_index++, t);
    recorder.add_vtu("tissue", t, last_file);
    last_output = t;
  }

  std::string
  AccurateStitchRecord::keep(const double t)
  {
    if (last_output >= 0 && last_output < t)
      write_state(t);
    return last_file.empty() ? "" : recorder.directory() + "/" + last_file;
  }

  void
  AccurateStitchRecord::finish(const double t)
  {
    auto &metrics = summary.metrics();
    summary.needle(stitch.np, stitch.needle->all_events(), peak_pull);
    recorder.write_file("stitches.csv", tearing::stitches_csv(summary.stitch_evaluation(
                                          stitch.np, stitch.needle->all_events(), stitch.wound,
                                          stitch.scene.stitch_evaluation)));
    summary.pass_outcome(stitch.np, stitch.needle->all_events(), t, stitch.suture.has_value());
    metrics["simulated_time"] = t;
    if (stitch.suture)
      {
        // as in the realtime path: no suture node may end inside the tissue, deeper than
        // its radius below the surface, but those a stitch carries between two pierce
        // points (the FE tissue known by its deformed boundary: a winding-number test)
        const auto      &suture = *stitch.suture;
        Eigen::Matrix3Xd nodes(3, suture.positions().size());
        for (std::size_t i = 0; i < suture.positions().size(); ++i)
          nodes.col(i) = suture.positions()[i];
        const auto split = collision::split_by_tracts(
          collision::surface_penetration(stitch.x_surface, stitch.surface.triangles, nodes,
                                         stitch.scene.suture.section.radius),
          stitch.needle->thread_nodes_in_tracts());
        metrics["suture_nodes_inside_tissue"] = split.outside_tracts;
        metrics["suture_penetration_depth"]   = split.depth;
        metrics["suture_nodes_in_tracts"]     = split.in_tracts;
      }
    if (stitch.closure)
      stitch.closure->write(metrics);
    if (stitch.series)
      stitch.series->write(metrics);
  }

  nlohmann::json
  AccurateStitchRecord::snapshot() const
  {
    return {{"peak_pull", peak_pull},
            {"last_output", last_output},
            {"output_index", output_index},
            {"last_file", last_file},
            {"tearing", tears ? tears->summary() : nlohmann::json()}};
  }

  void
  AccurateStitchRecord::restore(const nlohmann::json &j)
  {
    peak_pull    = j.at("peak_pull").get<double>();
    last_output  = j.at("last_output").get<double>();
    output_index = j.at("output_index").get<unsigned>();
    last_file    = j.at("last_file").get<std::string>();
    if (tears && j.contains("tearing") && !j.at("tearing").is_null())
      tears->restore(j.at("tearing"));
    recorder.restore_summary();
  }
} // namespace suturesim::scene
