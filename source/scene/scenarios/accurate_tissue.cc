/**
 * The accurate tissue alone (Model = accurate, Bodies = tissue, no needle): the
 * finite-strain FE model of tissue/ on the scene's mesh, integrated in time by the
 * registered tissue integrator of Time/Integrator (quasi-static load stepping or IDA
 * dynamics), recorded by scene/tissue_recorder.h.
 */
#include <suturesim/scene/knot_parameters.h>
#include <suturesim/scene/run_summary.h>
#include <suturesim/scene/scenario.h>
#include <suturesim/scene/timed_run.h>
#include <suturesim/scene/tissue_recorder.h>
#include <suturesim/tissue/time_integrator.h>

#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_tools.h>

#include <iostream>

namespace suturesim::scene
{
  using namespace dealii;

  namespace
  {
    class AccurateTissue : public Scenario
    {
    public:
      AccurateTissue(ParameterHandler &prm, SceneParameters &s)
        : scene(s)
      {
        scene.scope("Closure").require(!scene.closure.present(), "Gap probes",
                                       "wound closure needs the suture in the tissue: Bodies = tissue and suture");
        KnotParameters::check(scene); // a Knot here has no suture to tie
        scene.parse_bodies(prm);
        const ParameterScope tissue = scene.scope("Tissue");
        tissue.require(scene.tissue.region_moduli.empty(), "Region moduli",
                       "layered tissue is realtime only so far: use Model = realtime");
        if (scene.tissue.formulation == "displacement" &&
            scene.material->bulk_modulus() > 1000 * scene.material->shear_modulus())
          std::cerr << "warning: " << scene.file->name()
                    << ": Tissue/Formulation = displacement with kappa/mu > 1000 locks "
                       "volumetrically; use 'mixed'\n";
        scene.parse_time(prm);
        const auto          &registry   = tissue::TimeIntegrator::Registry::instance();
        const ParameterScope time       = scene.scope("Time");
        const std::string   &integrator = scene.time.integrator;
        if (integrator != "quasi-static")
          tissue.subsection("Material")
            .require(scene.material->density() > 0, "Density",
                     "must be > 0 kg/m^3 for dynamics (Time/Integrator = " + integrator + ")");
        time.require(registry.all().count(integrator) > 0, "Integrator",
                     "'" + integrator + "' does not integrate the tissue; use " + registry.selection_pattern());
        time.require(integrator == "quasi-static" || scene.time.max_step_size <= scene.time.step_size,
                     "Max step size", "adaptive steps are quasi-static only (Time/Integrator = quasi-static)");
        tissue.subsection("Phase field")
          .require(!scene.tissue.phase_field.enabled || integrator == "quasi-static", "Enabled",
                   "the phase field's staggered update follows quasi-static steps only (Time/Integrator = " +
                     integrator + ")");
        prm.enter_subsection("Time");
        time_integrator = registry.get(integrator).create(prm, time);
        prm.leave_subsection();
      }

      void
      run(io::Recorder &recorder) override
      {
        run_timed(recorder, [&](TimerOutput &timer, ConditionalOStream &pcout) {
          MPI_Comm                                comm = MPI_COMM_WORLD;
          parallel::distributed::Triangulation<3> tria(comm);
          mesh::MeshInfo                          mesh_info;
          {
            TimerOutput::Scope section(timer, "mesh");
            mesh_info = mesh::create_mesh(scene.mesh, recorder.directory(), tria);
          }
          scene.boundary_conditions.resolve(mesh_info);
          tissue::TissueModel model(comm, scene.tissue, *scene.material, scene.boundary_conditions, tria, timer);
          model.setup();

          RunSummary summary(recorder.summary());
          summary.begin(scene);
          summary.fe_mesh(mesh_info.description, tria.n_global_active_cells(), model.n_dofs(),
                          dealii::GridTools::volume(tria), scene.tissue);
          pcout << "suturesim: scene '" << scene.name << "', " << mesh_info.description << ", "
                << tria.n_global_active_cells() << " cells, " << model.n_dofs() << " DoFs, Q" << scene.tissue.degree
                << " " << scene.tissue.formulation << ", " << Utilities::MPI::n_mpi_processes(comm)
                << " MPI process(es)\n";
          TissueRecorder observer(model, scene.time, recorder);
          time_integrator->run(model, scene.time, observer);
        });
      }

    private:
      SceneParameters                        &scene;
      std::unique_ptr<tissue::TimeIntegrator> time_integrator;
    };

    const bool registered = Scenario::Registry::instance().add(
      {"accurate tissue",
       "the finite-strain FE tissue alone, quasi-static or dynamic (Model = accurate, Bodies = tissue, "
       "no needle)",
       nullptr,
       [](const SceneParameters &s) { return s.model == "accurate" && s.bodies == "tissue" && !s.needle.present(); },
       [](ParameterHandler &prm, SceneParameters &s) { return std::unique_ptr<Scenario>(new AccurateTissue(prm, s)); }});
  } // namespace
} // namespace suturesim::scene
