#include <suturesim/io/surface_field.h>
#include <suturesim/scene/run_summary.h>
#include <suturesim/scene/tissue_recorder.h>

#include <stdexcept>

namespace suturesim::scene
{
  TissueRecorder::TissueRecorder(tissue::TissueModel &model, const TimeParameters &time, io::Recorder &recorder)
    : model(model)
    , time(time)
    , recorder(recorder)
  {
    std::vector<std::string> columns{"time [s]"};
    for (const auto &d : model.boundary_conditions().dirichlet)
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(d.name + "_reaction_" + std::string(1, c) + " [N]");
    for (const auto &[name, point] : model.probes())
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(name + "_displacement_" + std::string(1, c) + " [m]");
    recorder.set_columns(columns);
  }

  void
  TissueRecorder::accepted(const double t, const nlohmann::json &statistics,
                           const tissue::TissueModel::Vector *velocity,
                           const tissue::TissueModel::Vector *acceleration)
  {
    const auto          reactions = model.reactions(t, velocity, acceleration);
    const auto          probes    = model.probe_displacements();
    std::vector<double> row{t};
    auto               &metrics = recorder.summary()["metrics"];
    for (const auto &r : reactions)
      {
        for (unsigned d = 0; d < 3; ++d)
          row.push_back(r.force[d]);
        metrics["reaction_force"][r.boundary] = {r.force[0], r.force[1], r.force[2]};
      }
    for (std::size_t p = 0; p < probes.size(); ++p)
      {
        const std::string &name = model.probes()[p].first;
        for (unsigned d = 0; d < 3; ++d)
          {
            row.push_back(probes[p][d]);
            metrics[name + "_displacement_" + std::string(1, char('x' + d))] = probes[p][d];
          }
        metrics["probes"][name] = {probes[p][0], probes[p][1], probes[p][2]};
      }
    recorder.add_row(row);

    if (time.output_due(t, last_output))
      {
        last_file = model.write_vtu(recorder.directory(), output_index++, t);
        recorder.add_vtu("tissue", t, last_file);
        last_output = t;
      }
    RunSummary(recorder.summary()).step(statistics, t);
    last_accepted = t;
    any           = true;
  }

  void
  TissueRecorder::write_surface() const
  {
    if (!any)
      return;
    const tissue::BoundarySurface surface = model.boundary_surface(); // collective
    Eigen::Matrix3Xd x;
    model.surface_positions(surface, x); // collective
    if (recorder.is_root())
      io::SurfaceField::of(last_accepted, surface.reference, x - surface.reference, surface.triangles)
        .write(recorder.directory() + "/surface_displacement.json");
  }

  std::string
  TissueRecorder::keep_last_accepted()
  {
    write_surface();
    if (any && last_output < last_accepted)
      {
        last_file = model.write_vtu(recorder.directory(), output_index++, last_accepted);
        recorder.add_vtu("tissue", last_accepted, last_file);
        last_output = last_accepted;
      }
    return last_file.empty() ? "" : recorder.directory() + "/" + last_file;
  }

  void
  TissueRecorder::totals(const nlohmann::json &solver)
  {
    write_surface();
    RunSummary summary(recorder.summary());
    summary.solver(solver);
    summary.factorization(model.linear_solver().statistics());
  }
} // namespace suturesim::scene
