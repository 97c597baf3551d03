#pragma once
// Runs the suturesim command as a user would and reads back what it wrote.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

namespace suturesim::test_support
{
  /// The source tree, the suturesim binary and the scratch folder of this build
  /// (tests/unit/test_paths.cc: the one file compiled with these paths, so that the other
  /// test files' compiler-cache entries do not depend on where the tree is checked out).
  const char *
  source_directory();
  const char *
  suturesim_binary();
  const char *
  scratch_directory();

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
    return std::string(source_directory()) + "/" + relative;
  }

  /// The scene of a benchmark folder: benchmarks/<name>/<name>.prm.
  inline std::string
  benchmark_scene(const std::string &name)
  {
    return source_path("benchmarks/" + name + "/" + name + ".prm");
  }

  /// benchmarks/<name>/reference.json: the benchmark's reference values with their
  /// source and tolerances, the one place where these numbers are written (the folder's
  /// compare.py reads the same file).
  inline nlohmann::json
  benchmark_reference(const std::string &name)
  {
    std::ifstream  in(source_path("benchmarks/" + name + "/reference.json"));
    nlohmann::json reference;
    in >> reference;
    return reference;
  }

  /// The folder the tests write their runs into: one per build tree (not the machine's
  /// shared temporary folder, where two builds' test runs of the same scene cleared
  /// and read each other's outputs).
  inline std::filesystem::path
  scratch_path()
  {
    const std::filesystem::path dir(scratch_directory());
    std::filesystem::create_directories(dir);
    return dir;
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

  /// The index of the first column of a forces.csv @p header whose name starts with
  /// @p name (names carry their unit, "x [m]"); a test failure if there is none.
  inline std::size_t
  column(const std::string &header, const std::string &name)
  {
    std::stringstream list(header);
    std::size_t       k = 0;
    for (std::string entry; std::getline(list, entry, ','); ++k)
      if (entry.rfind(name, 0) == 0)
        return k;
    ADD_FAILURE() << "no column " << name;
    return 0;
  }

  /// The value of "Sub/Sub/Key" in the run's parameters.prm (every value the run used);
  /// empty when the key is not there.
  inline std::string
  run_parameter(const RunResult &r, const std::string &path)
  {
    const auto trim = [](std::string s) {
      const auto a = s.find_first_not_of(" \t");
      const auto b = s.find_last_not_of(" \t");
      return a == std::string::npos ? std::string() : s.substr(a, b - a + 1);
    };
    std::ifstream            prm(r.directory + "/parameters.prm");
    std::vector<std::string> sections;
    for (std::string line; std::getline(prm, line);)
      {
        line = trim(line.substr(0, line.find('#')));
        if (line.rfind("subsection ", 0) == 0)
          sections.push_back(trim(line.substr(11)));
        else if (line == "end" && !sections.empty())
          sections.pop_back();
        else if (line.rfind("set ", 0) == 0 && line.find('=') != std::string::npos)
          {
            std::string key = trim(line.substr(4, line.find('=') - 4));
            for (auto s = sections.rbegin(); s != sections.rend(); ++s)
              key = *s + "/" + key;
            if (key == path)
              return trim(line.substr(line.find('=') + 1));
          }
      }
    return "";
  }

  /// The whole text of @p file ("" if it cannot be read).
  inline std::string
  read_text(const std::string &file)
  {
    std::ifstream     in(file);
    std::stringstream s;
    s << in.rdbuf();
    return s.str();
  }

  /// Runs the shell command @p command with its output into @p log; its exit code (-1 if
  /// it did not exit), the output in @p output.
  inline int
  run_logged(const std::string &command, const std::string &log, std::string &output)
  {
    const int status = std::system((command + " > '" + log + "' 2>&1").c_str());
    output           = read_text(log);
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  /// Runs `[launcher] suturesim args --output <fresh folder>`.
  inline RunResult
  run_suturesim(const std::string &name, const std::string &args,
                const std::string &launcher = "")
  {
    namespace fs = std::filesystem;
    RunResult r;
    r.directory = (scratch_path() / name).string();
    fs::remove_all(r.directory);
    r.exit_code = run_logged(launcher + " " + suturesim_binary() + " " + args + " --output '" + r.directory + "'",
                             r.directory + ".log", r.output);
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
