#pragma once
/**
 * @file
 * `suturesim study <study.prm> [--output DIR] [--jobs N] [--validate]
 *  [--export snakemake] [--case NAME]` (issue 24): reads and checks the study, runs the
 * cases not yet done (study/case_run.h), measures them against the reference
 * (study/case_metrics.h), writes the tables and best.prm (study/study_report.h) and the
 * figures (postprocess/study_figures.py, with Debian's python3). With --export snakemake
 * it writes a Snakefile instead (study/snakemake_export.h); --case runs one case, as the
 * Snakefile's rules do.
 */

#include <functional>
#include <string>
#include <vector>

namespace suturesim::study
{
  /// Exit codes as suturesim's: 0 done, 2 bad input (one line naming the study file and
  /// line), 1 the figures could not be drawn (the tables are written).
  int
  study_command(const std::vector<std::string> &arguments);

  /// Runs @p body, the work of suturesim's command @p name (study, calibrate), and turns
  /// what it throws into the exit codes of docs/input_errors.md with one line on stderr:
  /// an InputError 2, a failed write (io::WriteError) 5, anything else 4 ("internal
  /// error: <name>: ..."). Otherwise @p body's own code.
  int
  command_exit_code(const std::string &name, const std::function<int()> &body);

  /// The interpreter of the postprocess scripts (study figures, calibration): Debian's
  /// python3, which has numpy, matplotlib and scipy (the first python3 on a PATH may not).
  inline constexpr const char *python3 = "/usr/bin/python3";
} // namespace suturesim::study
