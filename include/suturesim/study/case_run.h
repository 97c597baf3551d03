#pragma once
/**
 * @file
 * Running a study's cases on this machine (issue 24). Each case is an ordinary suturesim
 * run in its own folder, started as a child process from an argument vector
 * (posix_spawn, never a shell: a setting cannot run a command), its standard output and
 * error in `log.txt`, and its outcome in `run.json`: exit code, status (completed,
 * failed = a solver that gave up or a diverged realtime run, refused = input the run
 * rejected, crashed), the error line, wall time, processor time of the process and its
 * children (user + system, from wait4) and peak resident memory.
 *
 * A case is done when its folder holds run.json of the same parameters (a digest of
 * every parameter with its value, as the scene file and the case's settings give them)
 * and, for a run that started, its parameters.prm and summary.json: a rerun of an
 * unchanged study runs nothing again, and a changed setting runs only the cases it
 * changes. (The digest is of the parsed parameters, before a scenario fills in what
 * they imply, e.g. a suture preset's radius: the run's parameters.prm shows those.)
 */

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

namespace suturesim::study
{
  struct CaseOutcome
  {
    /// completed | failed | refused | crashed | not run | interrupted; incomplete: the
    /// run said so (exit 6: it ended without what its scene asked for), or, set by the
    /// metrics, it completed without a metric the reference has; no reference: set by
    /// the report, it completed but its own reference failed (Reference/On failure)
    std::string status = "not run";
    std::string reason;             ///< the run's error line, when not completed
    int         exit_code         = -1;
    double      wall_seconds      = 0; ///< s
    double      cpu_seconds       = 0; ///< user + system time, s
    double      peak_memory_bytes = 0; ///< peak resident set, bytes
    bool        reused            = false; ///< found complete, not run again
  };

  /// One case to run: its folder and the suturesim arguments after the executable.
  struct CaseJob
  {
    std::string              name;
    std::string              folder;
    std::string              scene;
    std::vector<std::string> settings;
    /// MPI processes of the run (Reference/Processes): above 1, under mpirun -np.
    unsigned processes = 1;
  };

  /// Every parameter of a run of @p settings over @p scene, with its value, as text.
  std::string
  case_parameters(const std::string &scene, const std::vector<std::string> &settings);

  /// The recorded outcome if @p job's folder holds a complete run of @p parameters.
  std::optional<CaseOutcome>
  completed_run(const CaseJob &job, const std::string &parameters);

  /// Runs @p jobs with @p executable (suturesim), at most @p concurrency processes at a
  /// time (a job of CaseJob::processes k takes k of them; one above @p concurrency runs
  /// alone), and writes each one's run.json; a line on @p progress after each start and
  /// end (done, running, failed, estimated time left). Returns the outcomes in job order.
  std::vector<CaseOutcome>
  run_cases(const std::string &executable, const std::vector<CaseJob> &jobs,
            const std::vector<std::string> &parameters, unsigned concurrency, std::ostream &progress);

  /// The value of `--jobs` @p text (study, calibrate): a whole number of cases run at
  /// once, 1–256; an InputError naming it otherwise.
  unsigned
  jobs_argument(const std::string &text);

  /// FNV-1a, 64 bit, as 16 hexadecimal digits: a stable digest across builds.
  std::string
  digest(const std::string &text);
} // namespace suturesim::study
