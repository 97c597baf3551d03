#include <suturesim/core/blas_threads.h>
#include <suturesim/core/error.h>
#include <suturesim/core/version.h>
#include <suturesim/io/checked_output.h>
#include <suturesim/io/checkpoint.h>
#include <suturesim/io/recorder.h>

#include <deal.II/base/data_out_base.h>
#include <deal.II/base/multithread_info.h>

#include <cerrno>
#include <filesystem>
#include <iomanip>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace suturesim::io
{
  namespace fs = std::filesystem;

  namespace
  {
    /// The resource limits (docs/input_errors.md, "Resource guards"): a stopped run may
    /// need them raised, and they change no result, so a restart may change them.
    const std::set<std::string> resource_limits{"Time/Maximum steps",   "Time/Maximum outputs",
                                                "Mesh/Maximum cells",   "Mesh/Gmsh time limit",
                                                "Mesh/Gmsh memory limit", "Tissue/Linear solver/Maximum memory"};

    /// Diagnostics that write files beside the run and change no result: a restart from
    /// a failed run's checkpoint may turn them on to see its failing step.
    const std::set<std::string> diagnostics{"Suture/Newton/Trace failures"};

    /// The settings of a parameters.prm text, "Subsection/Key" → value, without those a
    /// restart may change: the end time, the checkpoints, the resource limits and the
    /// diagnostics.
    std::map<std::string, std::string>
    settings(const std::string &text)
    {
      const auto trim = [](std::string t) {
        t.erase(0, t.find_first_not_of(' '));
        t.erase(t.find_last_not_of(' ') + 1);
        return t;
      };
      std::vector<std::string>           path;
      std::map<std::string, std::string> values;
      std::istringstream                 in(text);
      for (std::string line; std::getline(in, line);)
        {
          line = trim(line);
          if (line.rfind("subsection ", 0) == 0)
            path.push_back(line.substr(11));
          else if (line == "end" && !path.empty())
            path.pop_back();
          else if (line.rfind("set ", 0) == 0 && line.find('=') != std::string::npos)
            {
              // "set Key   = value   # default: ..." (the PRM writer aligns the '=' and
              // notes a default that differs); a value may hold a '#' of its own
              std::string key = trim(line.substr(4, line.find('=') - 4));
              for (auto p = path.rbegin(); p != path.rend(); ++p)
                key = *p + "/" + key;
              std::string value = line.substr(line.find('=') + 1);
              value             = trim(value.substr(0, value.rfind(" # default:")));
              if (key != "Time/End time" && key.rfind("Time/Checkpoint", 0) != 0 && !resource_limits.count(key) &&
                  !diagnostics.count(key))
                values[key] = value;
            }
        }
      return values;
    }
  } // namespace

  std::string
  first_difference(const std::string &before, const std::string &now)
  {
    const auto a = settings(before), b = settings(now);
    for (const auto &[key, value] : b)
      if (a.count(key) == 0 || a.at(key) != value)
        return "'" + key + " = " + (a.count(key) ? a.at(key) : std::string("(none)")) + "' then, '" + key + " = " +
               value + "' now";
    for (const auto &[key, value] : a)
      if (b.count(key) == 0)
        return "'" + key + " = " + value + "' then, none now";
    return "";
  }

  Recorder::Recorder(const std::string &directory, MPI_Comm comm)
    : dir(directory)
    , comm(comm)
    , root(dealii::Utilities::MPI::this_mpi_process(comm) == 0)
  {
    int ok = 1;
    std::string reason;
    if (root)
      {
        std::error_code ec;
        fs::create_directories(dir, ec);
        const fs::path probe = fs::path(dir) / ".suturesim_write_test";
        std::ofstream  out(probe);
        if (ec || !out)
          {
            ok     = 0;
            reason = ec ? ec.message() : "permission denied";
          }
        else
          {
            out.close();
            fs::remove(probe);
          }
      }
    ok = dealii::Utilities::MPI::min(ok, comm);
    if (!ok)
      throw InputError("--output " + dir + ": cannot write the output folder (" +
                       (reason.empty() ? "see rank 0" : reason) + ")");
    json["version"] = version_string;
    json["commit"]  = git_commit;
    json["mpi_processes"] = dealii::Utilities::MPI::n_mpi_processes(comm);
    // threads per process for the accurate path's assembly (main.cc)
    json["threads"] = dealii::MultithreadInfo::n_threads();
    // what the dense kernels of MUMPS ran on (core/blas_threads.h): timings depend on it
    json["blas_kernels"] = blas_kernels();
  }

  void
  Recorder::clear_stale_outputs() const
  {
    if (!root)
      return;
    for (const auto &entry : fs::directory_iterator(dir))
      {
        const std::string name = entry.path().filename().string();
        const std::string ext  = entry.path().extension().string();
        if (name == "summary.json" || name == "forces.csv" || name == "parameters.prm" || name == "surface_displacement.json" ||
            name == "stitches.csv" ||
            ext == ".pvd" || ext == ".vtu" || ext == ".pvtu")
          fs::remove(entry.path());
      }
    remove_checkpoint(dir);
  }

  void
  Recorder::write_file(const std::string &name, const std::string &text) const
  {
    if (root)
      write_whole((fs::path(dir) / name).string(), text);
  }

  void
  Recorder::write_parameters(const dealii::ParameterHandler &prm)
  {
    std::ostringstream text;
    prm.print_parameters(text, dealii::ParameterHandler::PRM);
    parameters = text.str();
    if (root)
      write_whole((fs::path(dir) / "parameters.prm").string(), parameters);
  }

  void
  Recorder::resume(const dealii::ParameterHandler &prm)
  {
    try
      {
        take_up(prm);
      }
    catch (const nlohmann::json::exception &e)
      {
        resumed = {};
        throw InputError("--restart " + dir + ": the checkpoint is not one of this version's (" + e.what() + ")");
      }
  }

  void
  Recorder::take_up(const dealii::ParameterHandler &prm)
  {
    resumed = read_checkpoint(dir, comm);
    std::ostringstream text;
    prm.print_parameters(text, dealii::ParameterHandler::PRM);
    const auto  &record    = resumed.first.at("record");
    const double t         = record.at("t").get<double>();
    const auto   csv_bytes = record.at("forces_csv_bytes").get<std::uintmax_t>();
    series_files           = record.at("series").get<decltype(series_files)>();
    // every check before the folder is touched, rank 0's file checks shared with all
    std::string refusal = first_difference(record.at("parameters").get<std::string>(), text.str());
    if (!refusal.empty())
      refusal = "the checkpoint was written with other parameters (" + refusal +
                "); a restart runs the checkpoint's scene, only Time/End time, the checkpoint settings and the "
                "resource limits (Time/Maximum steps and outputs, Mesh/Maximum cells, Mesh/Gmsh time and memory "
                "limit, Tissue/Linear solver/Maximum memory) may change";
    else if (const double end = prm.get_double({"Time"}, "End time"); !(end > t * (1 + 1e-12)))
      refusal = "Time/End time = " + std::to_string(end) + " s is not after the checkpoint's t = " +
                std::to_string(t) + " s";
    const fs::path  forces = fs::path(dir) / "forces.csv";
    std::error_code error;
    if (root && refusal.empty() && !fs::exists(forces, error))
      refusal = "forces.csv is missing";
    else if (root && refusal.empty() && fs::file_size(forces, error) < csv_bytes)
      refusal = "forces.csv is shorter than the checkpoint's record";
    refusal = dealii::Utilities::MPI::broadcast(comm, refusal, 0);
    if (!refusal.empty())
      {
        resumed = {};
        throw InputError("--restart " + dir + ": " + refusal);
      }
    write_parameters(prm);
    if (!root)
      return;
    // the record as it was at the checkpoint: forces.csv's rows, the series, no summary
    fs::resize_file(forces, csv_bytes, error);
    if (error)
      throw WriteError(forces.string() + ": cannot be written (" + error.message() + ")");
    fs::remove(fs::path(dir) / "summary.json", error);
    std::set<std::string> listed;
    for (const auto &[series, files] : series_files)
      {
        for (const auto &file : files)
          listed.insert(file.second);
        std::ostringstream pvd;
        dealii::DataOutBase::write_pvd_record(pvd, files);
        write_whole((fs::path(dir) / (series + ".pvd")).string(), pvd.str());
      }
    // states written after the checkpoint: not the run's any more
    for (const auto &entry : fs::directory_iterator(dir, error))
      if ((entry.path().extension() == ".vtu" || entry.path().extension() == ".pvtu") &&
          listed.count(entry.path().filename().string()) == 0)
        fs::remove(entry.path(), error);
  }

  void
  Recorder::restore_summary()
  {
    // the run's record so far, by the binary and on the processes that finish it
    const nlohmann::json now = json;
    json                     = resumed.first.at("record").at("summary");
    for (const char *key : {"version", "commit", "mpi_processes", "threads", "blas_kernels"})
      json[key] = now[key];
    json["restarted_from"] = {{"t", resumed.first.at("record").at("t")}};
  }

  void
  Recorder::checkpoint(const double t, const nlohmann::json &shared, const nlohmann::json &local)
  {
    std::error_code      error;
    const std::uintmax_t bytes = root ? fs::file_size(fs::path(dir) / "forces.csv", error) : 0;
    if (error)
      throw WriteError((fs::path(dir) / "forces.csv").string() + ": cannot be read back (" + error.message() + ")");
    nlohmann::json state;
    state["processes"] = dealii::Utilities::MPI::n_mpi_processes(comm);
    state["scenario"]  = shared;
    state["record"]    = {{"t", t},
                          {"parameters", parameters},
                          {"summary", json},
                          {"series", series_files},
                          {"forces_csv_bytes", bytes}};
    write_checkpoint(dir, state, local, comm);
  }

  void
  Recorder::set_columns(const std::vector<std::string> &names)
  {
    n_columns = names.size();
    if (!root)
      return;
    errno = 0;
    std::ostringstream header;
    for (std::size_t i = 0; i < names.size(); ++i)
      header << (i ? "," : "") << names[i];
    header << '\n';
    if (resuming())
      {
        // the rows up to the checkpoint are there: go on after them
        csv.open(fs::path(dir) / "forces.csv", std::ios::app);
        check_written(csv, (fs::path(dir) / "forces.csv").string());
        return;
      }
    csv.open(fs::path(dir) / "forces.csv");
    csv << header.str();
    check_written(csv, (fs::path(dir) / "forces.csv").string());
  }

  void
  Recorder::add_row(const double *values, const std::size_t n, const bool flush)
  {
    if (n != n_columns)
      throw std::logic_error("forces.csv row has the wrong number of columns");
    if (!root)
      return;
    errno = 0;
    csv << std::setprecision(std::numeric_limits<double>::max_digits10);
    for (std::size_t i = 0; i < n; ++i)
      csv << (i ? "," : "") << values[i];
    csv << '\n';
    // a row per realtime tick: the file's name is built only when the write failed
    if (flush)
      csv.flush();
    if (!csv.good())
      check_written(csv, (fs::path(dir) / "forces.csv").string());
  }

  void
  Recorder::flush_rows()
  {
    if (root && !csv.flush().good())
      check_written(csv, (fs::path(dir) / "forces.csv").string());
  }

  void
  Recorder::add_vtu(const std::string &series, const double time, const std::string &vtu_file)
  {
    auto &files = series_files[series];
    files.emplace_back(time, vtu_file);
    if (!root)
      return;
    std::ostringstream text;
    dealii::DataOutBase::write_pvd_record(text, files);
    write_whole((fs::path(dir) / (series + ".pvd")).string(), text.str());
  }

  void
  Recorder::finish(const std::string &status, const std::string &message)
  {
    json["status"] = status;
    if (!message.empty())
      json["error"] = message;
    if (!root)
      return;
    write_whole((fs::path(dir) / "summary.json").string(), json.dump(2) + '\n');
  }
} // namespace suturesim::io
