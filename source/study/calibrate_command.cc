#include <suturesim/core/error.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/core/process.h>
#include <suturesim/io/checked_output.h>
#include <suturesim/study/calibrate_command.h>
#include <suturesim/study/case_run.h>
#include <suturesim/study/study_command.h>
#include <suturesim/study/study_definition.h>

#include <nlohmann/json.hpp>

#include <filesystem>
#include <iostream>


namespace suturesim::study
{
  namespace fs = std::filesystem;

  namespace
  {
    const char *usage = "usage: suturesim calibrate <calibration.prm> [--output DIR] [--jobs N] [--validate]\n"
                        "                           [--set S/K=V]...\n"
                        "  --output DIR  the calibration's folder (default: output/calibration/<name>)\n"
                        "  --jobs N      cases run at once, 1-256 (default 1): a Jacobian's runs go together\n"
                        "  --validate    read and check the calibration file, then exit\n"
                        "  --set S/K=V   a setting for every run and the reference, after their own\n";

    struct Options
    {
      std::string              file, output;
      std::vector<std::string> overrides;
      unsigned                 jobs     = 1;
      bool                     validate = false;
    };

    Options
    parse(const std::vector<std::string> &args)
    {
      Options o;
      for (std::size_t i = 0; i < args.size(); ++i)
        {
          const std::string &a        = args[i];
          const bool         has_next = i + 1 < args.size();
          if (a == "--validate")
            o.validate = true;
          else if (a == "--output" && has_next)
            o.output = args[++i];
          else if (a == "--set" && has_next)
            o.overrides.push_back(args[++i]);
          else if (a == "--jobs" && has_next)
            o.jobs = jobs_argument(args[++i]);
          else if (a.rfind("--", 0) == 0 || !o.file.empty())
            throw InputError("calibrate: unknown, incomplete or extra argument '" + a + "'\n" + usage);
          else
            o.file = a;
        }
      if (o.file.empty())
        throw InputError(std::string("calibrate: no calibration file\n") + usage);
      return o;
    }

    /// What postprocess/calibrate.py needs, every path absolute (the driver runs the
    /// study from its own working folder).
    nlohmann::json
    plan(const StudyDefinition &d, const Options &o, const std::string &folder)
    {
      nlohmann::json p;
      p["executable"]      = fs::read_symlink("/proc/self/exe").string();
      p["calibration"]     = fs::absolute(o.file).string();
      p["name"]            = d.name;
      p["folder"]          = fs::absolute(folder).string();
      p["jobs"]            = o.jobs;
      p["overrides"]       = o.overrides;
      p["max_evaluations"] = d.calibration.max_evaluations;
      p["difference_step"] = d.calibration.difference_step;
      p["probes"]          = d.metrics.probes;
      p["parameters"]      = nlohmann::json::array();
      for (const auto &q : d.calibration.parameters)
        p["parameters"].push_back({{"path", q.path}, {"initial", q.initial}, {"lower", q.lower}, {"upper", q.upper}});
      p["weights"] = nlohmann::json::array();
      for (const auto &[column, w] : d.calibration.weights)
        p["weights"].push_back({{"column", column}, {"weight", w}});
      p["validation"] = nlohmann::json::array();
      for (const auto &v : d.calibration.validation)
        p["validation"].push_back({{"name", v.name}, {"settings", v.settings}});
      return p;
    }
  } // namespace

  int
  calibrate_command(const std::vector<std::string> &arguments)
  {
    return command_exit_code("calibrate", [&] {
        const Options         o = parse(arguments);
        const StudyDefinition d = StudyDefinition::read(o.file, o.overrides);
        if (d.calibration.parameters.empty())
          throw InputError(o.file + ": Calibration/Parameters: not a calibration (no parameters to fit)");
        if (o.validate)
          {
            std::cout << o.file << ": valid, " << d.calibration.parameters.size() << " parameters, "
                      << d.calibration.weights.size() << " weighted metrics, " << d.calibration.validation.size()
                      << " validation cases\n";
            return 0;
          }
        const std::string folder = o.output.empty() ? "output/calibration/" + d.name : o.output;
        fs::create_directories(folder);
        const std::string plan_file = (fs::path(folder) / "calibration_plan.json").string();
        io::write_whole(plan_file, plan(d, o, folder).dump(2) + "\n");
        const std::string script = project_path("postprocess/calibrate.py");
        const int         status = run_process({python3, script, plan_file});
        if (status == 0 || status == 2 || status == 3)
          return status;
        std::cerr << "error: calibrate: " << python3 << " " << script << " " << plan_file
                  << " failed (exit " << status << ")\n";
        return 1;
    });
  }
} // namespace suturesim::study
