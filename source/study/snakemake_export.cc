#include <suturesim/core/error.h>
#include <suturesim/study/snakemake_export.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>

namespace suturesim::study
{
  namespace fs = std::filesystem;

  namespace
  {
    /// A Python string literal (JSON's escapes are Python's).
    std::string
    literal(const std::string &s)
    {
      return nlohmann::json(s).dump();
    }
  } // namespace

  void
  export_snakemake(const std::string &executable, const std::string &study_file, const std::string &folder,
                   const std::vector<CaseJob> &jobs, const std::vector<std::string> &parameters,
                   const std::vector<std::string> &study_arguments)
  {
    const nlohmann::json settings = study_arguments;
    const std::string out = fs::absolute(folder).lexically_normal().string();
    const std::string file = (fs::path(folder) / "Snakefile").string();
    std::ofstream     s(file);
    s << "# A suturesim study as a Snakemake workflow, written by\n"
      << "#   suturesim study " << study_file << " --output " << folder << " --export snakemake\n"
      << "# Run: snakemake --snakefile " << file << " --cores N   (or with a cluster profile)\n"
      << "import subprocess\n\n"
      << "SUTURESIM = " << literal(fs::absolute(executable).string()) << "\n"
      << "STUDY = " << literal(fs::absolute(study_file).lexically_normal().string()) << "\n"
      << "OUT = " << literal(out) << "\n"
      << "SETTINGS = " << settings.dump() << "\n"
      << "# each case with the digest of its parameters: a changed case is run again\n"
      << "CASES = {\n";
    for (std::size_t k = 0; k < jobs.size(); ++k)
      s << "    " << literal(jobs[k].name) << ": " << literal(digest(parameters[k])) << ",\n";
    s << "}\n"
      << "# the MPI processes of each case's run (Reference/Processes): its cores\n"
      << "PROCESSES = {\n";
    for (const auto &job : jobs)
      s << "    " << literal(job.name) << ": " << job.processes << ",\n";
    s << "}\n\n"
      << "wildcard_constraints:\n    name=\"[A-Za-z0-9._-]+\"\n\n"
      << "rule all:\n    input: OUT + \"/cases.csv\"\n\n"
      << "rule run_case:\n"
      << "    output: OUT + \"/cases/{name}/run.json\"\n"
      << "    params: digest=lambda w: CASES[w.name]\n"
      << "    threads: lambda w: PROCESSES[w.name]\n"
      << "    run:\n"
      << "        subprocess.run([SUTURESIM, \"study\", STUDY, \"--output\", OUT, \"--case\", wildcards.name,"
         " \"--jobs\", str(threads)] + SETTINGS, check=True)\n\n"
      << "rule aggregate:\n"
      << "    input: expand(OUT + \"/cases/{name}/run.json\", name=list(CASES))\n"
      << "    output: OUT + \"/cases.csv\", OUT + \"/study.json\"\n"
      << "    run:\n"
      << "        subprocess.run([SUTURESIM, \"study\", STUDY, \"--output\", OUT] + SETTINGS, check=True)\n";
    if (!s.good())
      throw InputError(file + ": cannot be written");
  }
} // namespace suturesim::study
