#pragma once
/**
 * @file
 * A study as a Snakemake workflow (issue 24): one rule instance per case, each running
 * `suturesim study <file> --output <folder> --case <name>` (so a case runs as it does
 * under --jobs), and an aggregation rule running `suturesim study <file> --output
 * <folder>`, which finds every case done and writes the tables and figures. The rules
 * call the program with an argument vector (Python's subprocess, no shell), and each
 * case rule carries the digest of its parameters as a Snakemake param, so that a changed
 * case is run again. `snakemake --snakefile <folder>/Snakefile --cores N` runs it here, a
 * cluster profile (Slurm, …) elsewhere.
 */

#include <suturesim/study/case_run.h>

#include <string>
#include <vector>

namespace suturesim::study
{
  /// Writes <folder>/Snakefile; @p executable, @p study_file and @p folder are written
  /// as absolute paths so that the workflow runs from any working directory, and
  /// @p study_arguments (the study's --set and --only options) are passed on to every
  /// command.
  void
  export_snakemake(const std::string &executable, const std::string &study_file, const std::string &folder,
                   const std::vector<CaseJob> &jobs, const std::vector<std::string> &parameters,
                   const std::vector<std::string> &study_arguments);
} // namespace suturesim::study
