#include <suturesim/core/error.h>
#include <suturesim/core/version.h>
#include <suturesim/io/checked_output.h>
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

  Recorder::Recorder(const std::string &directory, MPI_Comm comm)
    : dir(directory)
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
  }

  void
  Recorder::write_parameters(const dealii::ParameterHandler &prm) const
  {
    if (!root)
      return;
    std::ostringstream text;
    prm.print_parameters(text, dealii::ParameterHandler::PRM);
    write_whole((fs::path(dir) / "parameters.prm").string(), text.str());
  }

  void
  Recorder::set_columns(const std::vector<std::string> &names)
  {
    n_columns = names.size();
    if (!root)
      return;
    errno = 0;
    csv.open(fs::path(dir) / "forces.csv");
    for (std::size_t i = 0; i < names.size(); ++i)
      csv << (i ? "," : "") << names[i];
    csv << '\n';
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
