#include <suturesim/core/error.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/core/process.h>
#include <suturesim/scene/simulation.h>
#include <suturesim/study/case_run.h>

#include <deal.II/base/parameter_handler.h>

#include <nlohmann/json.hpp>

#include <sys/resource.h>
#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <sstream>

namespace suturesim::study
{
  namespace fs = std::filesystem;
  using Clock  = std::chrono::steady_clock;

  // run.json's record of an outcome (reused is not recorded: it says how this study got it)
  NLOHMANN_DEFINE_TYPE_NON_INTRUSIVE(CaseOutcome, status, reason, exit_code, wall_seconds, cpu_seconds,
                                     peak_memory_bytes)

  std::string
  digest(const std::string &text)
  {
    std::uint64_t h = 14695981039346656037ull;
    for (const unsigned char c : text)
      h = (h ^ c) * 1099511628211ull;
    std::ostringstream out;
    out << std::hex << std::setw(16) << std::setfill('0') << h;
    return out.str();
  }

  std::string
  case_parameters(const std::string &scene, const std::vector<std::string> &settings)
  {
    dealii::ParameterHandler prm;
    scene::Simulation::declare_parameters(prm);
    ParameterFile::from_file(prm, scene, settings);
    std::ostringstream out;
    prm.print_parameters(out, dealii::ParameterHandler::PRM);
    return out.str();
  }

  namespace
  {
    std::string
    read_text(const fs::path &file)
    {
      std::ifstream      in(file);
      std::ostringstream text;
      text << in.rdbuf();
      return text.str();
    }

    /// The last "error: ..." or "incomplete: ..." line of the case's log (its one-line
    /// diagnostic); without one, its last non-blank line in @p other (what a library
    /// that stopped the process said last, such as Open MPI's failed MPI_Init).
    std::string
    error_line(const fs::path &log, std::string &other)
    {
      std::ifstream in(log);
      std::string   line, last;
      while (std::getline(in, line))
        if (line.rfind("error: ", 0) == 0)
          last = line.substr(7);
        else if (line.rfind("incomplete: ", 0) == 0)
          last = line.substr(12);
        else if (line.find_first_not_of(" \t\r") != std::string::npos)
          other = line;
      return last;
    }

    void
    write_run_json(const CaseJob &job, const std::string &parameters, const CaseOutcome &o)
    {
      nlohmann::json j;
      j["case"]              = job.name;
      j["scene"]             = job.scene;
      j["settings"]          = job.settings;
      j["parameters_digest"] = digest(parameters);
      j.update(nlohmann::json(o));
      const fs::path file    = fs::path(job.folder) / "run.json";
      std::ofstream  out(file);
      out << j.dump(1) << '\n';
      if (!out.good())
        throw InputError(file.string() + ": cannot write the case's run record");
    }

    /// The case's child process: suturesim <scene> --output <folder> --set ... with its
    /// output in log.txt, each process on one thread (the study's concurrency is its
    /// processes); with CaseJob::processes above 1 under mpirun -np, which gets an
    /// environment without this process's own MPI variables (a study is an MPI singleton,
    /// and mpirun started with its variables would take itself for one of its ranks).
    pid_t
    spawn(const std::string &executable, const CaseJob &job)
    {
      fs::create_directories(job.folder);
      std::vector<std::string> args{executable, job.scene, "--output", job.folder};
      for (const auto &s : job.settings)
        args.insert(args.end(), {"--set", s});
      std::vector<std::string> environment{"OPENBLAS_NUM_THREADS=1", "OMP_NUM_THREADS=1"};
      if (job.processes > 1)
        {
          args.insert(args.begin(), {"mpirun", "-np", std::to_string(job.processes)});
          // Open MPI refuses root unless told; other MPIs ignore these
          environment.insert(environment.end(), {"OMPI_*", "PMIX_*", "OPAL_*", "OMPI_ALLOW_RUN_AS_ROOT=1",
                                                 "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1"});
        }
      try
        {
          return start_process(args, (fs::path(job.folder) / "log.txt").string(), environment);
        }
      catch (const std::runtime_error &e)
        {
          throw InputError("study: case '" + job.name + "': " + e.what());
        }
    }

    CaseOutcome
    outcome_of(const CaseJob &job, const int status, const rusage &usage, const double wall)
    {
      CaseOutcome o;
      o.wall_seconds = wall;
      o.cpu_seconds  = usage.ru_utime.tv_sec + 1e-6 * usage.ru_utime.tv_usec + usage.ru_stime.tv_sec +
                      1e-6 * usage.ru_stime.tv_usec;
      o.peak_memory_bytes = 1024.0 * usage.ru_maxrss; // Linux: kilobytes
      const fs::path log  = fs::path(job.folder) / "log.txt";
      if (WIFSIGNALED(status))
        {
          o.status = "crashed";
          o.reason = std::string("killed by signal ") + std::to_string(WTERMSIG(status)) + " (" +
                     strsignal(WTERMSIG(status)) + ")";
          return o;
        }
      o.exit_code = WEXITSTATUS(status);
      const std::map<int, std::string> statuses{
        {0, "completed"}, {2, "refused"},     {3, "failed"},
        {5, "failed"},    {6, "incomplete"}, {130, "interrupted"}, {143, "interrupted"}};
      const auto                       s = statuses.find(o.exit_code);
      o.status = s == statuses.end() ? "crashed" : s->second;
      std::string last;
      if (o.exit_code != 0)
        o.reason = error_line(log, last);
      if (o.reason.empty() && o.exit_code != 0)
        o.reason = "exit code " + std::to_string(o.exit_code) + (last.empty() ? "" : " after '" + last.substr(0, 200) + "'") +
                   ", see " + log.string();
      return o;
    }

    std::string
    duration(const double seconds)
    {
      const long         s = std::lround(seconds);
      std::ostringstream out;
      if (s >= 60)
        out << s / 60 << " min ";
      out << s % 60 << " s";
      return out.str();
    }
  } // namespace

  std::optional<CaseOutcome>
  completed_run(const CaseJob &job, const std::string &parameters)
  {
    const fs::path dir = job.folder;
    if (!fs::exists(dir / "run.json"))
      return std::nullopt;
    nlohmann::json j;
    try
      {
        j = nlohmann::json::parse(read_text(dir / "run.json"));
        if (j.at("parameters_digest").get<std::string>() != digest(parameters))
          return std::nullopt;
        auto o             = j.get<CaseOutcome>();
        o.reused           = true;
        const bool started  = o.status == "completed" || o.status == "failed" || o.status == "incomplete";
        if (started && (!fs::exists(dir / "parameters.prm") || !fs::exists(dir / "summary.json")))
          return std::nullopt;
        return o;
      }
    catch (const nlohmann::json::exception &)
      {
        return std::nullopt; // a damaged record: run the case again
      }
  }

  std::vector<CaseOutcome>
  run_cases(const std::string &executable, const std::vector<CaseJob> &jobs,
            const std::vector<std::string> &parameters, const unsigned concurrency, std::ostream &progress)
  {
    std::vector<CaseOutcome>                              outcomes(jobs.size());
    std::map<pid_t, std::pair<std::size_t, Clock::time_point>> running;
    std::size_t                                           next = 0, done = 0, failed = 0;
    unsigned                                              busy = 0; ///< processes of the running cases
    double                                                run_time = 0;
    const auto                                            start    = Clock::now();
    const auto report = [&](const std::string &event) {
      const std::size_t left = jobs.size() - done;
      std::string       eta  = "";
      if (done > 0 && left > 0)
        eta = ", about " + duration(run_time / done * left / std::max<std::size_t>(1, concurrency)) +
              " left at the mean case time";
      progress << "study: " << done << "/" << jobs.size() << " done, " << running.size() << " running, " << failed
               << " failed" << eta << " (" << event << ", " << duration(std::chrono::duration<double>(Clock::now() - start).count())
               << ")\n"
               << std::flush;
    };
    while (done < jobs.size())
      {
        while (next < jobs.size() &&
               (running.empty() || busy + jobs[next].processes <= std::max(1u, concurrency)))
          {
            const pid_t pid = spawn(executable, jobs[next]);
            running[pid]    = {next, Clock::now()};
            busy += jobs[next].processes;
            report("started " + jobs[next++].name);
          }
        int    status = 0;
        rusage usage{};
        const pid_t pid = wait4(-1, &status, 0, &usage);
        if (pid < 0)
          throw std::runtime_error(std::string("study: waiting for a case failed: ") + std::strerror(errno));
        const auto it = running.find(pid);
        if (it == running.end())
          continue;
        const auto [k, t0] = it->second;
        running.erase(it);
        busy -= jobs[k].processes;
        const double wall = std::chrono::duration<double>(Clock::now() - t0).count();
        outcomes[k]       = outcome_of(jobs[k], status, usage, wall);
        write_run_json(jobs[k], parameters[k], outcomes[k]);
        run_time += wall;
        ++done;
        failed += outcomes[k].status != "completed";
        report(jobs[k].name + " " + outcomes[k].status);
      }
    return outcomes;
  }

  unsigned
  jobs_argument(const std::string &text)
  {
    char      *end = nullptr;
    const long v   = std::strtol(text.c_str(), &end, 10);
    if (text.empty() || *end != '\0' || v < 1 || v > 256)
      throw InputError("--jobs " + text + ": must be a whole number of cases from 1 to 256");
    return static_cast<unsigned>(v);
  }
} // namespace suturesim::study
