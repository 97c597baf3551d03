#include <suturesim/tissue/time_integrator.h>

#include <iomanip>
#include <iostream>
#include <sstream>

namespace suturesim::tissue
{
  void
  TimeParameters::declare(dealii::ParameterHandler &prm,
                          const std::map<std::string, std::string> &other_integrators)
  {
    const TimeParameters d;
    const auto          &integrators = TimeIntegrator::Registry::instance();
    std::string          pattern     = integrators.selection_pattern();
    std::string          doc         = "Time integration. Tissue: " + integrators.documentation();
    if (!other_integrators.empty())
      doc += "Suture: ";
    for (const auto &[name, description] : other_integrators)
      {
        if (integrators.all().count(name) == 0)
          pattern += "|" + name;
        doc += "'" + name + "': " + description + " ";
      }
    prm.declare_entry("Integrator", d.integrator, dealii::Patterns::Selection(pattern), doc);
    prm.declare_entry("End time",
                      "1",
                      dealii::Patterns::Double(0),
                      "Simulated time at the end of the run (for quasi-static runs the "
                      "load parameter of the boundary-condition functions). Unit: s. "
                      "Range: > 0.");
    prm.declare_entry("Step size",
                      "0.1",
                      dealii::Patterns::Double(0),
                      "Load step (quasi-static) or initial step (IDA). Unit: s. Range: > 0.");
    prm.declare_entry("Max cutbacks",
                      "6",
                      dealii::Patterns::Integer(0, 30),
                      "Consecutive halvings of a failing quasi-static step before the run "
                      "stops. Unit: 1. Range: 0-30.");
    prm.declare_entry("Output interval",
                      "0",
                      dealii::Patterns::Double(0),
                      "Simulated time between VTU outputs; 0 writes every step (quasi-"
                      "static) or every 'Step size' (IDA). Unit: s. Range: >= 0.");
    for (const auto &[name, entry] : integrators.all())
      if (entry.declare_parameters)
        entry.declare_parameters(prm);
  }

  void
  TimeParameters::parse(const dealii::ParameterHandler &prm, const ParameterScope &scope)
  {
    integrator      = prm.get("Integrator");
    end_time        = prm.get_double("End time");
    step_size       = prm.get_double("Step size");
    max_cutbacks    = prm.get_integer("Max cutbacks");
    output_interval = prm.get_double("Output interval");
    scope.require(end_time > 0, "End time", "must be > 0 s");
    scope.require(step_size > 0, "Step size", "must be > 0 s");
    scope.require(step_size <= end_time, "Step size", "must not exceed the end time");
  }

  void
  TimeIntegrator::record(TissueModel                &model,
                         io::Recorder               &recorder,
                         const TimeParameters       &time,
                         const double                t,
                         nlohmann::json              statistics,
                         const TissueModel::Vector *velocity,
                         const TissueModel::Vector *acceleration)
  {
    const auto reactions = model.reactions(t, velocity, acceleration);
    const auto probes    = model.probe_displacements();
    std::vector<double> row{t};
    auto &metrics = recorder.summary()["metrics"];
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

    const bool due = time.output_interval <= 0 || last_output_time < 0 ||
                     t >= last_output_time + time.output_interval * (1 - 1e-9) ||
                     t >= time.end_time * (1 - 1e-12);
    if (due)
      {
        last_output_file = model.write_vtu(recorder.directory(), output_index++, t);
        recorder.add_vtu("tissue", t, last_output_file);
        last_output_time = t;
      }
    statistics["time"] = t;
    recorder.summary()["steps"].push_back(statistics);
    last_converged_time = t;
  }

  void
  TimeIntegrator::progress(const unsigned     step,
                           const unsigned     expected_steps,
                           const double       t,
                           const double       end_time,
                           const std::string &solver_info)
  {
    if (dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) != 0)
      return;
    const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double eta = t > 0 ? elapsed * (end_time - t) / t : 0;
    std::ostringstream s;
    s << "step " << step << "/" << expected_steps << "  t = " << std::setprecision(4) << t
      << " s  " << solver_info << "  elapsed " << std::fixed << std::setprecision(1)
      << elapsed << " s  ETA " << eta << " s";
    std::cout << s.str() << std::endl;
  }
} // namespace suturesim::tissue
