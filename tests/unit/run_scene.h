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

  /// Runs `[launcher] suturesim args --output <fresh folder>`.
  inline RunResult
  run_suturesim(const std::string &name, const std::string &args,
                const std::string &launcher = "")
  {
    namespace fs = std::filesystem;
    RunResult r;
    r.directory = (fs::temp_directory_path() / ("suturesim_test_" + name)).string();
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
