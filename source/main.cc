// suturesim [--validate] [--output DIR | --restart DIR] [--set "Subsection/Key=value"]... [scene.prm]
#include <suturesim/core/blas_threads.h>
#include <suturesim/core/error.h>
#include <suturesim/core/interruption.h>
#include <suturesim/core/mpi_session.h>
#include <suturesim/core/version.h>
#include <suturesim/io/checked_output.h>
#include <suturesim/scene/default_scene.h>
#include <suturesim/scene/simulation.h>
#include <suturesim/study/calibrate_command.h>
#include <suturesim/study/study_command.h>

#include <deal.II/base/exceptions.h>
#include <deal.II/base/mpi.h>
#include <deal.II/base/multithread_info.h>

#include <chrono>
#include <cstdlib>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#ifndef SUTURESIM_SOURCE_DIR
#  define SUTURESIM_SOURCE_DIR "."
#endif

namespace
{
  const char *usage =
    "usage: suturesim [--validate] [--output DIR | --restart DIR] [--set \"Subsection/Key=value\"]... "
    "[--threads N] [scene.prm]\n"
    "  scene.prm     deal.II parameter file; without it the embedded default scene runs\n"
    "  --validate    parse and check the scene, then exit (0 when valid)\n"
    "  --output DIR  output folder (default: output/<scene file stem>, output/default)\n"
    "  --restart DIR go on from the checkpoint in DIR (a run of the same scene and --set\n"
    "                into DIR that stopped, or wrote Time/Checkpoint steps); its outputs\n"
    "                continue there as if it had not stopped. Only Time/End time, the\n"
    "                checkpoint settings and the resource limits may change\n"
    "  --set S/K=V   override a parameter, e.g. --set \"Time/End time=0.5\"; it goes over\n"
    "                the file and its 'subsection Model <path>' settings; --set \"Model\n"
    "                accurate/Time/Step size=0.01\" sets that section's key instead\n"
    "  --threads N   threads per process for the accurate path's assembly (default 1; at\n"
    "                most the node's cores shared among its MPI processes, 0: all of that\n"
    "                share). Results differ from one thread's at round-off (deal.II's\n"
    "                cell-similarity shortcut is off with threads), not between counts above one\n"
    "  --help        this text and every parameter with its unit and range\n"
    "       suturesim study <study.prm> [--output DIR] [--jobs N] [--validate] [--export snakemake]\n"
    "                 runs a study's cases and measures them against its reference (docs/studies.md)\n"
    "       suturesim calibrate <calibration.prm> [--output DIR] [--jobs N] [--validate]\n"
    "                 fits realtime parameters to the study's reference (docs/calibration.md)\n";

  /// The threads per process for --threads @p asked: at most the node's cores shared
  /// among this node's MPI processes, all of that share for 0, at least one. deal.II's
  /// set_thread_limit() then also honours DEAL_II_NUM_THREADS.
  unsigned
  assembly_threads(const unsigned asked)
  {
    MPI_Comm node;
    MPI_Comm_split_type(MPI_COMM_WORLD, MPI_COMM_TYPE_SHARED, 0, MPI_INFO_NULL, &node);
    const unsigned on_node = dealii::Utilities::MPI::n_mpi_processes(node);
    MPI_Comm_free(&node);
    const unsigned share = std::max(1u, dealii::MultithreadInfo::n_cores() / on_node);
    return asked == 0 ? share : std::min(asked, share);
  }
} // namespace

int
main(int argc, char **argv)
{
  using namespace suturesim;
  select_blas_kernels(argv); // may run the program again, before anything has started
  // A study starts its cases as processes of their own: it is not an MPI process itself.
  if (argc > 1 && std::string(argv[1]) == "study")
    return study::study_command(std::vector<std::string>(argv + 2, argv + argc));
  if (argc > 1 && std::string(argv[1]) == "calibrate")
    return study::calibrate_command(std::vector<std::string>(argv + 2, argv + argc));
  // One thread per process unless --threads asks for more (below); an Open MPI singleton
  // isolated in a session directory of its own (core/mpi_session.h).
  const MpiSession mpi(argc, argv);
  limit_blas_threads();
  const bool root = dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0;

  bool                     validate = false, help = false;
  std::string              output, scene_file, restart;
  std::vector<std::string> overrides;
  for (int i = 1; i < argc; ++i)
    {
      const std::string a = argv[i];
      if (a == "--validate")
        validate = true;
      else if (a == "--help" || a == "-h")
        help = true;
      else if ((a == "--output" || a == "--set") && i + 1 < argc)
        (a == "--output" ? output : (overrides.emplace_back(), overrides.back())) = argv[++i];
      else if (a == "--restart" && i + 1 < argc)
        restart = argv[++i];
      else if (a == "--threads" && i + 1 < argc)
        {
          const std::string n = argv[++i];
          if (n.empty() || n.size() > 4 || n.find_first_not_of("0123456789") != std::string::npos)
            {
              if (root)
                std::cerr << "error: --threads " << n << ": expected a whole number 0-9999\n";
              return 2;
            }
          dealii::MultithreadInfo::set_thread_limit(assembly_threads(std::stoul(n)));
        }
      else if (a.rfind("--", 0) == 0)
        {
          if (root)
            std::cerr << "error: unknown or incomplete option '" << a << "'\n" << usage;
          return 2;
        }
      else if (scene_file.empty())
        scene_file = a;
      else
        {
          if (root)
            std::cerr << "error: more than one scene file ('" << scene_file << "', '" << a
                      << "')\n";
          return 2;
        }
    }

  dealii::ParameterHandler prm;
  scene::Simulation::declare_parameters(prm);
  if (help)
    {
      if (root)
        {
          std::cout << usage << "\nParameters (suturesim " << version_string << ", "
                    << git_commit << "):\n";
          prm.print_parameters(std::cout, dealii::ParameterHandler::Text);
        }
      return 0;
    }

  std::unique_ptr<io::Recorder> recorder;
  try
    {
      std::unique_ptr<ParameterFile> file;
      if (scene_file.empty())
        file = std::make_unique<ParameterFile>(
          prm, scene::default_scene_text,
          std::string("<default scene ") + scene::default_scene_name + ">",
          std::string(SUTURESIM_SOURCE_DIR) + "/parameters", overrides);
      else
        file = std::make_unique<ParameterFile>(
          ParameterFile::from_file(prm, scene_file, overrides));

      scene::Simulation simulation(prm, *file);
      if (validate)
        {
          if (root)
            std::cout << file->name() << ": valid\n";
          return 0;
        }

      if (!restart.empty() && !output.empty() && output != restart)
        throw InputError("--restart " + restart + ": a restart writes into its own folder, not --output " + output);
      if (!restart.empty())
        output = restart;
      if (output.empty())
        output = "output/" + (scene_file.empty() ? std::string("default")
                                                 : std::filesystem::path(scene_file).stem().string());
      recorder = std::make_unique<io::Recorder>(output, MPI_COMM_WORLD);
      if (restart.empty())
        {
          recorder->clear_stale_outputs();
          recorder->write_parameters(prm);
        }
      else
        recorder->resume(prm);
      const auto start = std::chrono::steady_clock::now();
      catch_stop_signals();
      simulation.run(*recorder);
      recorder->summary()["wall_time_seconds"] =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      // a run that ended without what its scene asked for says so (scene/run_summary.h)
      std::string incomplete;
      for (const auto &reason : recorder->summary().value("incomplete", nlohmann::json::array()))
        incomplete += (incomplete.empty() ? "" : "; ") + reason.get<std::string>();
      recorder->finish(incomplete.empty() ? "completed" : "incomplete");
      if (root)
        std::cout << "suturesim: wrote " << output << "/ (summary.json, forces.csv, "
                  << "*.pvd, parameters.prm)\n";
      if (!incomplete.empty())
        {
          if (root)
            std::cerr << "incomplete: " << incomplete << '\n';
          return 6;
        }
      return 0;
    }
  catch (const InputError &e)
    {
      if (root)
        std::cerr << "error: " << e.what() << '\n';
      return 2;
    }
  catch (const io::WriteError &e)
    {
      // no summary.json: the run's outputs are not complete (io/checked_output.h). Rank 0
      // writes the record, every rank its part of a checkpoint (io/checkpoint.h): the
      // others would wait for the one that failed in their next collective call, so with
      // several the job ends here, and the rank that failed says so.
      std::cerr << "error: " << e.what();
      if (!root)
        std::cerr << " (MPI rank " << dealii::Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) << ")";
      std::cerr << std::endl;
      if (dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1)
        MPI_Abort(MPI_COMM_WORLD, 5);
      return 5;
    }
  catch (const Interrupted &e)
    {
      // the run's outputs hold the state of the step it stopped after; the summary says
      // it is not the end time's
      if (recorder)
        recorder->finish("interrupted", e.what());
      if (root)
        std::cerr << "suturesim: " << e.what() << '\n';
      return 128 + e.signal;
    }
  catch (const SolverError &e)
    {
      if (recorder)
        recorder->finish("failed", e.what());
      if (root)
        std::cerr << "error: " << e.what() << '\n';
      return 3;
    }
  catch (const std::exception &e)
    {
      // anything else is suturesim's own fault: one line on the terminal (of a deal.II
      // exception its additional information, not its block and stack trace), the whole
      // text in the run's folder, and a summary that says so
      std::ostringstream brief;
      if (const auto *dealii_error = dynamic_cast<const dealii::ExceptionBase *>(&e))
        dealii_error->print_info(brief);
      else
        brief << e.what();
      std::string what = "internal error: " + one_line(brief.str()).substr(0, 300);
      if (recorder && root)
        {
          const std::string report = recorder->directory() + "/error.log";
          std::ofstream     out(report);
          if (out << e.what() << '\n' && out.flush())
            what += "; the full report is in " + report;
        }
      if (recorder)
        recorder->finish("failed", what);
      if (root)
        std::cerr << "error: " << what << '\n';
      return 4;
    }
}
