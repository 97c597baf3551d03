#pragma once
// Runs the suturesim command as a user would and reads back what it wrote.
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace suturesim::test_support
{
  struct RunResult
  {
    int            exit_code = -1;
    std::string    output; // stdout and stderr
    std::string    directory;
    bool           has_summary = false;
    nlohmann::json summary;
  };

  inline std::string
  source_path(const std::string &relative)
  {
    return std::string(SUTURESIM_SOURCE_DIR) + "/" + relative;
  }

  /// A launcher prefix for run_suturesim() that starts @p n fresh MPI processes. The test
  /// process is an MPI singleton: its OMPI_/PMIX_ variables would make the child mpirun
  /// join it, so they are removed first.
  inline std::string
  mpi_launcher(const unsigned n)
  {
    return "for v in $(env | cut -d= -f1 | grep -E '^(OMPI_|PMIX_|OPAL_)'); do unset $v; "
           "done; OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 mpirun -np " +
           std::to_string(n) + " --oversubscribe";
  }

  /// The numeric rows of a run's forces.csv (the header is checked by the caller).
  inline std::vector<std::vector<double>>
  read_forces(const RunResult &r, std::string *header = nullptr)
  {
    std::ifstream csv(r.directory + "/forces.csv");
    std::string   first;
    std::getline(csv, first);
    if (header != nullptr)
      *header = first;
    std::vector<std::vector<double>> rows;
    for (std::string line; std::getline(csv, line);)
      {
        std::stringstream   s(line);
        std::vector<double> v;
        for (std::string cell; std::getline(s, cell, ',');)
          v.push_back(std::stod(cell));
        rows.push_back(v);
      }
    return rows;
  }

  /// Runs `[launcher] suturesim args --output <fresh folder>`. The folder is in the build
  /// tree that holds the suturesim binary (test_runs/<name>), not in /tmp: two build
  /// trees, or two clones, testing at once on one machine must not share it.
  inline RunResult
  run_suturesim(const std::string &name, const std::string &args,
                const std::string &launcher = "")
  {
    namespace fs = std::filesystem;
    RunResult r;
    r.directory = (fs::path(SUTURESIM_BINARY).parent_path() / "test_runs" / name).string();
    fs::create_directories(fs::path(r.directory).parent_path());
    fs::remove_all(r.directory);
    const std::string log = r.directory + ".log";
    const std::string cmd = launcher + " " + SUTURESIM_BINARY + " " + args + " --output '" +
                            r.directory + "' > '" + log + "' 2>&1";
    const int status = std::system(cmd.c_str());
    r.exit_code      = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    std::ifstream      in(log);
    std::stringstream  s;
    s << in.rdbuf();
    r.output = s.str();
    const fs::path summary = fs::path(r.directory) / "summary.json";
    if (fs::exists(summary))
      {
        r.has_summary = true;
        std::ifstream js(summary);
        js >> r.summary;
      }
    return r;
  }
} // namespace suturesim::test_support
