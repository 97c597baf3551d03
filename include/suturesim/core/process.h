#pragma once
/**
 * @file
 * Child processes started from an argument vector (posix_spawnp), never through a
 * shell: a file name, a setting or a parameter key is an argument, never a command. One
 * place for what gmsh (mesh/mesh_loader), a study's cases (study/case_run) and its
 * figures (study/study_command) need.
 */

#include <sys/types.h>

#include <string>
#include <utility>
#include <vector>

namespace suturesim
{
  /// Starts @p argv (argv[0] found on PATH unless it has a '/'); its standard output and
  /// error go to @p log (created or truncated; empty: this process's), its environment is
  /// this process's with @p environment ("NAME=value") set over it, less the variables
  /// whose names begin with a "PREFIX*" of @p environment. Returns the child's
  /// pid; throws std::runtime_error naming argv[0] when it cannot be started.
  pid_t
  start_process(const std::vector<std::string> &argv, const std::string &log = "",
                const std::vector<std::string> &environment = {});

  /// start_process() and wait: the exit status, -1 when it could not be started or did
  /// not exit normally (a signal).
  int
  run_process(const std::vector<std::string> &argv, const std::string &log = "");
} // namespace suturesim
