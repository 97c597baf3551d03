#pragma once
/**
 * @file
 * The output contract of a run (architecture.md): parameters.prm (every value used),
 * summary.json (scene, model, status, metrics, timings, solver statistics, version),
 * forces.csv (header names each column with its unit) and *.pvd series of .vtu files.
 * Formats go through libraries (nlohmann::json, deal.II DataOutBase). Only MPI rank 0
 * writes these files; the .vtu files are written collectively by the models.
 *
 * A run that fails leaves summary.json with "status": "failed" and the reason, so no
 * failed run looks complete; stale outputs of an earlier run are removed first.
 */

#include <deal.II/base/mpi.h>
#include <deal.II/base/parameter_handler.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <string>
#include <utility>
#include <vector>

namespace suturesim::io
{
  class Recorder
  {
  public:
    /// Creates @p directory and checks that it can be written (InputError otherwise).
    Recorder(const std::string &directory, MPI_Comm comm);

    const std::string &
    directory() const
    {
      return dir;
    }

    /// Removes outputs of an earlier run in the same folder.
    void
    clear_stale_outputs() const;

    void
    write_parameters(const dealii::ParameterHandler &prm) const;

    /// Column names, each with its unit in brackets, e.g. "time [s]".
    void
    set_columns(const std::vector<std::string> &names);

    void
    add_row(const std::vector<double> &values);

    /// Appends a .vtu (a file name inside the folder) to @p series.pvd and rewrites it,
    /// so the series is valid after every step.
    void
    add_vtu(const std::string &series, double time, const std::string &vtu_file);

    /// The summary written by finish(); models add metrics and statistics to it.
    nlohmann::json &
    summary()
    {
      return json;
    }

    /// Writes summary.json with the given status ("completed" or "failed").
    void
    finish(const std::string &status, const std::string &message = "");

    bool
    is_root() const
    {
      return root;
    }

  private:
    std::string                                                       dir;
    bool                                                              root;
    std::ofstream                                                     csv;
    std::size_t                                                       n_columns = 0;
    std::map<std::string, std::vector<std::pair<double, std::string>>> series_files;
    nlohmann::json                                                    json;
  };
} // namespace suturesim::io
