#include <suturesim/core/error.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/core/process.h>
#include <suturesim/io/checked_output.h>
#include <suturesim/study/case_metrics.h>
#include <suturesim/study/reference_series.h>
#include <suturesim/study/snakemake_export.h>
#include <suturesim/study/study_command.h>
#include <suturesim/study/study_report.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <optional>


namespace suturesim::study
{
  namespace fs = std::filesystem;
  using Clock  = std::chrono::steady_clock;

  namespace
  {
    const char *usage =
      "usage: suturesim study <study.prm> [--output DIR] [--jobs N] [--validate] [--export snakemake]\n"
      "                       [--case NAME] [--only NAME,...] [--set S/K=V]...\n"
      "  --output DIR        the study's folder (default: output/studies/<study name>)\n"
      "  --jobs N            cases run at once on this machine, 1-256 (default 1)\n"
      "  --validate          read and check the study and every case, then exit\n"
      "  --export snakemake  write DIR/Snakefile (run it with snakemake --cores N) and exit\n"
      "  --case NAME         run one case (what the Snakefile's rules do) and exit\n"
      "  --only NAME,...     only these cases (and the references they are measured against)\n"
      "  --case-list FILE    the cases of FILE (\"name: settings; ...\", as Cases/List) in place of\n"
      "                      the study's axes and list (what suturesim calibrate runs)\n"
      "  --no-figures        write the tables only\n"
      "  --set S/K=V         a setting for every case and the reference, after their own\n"
      "                      (e.g. --set \"Time/End time=0.2\" for a small run of the study;\n"
      "                      --set \"Model accurate/Mesh/Geo parameters=...\" sets the scene's\n"
      "                      accurate section, under the cases' own settings)\n";

    struct Options
    {
      std::string              file, output, export_to, one_case, case_list;
      std::vector<std::string> overrides, only;
      unsigned    jobs     = 1;
      bool        validate = false, figures = true;
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
          else if (a == "--only" && has_next)
            {
              std::string name;
              for (const char c : args[++i] + ",")
                if (c != ',')
                  name += c;
                else if (!name.empty())
                  o.only.push_back(name), name.clear();
            }
          else if (a == "--case-list" && has_next)
            o.case_list = args[++i];
          else if (a == "--no-figures")
            o.figures = false;
          else if (a == "--case" && has_next)
            o.one_case = args[++i];
          else if (a == "--export" && has_next && args[i + 1] == "snakemake")
            o.export_to = args[++i];
          else if (a == "--jobs" && has_next)
            o.jobs = jobs_argument(args[++i]);
          else if (a.rfind("--", 0) == 0 || !o.file.empty())
            throw InputError("study: unknown, incomplete or extra argument '" + a + "'\n" + usage);
          else
            o.file = a;
        }
      if (o.file.empty())
        throw InputError(std::string("study: no study file\n") + usage);
      return o;
    }

    /// The text of --case-list @p file: at most 1 MiB (some thousand cases).
    std::string
    case_list_text(const std::string &file)
    {
      constexpr std::size_t limit = 1 << 20;
      std::ifstream         in(file, std::ios::binary);
      std::string           text(limit + 1, '\0');
      in.read(text.data(), static_cast<std::streamsize>(text.size()));
      if (in.bad() || (!in && !in.eof()) || !fs::is_regular_file(file))
        throw InputError("study: --case-list " + file + ": cannot be read");
      text.resize(static_cast<std::size_t>(in.gcount()));
      if (text.size() > limit)
        throw InputError("study: --case-list " + file + ": longer than 1 MiB");
      return text;
    }

    /// The arguments that make a study the same study again (the Snakefile's commands).
    std::vector<std::string>
    study_arguments(const Options &o)
    {
      std::vector<std::string> out;
      for (const auto &s : o.overrides)
        out.insert(out.end(), {"--set", s});
      if (!o.only.empty())
        {
          std::string names;
          for (const auto &n : o.only)
            names += (names.empty() ? "" : ",") + n;
          out.insert(out.end(), {"--only", names});
        }
      return out;
    }

    /// @p study restricted to the cases of --only, with the references they are measured
    /// against (renumbered).
    void
    restrict_to(StudyDefinition &study, const Options &o)
    {
      if (o.only.empty())
        return;
      // (a resolution series is one reference: all of its runs stay)
      for (const auto &name : o.only)
        if (std::none_of(study.cases.begin(), study.cases.end(), [&](const Case &c) { return c.name == name; }))
          throw InputError(o.file + ": --only " + name + ": the study has no such case");
      const auto        kept = [&](const Case &c) { return std::find(o.only.begin(), o.only.end(), c.name) != o.only.end(); };
      std::vector<Case> cases, references;
      if (study.reference_series)
        {
          std::copy_if(study.cases.begin(), study.cases.end(), std::back_inserter(cases), kept);
          study.cases = cases;
          return;
        }
      std::vector<std::size_t> renumbered(study.references.size(), study.references.size());
      for (auto c : study.cases)
        if (kept(c))
          {
            if (renumbered[c.reference] == study.references.size())
              {
                renumbered[c.reference] = references.size();
                references.push_back(study.references[c.reference]);
                references.back().reference = renumbered[c.reference];
              }
            c.reference = renumbered[c.reference];
            cases.push_back(c);
          }
      study.cases      = cases;
      study.references = references;
    }

    /// The row of a case that has run (@p is_reference: one of the references): its metrics
    /// against the reference.
    CaseRow
    row_of(const StudyDefinition &study, const Case &c, const bool is_reference, const CaseOutcome &outcome,
           const RunData *data, const RunData &reference)
    {
      CaseRow row;
      row.definition = &c;
      row.outcome    = outcome;
      if (data == nullptr)
        {
          row.costs = case_costs(RunData{}, outcome);
          return row;
        }
      const RunData &run = *data;
      row.costs          = case_costs(run, outcome);
      const auto &rt    = run.summary.value("realtime", nlohmann::json::object());
      // dt_crit_s is "none" for an unconditionally stable integrator
      const auto seconds = [&](const char *key) {
        return rt.contains(key) && rt.at(key).is_number() ? rt.at(key).get<double>() : NAN;
      };
      row.dt      = seconds("dt_s");
      row.dt_crit = seconds("dt_crit_s");
      for (const auto &[name, bound] : study.objective.limits)
        row.limit_values.push_back(run.metric(name).value_or(NAN));
      // a reference row keeps the reference's metric of each map entry
      for (const auto &[own, other] : study.figures.map_metrics)
        row.map_values.push_back(run.metric(is_reference ? other : own).value_or(NAN));
      for (const auto &name : study.figures.map_flags)
        row.map_flags.push_back(run.metric(name).value_or(NAN));
      // an incomplete run (exit 6) measured what it did until it ended: a needle that its
      // tightening drove back into the tissue stops a stitch whose punctures stand
      if (outcome.status != "completed" && outcome.status != "incomplete")
        return row;
      std::vector<std::string> missing;
      try
        {
          row.errors = case_errors(study.metrics, run, reference, missing);
        }
      catch (const MissingMetric &e)
        {
          study.fail(e.key, e.what());
        }
      if (!missing.empty() && row.outcome.status == "completed")
        {
          row.outcome.status = "incomplete";
          row.outcome.reason = missing.front() + (missing.size() > 1 ? " (and " + std::to_string(missing.size() - 1) +
                                                                         " more)"
                                                                     : "");
        }
      if (!study.figures.convergence_metric.empty())
        row.convergence_value = run.metric(study.figures.convergence_metric).value_or(NAN);
      const auto &mesh = run.summary.value("mesh", nlohmann::json::object());
      if (mesh.contains("representative_size") && mesh.at("representative_size").is_number())
        row.mesh_size = mesh.at("representative_size").get<double>();
      return row;
    }

    /// The run in @p folder, if it wrote its summary.json (a refused run writes none).
    std::optional<RunData>
    written_run(const std::string &folder)
    {
      if (!fs::exists(fs::path(folder) / "summary.json"))
        return std::nullopt;
      return RunData::read(folder);
    }

    /// The row of a case whose reference @p reference failed or ended incomplete: its own
    /// metrics for the map, no errors; a case that completed or ended incomplete (which
    /// row_of() would measure) says why it is not compared.
    CaseRow
    unreferenced_row(const StudyDefinition &study, const Case &c, const CaseOutcome &outcome, const RunData *data,
                     const std::string &reference, const CaseOutcome &theirs)
    {
      CaseOutcome own = outcome;
      if (own.status == "completed" || own.status == "incomplete")
        {
          own.status = "no reference";
          own.reason = "its reference run '" + reference + "' " + theirs.status + ": " + theirs.reason;
        }
      return row_of(study, c, false, own, data, RunData{});
    }

    /// ", best.prm" or ", N best_<values>.prm" for the summary line ("" when none).
    std::string
    best_files(const StudyReport &report)
    {
      const auto  chosen = report.best();
      const auto  count  = std::count_if(chosen.begin(), chosen.end(), [](const auto &k) { return k.has_value(); });
      if (count == 0)
        return "";
      return chosen.size() == 1 ? ", best.prm" : ", " + std::to_string(count) + " best_<values>.prm";
    }

    /// The extrapolated reference of a Reference/Series; its errors name the study's line.
    SeriesReference
    reference_series(const StudyDefinition &study, const std::vector<CaseJob> &jobs, const std::vector<RunData> &runs)
    {
      std::vector<std::string> names;
      for (std::size_t k = 0; k < runs.size(); ++k)
        names.push_back(jobs[k].name);
      try
        {
          return series_reference(study.metrics, runs, names, study.figures.convergence_sizes);
        }
      catch (const MissingMetric &e)
        {
          study.fail(e.key, e.what());
        }
      catch (const std::invalid_argument &e)
        {
          study.fail("Reference/Series", e.what());
        }
    }

    /// Runs postprocess/study_figures.py on @p folder; false (with the reason on
    /// stderr) when it fails.
    bool
    draw_figures(const std::string &folder)
    {
      const std::string script = project_path("postprocess/study_figures.py");
      if (run_process({python3, script, folder}) == 0)
        return true;
      std::cerr << "error: study: the figures were not drawn (" << python3 << " " << script << " " << folder
                << " failed)\n";
      return false;
    }

    /// Every case (the reference first) as a job in @p folder, with its parameters.
    struct Plan
    {
      std::vector<const Case *> cases;
      std::vector<CaseJob>      jobs;
      std::vector<std::string>  parameters;
    };

    Plan
    plan(const StudyDefinition &study, const std::string &folder)
    {
      Plan p;
      for (const auto &r : study.references)
        p.cases.push_back(&r);
      for (const auto &c : study.cases)
        p.cases.push_back(&c);
      for (const auto *c : p.cases)
        {
          p.jobs.push_back({c->name, (fs::path(folder) / "cases" / c->name).string(), study.base_scene, c->settings,
                            c->processes});
          p.parameters.push_back(case_parameters(study.base_scene, c->settings));
        }
      return p;
    }

    struct Execution
    {
      std::vector<CaseOutcome> outcomes;
      std::size_t              run        = 0;
      double                   cases_wall = 0; ///< the cases' own wall time, s
      double                   run_phase  = 0; ///< wall time of running them, s
    };

    /// Runs the cases not done yet (with --case only that one); the others' outcomes are
    /// their records.
    Execution
    execute(const Plan &p, const Options &o, const std::string &executable)
    {
      Execution                e;
      std::vector<std::size_t> todo;
      e.outcomes.resize(p.jobs.size());
      for (std::size_t k = 0; k < p.jobs.size(); ++k)
        {
          if (!o.one_case.empty() && p.jobs[k].name != o.one_case)
            continue;
          if (const auto done = completed_run(p.jobs[k], p.parameters[k]))
            e.outcomes[k] = *done;
          else
            todo.push_back(k);
        }
      if (!o.one_case.empty() &&
          std::none_of(p.jobs.begin(), p.jobs.end(), [&](const CaseJob &j) { return j.name == o.one_case; }))
        throw InputError(o.file + ": --case " + o.one_case + ": the study has no such case");
      std::vector<CaseJob>     jobs;
      std::vector<std::string> parameters;
      for (const auto k : todo)
        jobs.push_back(p.jobs[k]), parameters.push_back(p.parameters[k]);
      const auto start = Clock::now();
      const auto ran   = run_cases(executable, jobs, parameters, o.jobs, std::cerr);
      e.run_phase      = std::chrono::duration<double>(Clock::now() - start).count();
      for (std::size_t i = 0; i < todo.size(); ++i)
        e.outcomes[todo[i]] = ran[i], e.cases_wall += ran[i].wall_seconds;
      e.run = todo.size();
      return e;
    }

    /// The metrics of every case, the tables and the figures; the exit code.
    int
    report(const StudyDefinition &study, const Plan &p, const Execution &e, const Options &o,
           const std::string &folder, const Clock::time_point start)
    {
      const std::size_t    count = study.references.size();
      std::vector<RunData> references;
      for (std::size_t k = 0; k < count; ++k)
        {
          const auto &outcome = e.outcomes[k];
          const bool  kept    = study.report_failed_references &&
                             (outcome.status == "failed" || outcome.status == "incomplete");
          if (outcome.status != "completed" && !kept)
            study.fail(study.reference_series ? "Reference/Series" : "Reference/Settings",
                       "the reference run '" + p.jobs[k].name + "' " + outcome.status + ": " + outcome.reason);
          // a failed run keeps its last converged state's summary (exit 3), an incomplete
          // one the state it ended in (exit 6)
          references.push_back(written_run(p.jobs[k].folder).value_or(RunData{}));
        }
      // a resolution series: every row against its extrapolation, the series' own too
      std::optional<SeriesReference> series;
      if (study.reference_series)
        series = reference_series(study, p.jobs, references);
      std::vector<CaseRow> rows;
      for (std::size_t k = 0; k < p.jobs.size(); ++k)
        {
          // the references are read once; a case without summary.json (refused) has no data
          const RunData &against = series ? series->data : references[k < count ? k : p.cases[k]->reference];
          std::optional<RunData> own;
          if (k >= count)
            own = written_run(p.jobs[k].folder);
          const RunData *data = k < count ? &references[k] : own ? &*own : nullptr;
          // a case whose own reference failed (only kept with Reference/On failure = report)
          const std::size_t theirs = p.cases[k]->reference;
          if (k >= count && e.outcomes[theirs].status != "completed")
            rows.push_back(unreferenced_row(study, *p.cases[k], e.outcomes[k], data, p.jobs[theirs].name,
                                            e.outcomes[theirs]));
          else
            rows.push_back(row_of(study, *p.cases[k], k < count, e.outcomes[k], data, against));
        }
      const StudyReport report(study, std::move(rows), series ? series->account : nlohmann::json(nullptr));
      nlohmann::json    timing{{"jobs", o.jobs},
                            {"cases_run", e.run},
                            {"cases_reused", p.jobs.size() - e.run},
                            {"cases_wall_seconds", e.cases_wall},
                            {"run_phase_seconds", e.run_phase}};
      report.write(folder, timing);
      const bool   figures           = o.figures && draw_figures(folder);
      const double total             = std::chrono::duration<double>(Clock::now() - start).count();
      timing["study_wall_seconds"] = total;
      report.write(folder, timing);
      std::cout << "study " << study.name << ": " << p.jobs.size() << " cases (" << e.run << " run, "
                << p.jobs.size() - e.run << " already done) in " << total << " s, the cases' own runs "
                << e.cases_wall << " s; wrote " << folder << "/ (cases.csv, study.json"
                << best_files(report) << (figures ? ", figures" : "") << ")\n";
      return figures || !o.figures ? 0 : 1;
    }
  } // namespace

  int
  study_command(const std::vector<std::string> &arguments)
  {
    const auto start = Clock::now();
    return command_exit_code("study", [&] {
        const Options         o     = parse(arguments);
        const std::string case_list = o.case_list.empty() ? "" : case_list_text(o.case_list);
        StudyDefinition study = StudyDefinition::read(o.file, o.overrides, o.case_list.empty() ? nullptr : &case_list);
        restrict_to(study, o);
        if (o.validate)
          {
            std::cout << o.file << ": valid, " << study.cases.size() << " cases and " << study.references.size()
                      << (study.references.size() == 1 ? " reference\n" : " references\n");
            return 0;
          }
        const std::string folder = o.output.empty() ? "output/studies/" + study.name : o.output;
        fs::create_directories(fs::path(folder) / "cases");
        const std::string executable = fs::read_symlink("/proc/self/exe").string();
        const Plan        p          = plan(study, folder);
        if (!o.export_to.empty())
          {
            export_snakemake(executable, o.file, folder, p.jobs, p.parameters, study_arguments(o));
            std::cout << "study: wrote " << folder << "/Snakefile; run it with snakemake --snakefile " << folder
                      << "/Snakefile --cores N\n";
            return 0;
          }
        const Execution e = execute(p, o, executable);
        return o.one_case.empty() ? report(study, p, e, o, folder, start) : 0;
    });
  }

  int
  command_exit_code(const std::string &name, const std::function<int()> &body)
  {
    try
      {
        return body();
      }
    catch (const InputError &e)
      {
        std::cerr << "error: " << e.what() << '\n';
        return 2;
      }
    catch (const io::WriteError &e)
      {
        std::cerr << "error: " << e.what() << '\n';
        return 5;
      }
    catch (const std::exception &e)
      {
        std::cerr << "error: internal error: " << name << ": " << e.what() << '\n';
        return 4;
      }
  }
} // namespace suturesim::study
