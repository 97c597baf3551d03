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
#include <sstream>

namespace suturesim::io
{
  namespace fs = std::filesystem;

  namespace
  {
    /// The settings of a parameters.prm text as "Subsection/Key = value" lines, without
    /// those a restart may change.
    std::vector<std::string>
    settings(const std::string &text)
    {
      std::vector<std::string> path, lines;
      std::istringstream       in(text);
      for (std::string line; std::getline(in, line);)
        {
          line.erase(0, line.find_first_not_of(' '));
          if (line.rfind("subsection ", 0) == 0)
            path.push_back(line.substr(11));
          else if (line == "end" && !path.empty())
            path.pop_back();
          else if (line.rfind("set ", 0) == 0 && line.find('=') != std::string::npos)
            {
              // "set Key   = value   # default: ..." (the PRM writer aligns the '=')
              const auto trim = [](std::string t) {
                t.erase(0, t.find_first_not_of(' '));
                t.erase(t.find_last_not_of(' ') + 1);
                return t;
              };
              std::string key = trim(line.substr(4, line.find('=') - 4));
              for (auto p = path.rbegin(); p != path.rend(); ++p)
                key = *p + "/" + key;
              const std::string value = trim(line.substr(line.find('=') + 1, line.find('#') - line.find('=') - 1));
              if (key != "Time/End time" && key.rfind("Time/Checkpoint", 0) != 0)
                lines.push_back(key + " = " + value);
            }
        }
      return lines;
    }
  } // namespace

  std::string
  first_difference(const std::string &before, const std::string &now)
  {
    const auto a = settings(before), b = settings(now);
    for (std::size_t k = 0; k < std::max(a.size(), b.size()); ++k)
      if (k >= a.size() || k >= b.size() || a[k] != b[k])
        return "'" + (k < a.size() ? a[k] : std::string("nothing")) + "' then, '" +
               (k < b.size() ? b[k] : std::string("nothing")) + "' now";
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
            ext == ".pvd" || ext == ".vtu" || ext == ".pvtu")
          fs::remove(entry.path());
      }
    remove_checkpoint(dir);
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
    const auto       &record     = resumed.first.at("record");
    const std::string difference = first_difference(record.at("parameters").get<std::string>(), text.str());
    if (!difference.empty())
      {
        resumed = {};
        throw InputError("--restart " + dir + ": the checkpoint was written with other parameters (" + difference +
                         "); a restart runs the checkpoint's scene, only Time/End time may change");
      }
    write_parameters(prm);
    series_files = record.at("series").get<decltype(series_files)>();
    const auto csv_bytes = record.at("forces_csv_bytes").get<std::uintmax_t>();
    if (!root)
      return;
    const fs::path forces = fs::path(dir) / "forces.csv";
    std::error_code error;
    if (fs::file_size(forces, error) < csv_bytes || error)
      throw InputError("--restart " + dir + ": forces.csv is shorter than the checkpoint's record");
    fs::resize_file(forces, csv_bytes, error);
    if (error)
      throw WriteError(forces.string() + ": cannot be written (" + error.message() + ")");
    fs::remove(fs::path(dir) / "summary.json");
  }

  void
  Recorder::checkpoint(const nlohmann::json &shared, const nlohmann::json &local)
  {
    nlohmann::json state;
    state["processes"] = dealii::Utilities::MPI::n_mpi_processes(comm);
    state["scenario"]  = shared;
    state["record"]    = {{"parameters", parameters},
                          {"summary", json},
                          {"series", series_files},
                          {"forces_csv_bytes", root ? fs::file_size(fs::path(dir) / "forces.csv") : 0}};
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
  Recorder::add_row(const std::vector<double> &values)
  {
    if (values.size() != n_columns)
      throw std::logic_error("forces.csv row has the wrong number of columns");
    if (!root)
      return;
    errno = 0;
    csv << std::setprecision(std::numeric_limits<double>::max_digits10);
    for (std::size_t i = 0; i < values.size(); ++i)
      csv << (i ? "," : "") << values[i];
    csv << '\n';
    // a row per realtime tick: the file's name is built only when the write failed
    if (!csv.flush().good())
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
