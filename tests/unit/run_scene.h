#pragma once
// Runs the suturesim command as a user would and reads back what it wrote.
#include <suturesim/core/process.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace suturesim::test_support
{
  /// A command as its argument vector: started without a shell, so a file name or a
  /// setting with spaces or quotes is one argument, never a command.
  using Args = std::vector<std::string>;

  /// @p a followed by @p b.
  inline Args
  join(Args a, const Args &b)
  {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  }

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

  /// The shipped scene @p relative (to the source tree) with each of @p sets given as
  /// "--set" on the command line.
  inline Args
  scene_with(const std::string &relative, const Args &sets)
  {
    Args a = {source_path(relative)};
    for (const auto &s : sets)
      {
        a.push_back("--set");
        a.push_back(s);
      }
    return a;
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

  /// scratch_path()/<stem>_<test name>, created: a folder of the running test's own, for a
  /// fixture that several tests use (ctest runs them in parallel; one shared folder let one
  /// test delete the mesh another had just written).
  inline std::filesystem::path
  test_scratch(const std::string &stem)
  {
    const auto *test = ::testing::UnitTest::GetInstance()->current_test_info();
    const auto  dir  = scratch_path() / (stem + "_" + (test ? test->name() : "none"));
    std::filesystem::create_directories(dir);
    return dir;
  }

  /// A launcher prefix for run_suturesim() that starts @p n fresh MPI processes (run_suturesim()
  /// gives a launched run mpi_environment()).
  inline Args
  mpi_launcher(const unsigned n)
  {
    return {"mpirun", "-np", std::to_string(n), "--oversubscribe"};
  }

  /// The environment of a launched run: the test process is an MPI singleton, its
  /// OMPI_/PMIX_/OPAL_ variables would make the child mpirun join it, so they are removed
  /// (start_process() removes the "PREFIX*" entries from the inherited environment only,
  /// then sets the "NAME=value" ones, so the two OMPI_ALLOW_ variables stay).
  inline Args
  mpi_environment()
  {
    return {"OMPI_*", "PMIX_*", "OPAL_*", "OMPI_ALLOW_RUN_AS_ROOT=1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1"};
  }

  /// The numeric rows of the CSV file @p path under a one-line header (checked by the
  /// caller).
  inline std::vector<std::vector<double>>
  read_numeric_csv(const std::string &path, std::string *header = nullptr)
  {
    std::ifstream csv(path);
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

  /// The numeric rows of a run's forces.csv (the header is checked by the caller).
  inline std::vector<std::vector<double>>
  read_forces(const RunResult &r, std::string *header = nullptr)
  {
    return read_numeric_csv(r.directory + "/forces.csv", header);
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

  /// How many lines of @p output begin with @p prefix (e.g. "error: ").
  inline std::size_t
  lines_starting(const std::string &output, const std::string &prefix)
  {
    std::size_t       n = 0;
    std::stringstream in(output);
    for (std::string line; std::getline(in, line);)
      n += line.rfind(prefix, 0) == 0;
    return n;
  }

  /// Runs @p argv (no shell; argv[0] found on PATH unless it has a '/') with @p environment
  /// (see start_process()) and its standard output and error into @p log; its exit code
  /// (-1 if it could not be started or did not exit), the output in @p output.
  inline int
  run_logged(const Args &argv, const std::string &log, std::string &output, const Args &environment = {})
  {
    int status = -1;
    try
      {
        const pid_t pid = start_process(argv, log, environment);
        if (waitpid(pid, &status, 0) != pid)
          status = -1;
        output = read_text(log);
      }
    catch (const std::runtime_error &e)
      {
        output = e.what();
        return -1;
      }
    return status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }

  /// Runs `[launcher...] suturesim args... --output <fresh folder>`; a run launched by
  /// mpirun (mpi_launcher()) gets mpi_environment(), any other launcher (such as
  /// `/usr/bin/env -C <folder>`) this process's environment.
  inline RunResult
  run_suturesim(const std::string &name, const Args &args, const Args &launcher = {})
  {
    namespace fs = std::filesystem;
    RunResult r;
    r.directory = (scratch_path() / name).string();
    fs::remove_all(r.directory);
    r.exit_code = run_logged(join(join(launcher, join({suturesim_binary()}, args)), {"--output", r.directory}),
                             r.directory + ".log", r.output,
                             !launcher.empty() && launcher.front() == "mpirun" ? mpi_environment() : Args{});
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
