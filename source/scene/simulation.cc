#include <suturesim/core/error.h>
#include <suturesim/scene/accurate_needle_pass.h>
#include <suturesim/scene/simulation.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>

#include <iostream>

namespace suturesim::scene
{
  using namespace dealii;

  void
  Simulation::declare_parameters(ParameterHandler &prm)
  {
    prm.declare_entry("Scene name",
                      "scene",
                      Patterns::Anything(),
                      "Name recorded in summary.json. Unit: none.");
    prm.declare_entry("Model",
                      "accurate",
                      Patterns::Selection("accurate|realtime"),
                      "Model path: 'accurate' (finite-strain hyperelastic FE tissue, "
                      "deal.II + PETSc, implicit; geometrically exact Cosserat-rod suture) or "
                      "'realtime' (the seed papers' reduced models at haptic rate; subsection "
                      "Realtime).");
    prm.declare_entry("Bodies",
                      "tissue",
                      Patterns::Selection("tissue|suture|tissue and suture"),
                      "What the scene simulates: 'tissue' (subsections Mesh, Tissue), "
                      "'suture' (subsection Suture), or both in contact ('tissue and "
                      "suture'; the accurate path couples them through a needle's pierce "
                      "points, the suture attached at its swage). "
                      "Unit: none.");
    prm.enter_subsection("Suture");
    rod::RodParameters::declare(prm);
    prm.leave_subsection();
    prm.enter_subsection("Mesh");
    mesh::MeshParameters::declare(prm);
    prm.leave_subsection();
    prm.enter_subsection("Tissue");
    tissue::TissueParameters::declare(prm);
    prm.enter_subsection("Material");
    tissue::Material::declare_parameters(prm);
    prm.leave_subsection();
    prm.enter_subsection("Boundary conditions");
    tissue::BoundaryConditions::declare(prm);
    prm.leave_subsection();
    prm.leave_subsection();
    prm.enter_subsection("Time");
    std::map<std::string, std::string> rod_integrators;
    for (const auto &[name, entry] : rod::RodIntegrator::Registry::instance().all())
      rod_integrators[name] = entry.description;
    tissue::TimeParameters::declare(prm, rod_integrators);
    for (const auto &[name, entry] : rod::RodIntegrator::Registry::instance().all())
      if (entry.declare_parameters)
        entry.declare_parameters(prm);
    prm.leave_subsection();
    prm.enter_subsection("Realtime");
    RealtimeScene::declare(prm);
    prm.leave_subsection();
    NeedleParameters::declare(prm);
    ClosureParameters::declare(prm);
  }

  Simulation::Simulation(ParameterHandler &prm, const ParameterFile &file)
    : file(file)
  {
    const ParameterScope root(file, "");
    scene_name = prm.get("Scene name");
    model_path = prm.get("Model");
    bodies     = prm.get("Bodies");
    needle_parameters.parse(prm, root);
    closure_parameters.parse(prm, root);
    if (model_path == "realtime")
      {
        parse_realtime(prm);
        return;
      }
    ParameterScope(file, "Closure")
      .require(!closure_parameters.present() || bodies == "tissue and suture", "Gap probes",
               "wound closure needs the suture in the tissue: Bodies = tissue and suture");
    root.require(bodies != "tissue and suture" || (needle_parameters.present() && needle_parameters.attach_suture),
                 "Bodies",
                 "the accurate path couples tissue and suture through a needle's pierce points: "
                 "set Needle/Shape and Needle/Attach suture = true, or use Model = realtime");
    ParameterScope(file, "Needle")
      .require(!needle_parameters.present() || bodies != "suture", "Shape",
               "the needle needs the tissue (Bodies = tissue, or tissue and suture)");
    if (bodies == "tissue and suture")
      {
        prm.enter_subsection("Suture");
        rod_parameters.parse(prm, root.subsection("Suture"));
        prm.leave_subsection();
        root.subsection("Suture/Start end")
          .require(rod_parameters.start_end.type == "free", "Type",
                   "must be free: the needle holds the suture's start (Needle/Attach suture)");
      }

    if (bodies == "suture")
      {
        prm.enter_subsection("Suture");
        rod_parameters.parse(prm, root.subsection("Suture"));
        prm.leave_subsection();
        for (const auto &[name, end] : {std::pair{"Suture/Start end", &rod_parameters.start_end},
                                        std::pair{"Suture/Last end", &rod_parameters.last_end}})
          root.subsection(name).require(end->grasp_time == 0, "Grasp time",
                                        "a grasp during the run is realtime only (Model = realtime)");
        prm.enter_subsection("Time");
        const ParameterScope time = root.subsection("Time");
        time_parameters.parse(prm, time);
        const auto &registry = rod::RodIntegrator::Registry::instance();
        time.require(registry.all().count(time_parameters.integrator) > 0, "Integrator",
                     "'" + time_parameters.integrator + "' does not integrate a suture; use " +
                       registry.selection_pattern());
        if (time_parameters.integrator != "quasi-static")
          root.subsection("Suture/Cross section")
            .require(rod_parameters.section.density > 0, "Density",
                     "must be > 0 kg/m^3 for dynamics (Time/Integrator = " +
                       time_parameters.integrator + ")");
        rod_integrator = registry.get(time_parameters.integrator).create(prm, time);
        prm.leave_subsection();
        return;
      }

    prm.enter_subsection("Mesh");
    mesh_parameters.parse(prm, root.subsection("Mesh"));
    prm.leave_subsection();

    prm.enter_subsection("Tissue");
    const ParameterScope tissue = root.subsection("Tissue");
    tissue_parameters.parse(prm, tissue);
    tissue.require(tissue_parameters.region_moduli.empty(), "Region moduli",
                   "layered tissue is realtime only so far: use Model = realtime");
    prm.enter_subsection("Material");
    material.emplace(tissue::Material::parse_parameters(prm, tissue.subsection("Material")));
    prm.leave_subsection();
    prm.enter_subsection("Boundary conditions");
    boundary_conditions.parse(prm, tissue.subsection("Boundary conditions"));
    prm.leave_subsection();
    prm.leave_subsection();
    if (tissue_parameters.formulation == "displacement" && material->bulk_modulus() > 1000 * material->shear_modulus())
      std::cerr << "warning: " << file.name()
                << ": Tissue/Formulation = displacement with kappa/mu > 1000 locks "
                   "volumetrically; use 'mixed'\n";

    prm.enter_subsection("Time");
    const ParameterScope time = root.subsection("Time");
    time_parameters.parse(prm, time);
    if (time_parameters.integrator != "quasi-static")
      tissue.subsection("Material").require(material->density() > 0, "Density",
                                            "must be > 0 kg/m^3 for dynamics (Time/Integrator = " +
                                              time_parameters.integrator + ")");
    const auto &registry = tissue::TimeIntegrator::Registry::instance();
    time.require(registry.all().count(time_parameters.integrator) > 0, "Integrator",
                 "'" + time_parameters.integrator + "' does not integrate the tissue; use " +
                   registry.selection_pattern());
    integrator = registry.get(time_parameters.integrator).create(prm, time);
    prm.leave_subsection();
  }

  void
  Simulation::parse_realtime(ParameterHandler &prm)
  {
    const ParameterScope root(file, "");
    RealtimeInputs       inputs;
    inputs.scene_name = scene_name;
    inputs.tissue     = bodies != "suture";
    inputs.suture     = bodies != "tissue";
    if (inputs.suture)
      {
        prm.enter_subsection("Suture");
        rod_parameters.parse(prm, root.subsection("Suture"));
        prm.leave_subsection();
        inputs.rod = &rod_parameters;
      }
    if (inputs.tissue)
      {
        prm.enter_subsection("Mesh");
        mesh_parameters.parse(prm, root.subsection("Mesh"));
        prm.leave_subsection();
        prm.enter_subsection("Tissue");
        const ParameterScope tissue = root.subsection("Tissue");
        tissue_parameters.parse(prm, tissue);
        prm.enter_subsection("Material");
        material.emplace(tissue::Material::parse_parameters(prm, tissue.subsection("Material")));
        prm.leave_subsection();
        prm.enter_subsection("Boundary conditions");
        boundary_conditions.parse(prm, tissue.subsection("Boundary conditions"));
        prm.leave_subsection();
        prm.leave_subsection();
        inputs.mesh                = &mesh_parameters;
        inputs.material            = &*material;
        inputs.boundary_conditions = &boundary_conditions;
        inputs.probes              = tissue_parameters.probes;
        inputs.region_moduli       = tissue_parameters.region_moduli;
      }
    // The realtime step is 1/Rate; of Time only the end and the output interval apply.
    prm.enter_subsection("Time");
    time_parameters.end_time        = prm.get_double("End time");
    time_parameters.output_interval = prm.get_double("Output interval");
    root.subsection("Time").require(time_parameters.end_time > 0, "End time", "must be > 0 s");
    prm.leave_subsection();
    inputs.time = &time_parameters;
    if (needle_parameters.present())
      {
        inputs.needle = &needle_parameters;
        if (inputs.suture && needle_parameters.attach_suture)
          root.subsection("Suture/Start end")
            .require(rod_parameters.start_end.type == "free", "Type",
                     "must be free: the needle holds the suture's start (Needle/Attach suture)");
      }
    inputs.closure = closure_parameters.present() ? &closure_parameters : nullptr;
    prm.enter_subsection("Realtime");
    realtime = std::make_unique<RealtimeScene>(prm, root.subsection("Realtime"), std::move(inputs));
    prm.leave_subsection();
  }

  void
  Simulation::run(io::Recorder &recorder)
  {
    if (realtime)
      {
        realtime->run(recorder);
        return;
      }
    // A failure is rethrown only after the timer has printed its table (its destructor
    // refuses to communicate while an exception is in flight).
    std::exception_ptr failure;
    {
      MPI_Comm           comm = MPI_COMM_WORLD;
      ConditionalOStream pcout(std::cout, Utilities::MPI::this_mpi_process(comm) == 0);
      // The table is printed for completed and for failed solves, not for bad input
      // (whose one-line error must stay the only output).
      TimerOutput timer(comm, pcout, TimerOutput::never, TimerOutput::wall_times);
      try
        {
          if (bodies == "suture")
            run_suture(recorder, timer, pcout);
          else
            run(recorder, timer, pcout);
          timer.print_summary();
        }
      catch (const SolverError &)
        {
          timer.print_summary();
          failure = std::current_exception();
        }
      catch (...)
        {
          failure = std::current_exception();
        }
    }
    if (failure)
      std::rethrow_exception(failure);
  }

  void
  Simulation::run(io::Recorder &recorder, TimerOutput &timer, ConditionalOStream &pcout)
  {
    if (needle_parameters.present())
      {
        AccurateNeedleInputs inputs{scene_name,          file.name(),      &mesh_parameters,
                                    &tissue_parameters,  &*material,       &boundary_conditions,
                                    &time_parameters,    &needle_parameters,
                                    bodies == "tissue and suture" ? &rod_parameters : nullptr,
                                    closure_parameters.present() ? &closure_parameters : nullptr};
        run_accurate_needle_pass(inputs, recorder, timer, pcout);
        auto &timings = recorder.summary()["timings"];
        for (const auto &[section, seconds] : timer.get_summary_data(TimerOutput::total_wall_time))
          timings[section] = seconds;
        return;
      }
    MPI_Comm comm = MPI_COMM_WORLD;

    parallel::distributed::Triangulation<3> tria(comm);
    mesh::MeshInfo                           mesh_info;
    {
      TimerOutput::Scope scope(timer, "mesh");
      mesh_info = mesh::create_mesh(mesh_parameters, recorder.directory(), tria);
    }
    boundary_conditions.resolve(mesh_info);

    tissue::TissueModel model(comm, tissue_parameters, *material, boundary_conditions, tria,
                              timer);
    model.setup();

    auto &summary            = recorder.summary();
    summary["scene"]         = scene_name;
    summary["scene_file"]    = file.name();
    summary["model"]         = model_path;
    summary["mesh"]          = {{"description", mesh_info.description},
                                {"cells", tria.n_global_active_cells()},
                                {"dofs", model.n_dofs()},
                                {"element_degree", tissue_parameters.degree},
                                {"formulation", tissue_parameters.formulation}};
    summary["metrics"]       = nlohmann::json::object();
    summary["steps"]         = nlohmann::json::array();
    pcout << "suturesim: scene '" << scene_name << "', " << mesh_info.description << ", "
          << tria.n_global_active_cells() << " cells, " << model.n_dofs() << " DoFs, Q"
          << tissue_parameters.degree << " " << tissue_parameters.formulation << ", "
          << Utilities::MPI::n_mpi_processes(comm) << " MPI process(es)\n";

    std::vector<std::string> columns{"time [s]"};
    for (const auto &d : boundary_conditions.dirichlet)
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(d.name + "_reaction_" + std::string(1, c) + " [N]");
    for (const auto &[name, point] : model.probes())
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(name + "_displacement_" + std::string(1, c) + " [m]");
    recorder.set_columns(columns);

    integrator->run(model, time_parameters, recorder);

    auto &timings = summary["timings"];
    for (const auto &[section, seconds] : timer.get_summary_data(TimerOutput::total_wall_time))
      timings[section] = seconds;
    summary["solver"]["linear_solver"] = tissue_parameters.linear.method +
                                         (tissue_parameters.linear.method == "direct"
                                            ? std::string(" (MUMPS)")
                                            : "+" + tissue_parameters.linear.preconditioner);
  }

  void
  Simulation::run_suture(io::Recorder &recorder, TimerOutput &timer, ConditionalOStream &pcout)
  {
    rod::RodProblem problem(rod_parameters, time_parameters, recorder);
    const auto     &section = rod_parameters.section;
    const auto      k       = section.stiffness();
    auto           &summary = recorder.summary();
    summary["scene"]        = scene_name;
    summary["scene_file"]   = file.name();
    summary["model"]        = model_path;
    summary["bodies"]       = bodies;
    summary["suture"]       = {{"elements", problem.model.n_elements()},
                               {"centreline", rod_parameters.centreline},
                               {"preset", rod_parameters.preset},
                               {"radius", section.radius},
                               {"EA", k.force[0]},
                               {"GA", k.force[1]},
                               {"EI", k.moment[1]},
                               {"GJ", k.moment[0]},
                               {"self_contact", rod_parameters.contact.enabled}};
    summary["metrics"]      = nlohmann::json::object();
    summary["steps"]        = nlohmann::json::array();
    pcout << "suturesim: scene '" << scene_name << "', suture of " << problem.model.n_elements()
          << " Cosserat rod elements (" << rod_parameters.centreline << "), EI = " << k.moment[1]
          << " N m^2, " << time_parameters.integrator << "\n";
    {
      TimerOutput::Scope scope(timer, "suture");
      rod_integrator->run(problem);
    }
    summary["solver"]["linear_solver"] = rod_parameters.contact.enabled
                                           ? "block-tridiagonal LU; sparse LU with contact"
                                           : "block-tridiagonal LU";
    auto &timings = summary["timings"];
    for (const auto &[section_name, seconds] : timer.get_summary_data(TimerOutput::total_wall_time))
      timings[section_name] = seconds;
  }
} // namespace suturesim::scene
