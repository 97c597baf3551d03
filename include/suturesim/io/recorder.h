#pragma once
/**
 * @file
 * The output contract of a run (architecture.md): parameters.prm (every value used),
 * summary.json (scene, model, status, metrics, timings, solver statistics, version),
 * forces.csv (header names each column with its unit) and *.pvd series of .vtu files.
 * Formats go through libraries (nlohmann::json, deal.II DataOutBase). Only MPI rank 0
 * writes these files; the .vtu files are written collectively by the models, and each
 * process writes its own part of a checkpoint (io/checkpoint.h).
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
  /// The first setting in which two parameters.prm texts differ, as "'Path/Key = a'
  /// then, 'Path/Key = b' now" ("": none), leaving out those a restart may change
  /// (Time/End time, Time/Checkpoint ...).
  std::string
  first_difference(const std::string &before, const std::string &now);

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

    /// Removes outputs of an earlier run in the same folder, its checkpoint among them.
    void
    clear_stale_outputs() const;

    void
    write_parameters(const dealii::ParameterHandler &prm);

    /// Writes @p text as the folder's file @p name whole (rank 0; checked_output.h), for
    /// a table made once at the end (stitches.csv).
    void
    write_file(const std::string &name, const std::string &text) const;

    /// Column names, each with its unit in brackets, e.g. "time [s]".
    void
    set_columns(const std::vector<std::string> &names);

    /// A row of @p n values (n = the number of columns), flushed to the disk at once
    /// unless @p flush is false: the realtime record's writer thread flushes every
    /// 100 ms (flush_rows()) instead of once a haptic tick.
    void
    add_row(const double *values, std::size_t n, bool flush = true);
    void
    add_row(const std::vector<double> &values)
    {
      add_row(values.data(), values.size());
    }
    /// Flushes the rows added without flushing; WriteError when a write failed.
    void
    flush_rows();

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

    /// Restart (suturesim --restart, io/checkpoint.h), in place of write_parameters():
    /// reads the folder's checkpoint, checks that it was written with the parameters of
    /// @p prm (Time/End time and the checkpoint settings may differ), writes them to
    /// parameters.prm and takes up the
    /// record it holds: the .pvd series, forces.csv cut back to the checkpoint's rows
    /// (set_columns() then appends), summary.json's contents (restore_summary()).
    /// summary.json is removed until the run ends, the .pvd series are written as they
    /// were, and states written after the checkpoint are removed. InputError naming
    /// --restart, before anything is changed, when the checkpoint does not fit (other
    /// parameters, an End time not after it, forces.csv missing or shorter).
    void
    resume(const dealii::ParameterHandler &prm);

    /// Whether this run goes on from a checkpoint (resume()).
    bool
    resuming() const
    {
      return !resumed.first.is_null();
    }

    /// The scenario's part of the checkpoint resume() read: what every process holds
    /// alike, and this process's own.
    const nlohmann::json &
    resumed_state() const
    {
      return resumed.first.at("scenario");
    }
    const nlohmann::json &
    resumed_local_state() const
    {
      return resumed.second;
    }

    /// summary.json's contents as the checkpoint resume() read holds them (the scenario
    /// calls it once its record is set up again), with this run's version, commit and
    /// processes and "restarted_from": {"t"}.
    void
    restore_summary();

    /// Writes a checkpoint (collective) of the state at @p t (s): the scenario's @p shared
    /// state and this process's @p local one, with the record so far.
    void
    checkpoint(double t, const nlohmann::json &shared, const nlohmann::json &local);

  private:
    /// resume(), JSON errors left to it.
    void
    take_up(const dealii::ParameterHandler &prm);

    std::string                                                       dir;
    MPI_Comm                                                          comm;
    bool                                                              root;
    std::string                                                       parameters; ///< parameters.prm's text
    std::pair<nlohmann::json, nlohmann::json>                         resumed;
    std::ofstream                                                     csv;
    std::size_t                                                       n_columns = 0;
    std::map<std::string, std::vector<std::pair<double, std::string>>> series_files;
    nlohmann::json                                                    json;
  };
} // namespace suturesim::io
