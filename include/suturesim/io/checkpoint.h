#pragma once
/**
 * @file
 * Checkpoints of a long run, and the restart from one (`suturesim <scene> --restart DIR`,
 * issue 26). A checkpoint is the state after an accepted step as JSON, stored as CBOR
 * (RFC 8949; nlohmann::json writes a double as binary64, or binary32 only when that is
 * exact, so every number is restored bit for bit), in DIR/checkpoint/:
 *
 *   shared.cbor     rank 0's: what every process holds alike (the time, the stepper,
 *                   the needle, the suture, the contacts, the record so far)
 *   rank-<k>.cbor   process k's part of the distributed tissue (its DoF values, its
 *                   cells' mixed fields)
 *
 * It is written whole into DIR/checkpoint.new/ and then renamed over DIR/checkpoint/, so
 * a checkpoint/ that exists is complete: a run killed while writing one keeps the one
 * before (against a killed process; the files are not synced to disk, so a machine
 * that crashes may lose the last one). The mesh is not stored: it is a function of the scene, built again the same
 * way, and its partition a function of the process count, which a restart must repeat
 * (checked). This is where suturesim differs from ASPECT's checkpoints, which store the
 * p4est forest and transfer the vectors to any process count: here the mesh never
 * changes during a run, so the scene is a complete description of it.
 */

#include <deal.II/base/mpi.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace suturesim::io
{
  /// When a run writes checkpoints: every @p steps accepted steps and every @p minutes of
  /// wall time, whichever comes first (0: never by that count).
  class CheckpointSchedule
  {
  public:
    CheckpointSchedule(unsigned steps, double minutes, MPI_Comm comm);

    /// Whether a checkpoint is due after the accepted step just taken; the same answer
    /// on every process (rank 0's clock decides the minutes).
    bool
    due();

    bool
    enabled() const
    {
      return steps > 0 || minutes > 0;
    }

  private:
    unsigned                              steps, since = 0;
    double                                minutes;
    MPI_Comm                              comm;
    std::chrono::steady_clock::time_point last;
  };

  /// Writes the checkpoint of @p directory: @p shared by rank 0, @p local by every
  /// process (collective). WriteError (io/checked_output.h) naming the file when a write
  /// fails.
  void
  write_checkpoint(const std::string &directory, const nlohmann::json &shared, const nlohmann::json &local,
                   MPI_Comm comm);

  /// The checkpoint of @p directory, read by every process: its shared part and this
  /// process's own. InputError naming --restart when there is none, it cannot be read,
  /// or it was written by another number of processes.
  std::pair<nlohmann::json, nlohmann::json>
  read_checkpoint(const std::string &directory, MPI_Comm comm);

  /// Removes the checkpoint of @p directory (a fresh run into a folder that holds one).
  void
  remove_checkpoint(const std::string &directory);

  /// An array of doubles as one binary CBOR string (compact for the tissue's vectors).
  nlohmann::json
  pack_doubles(const std::vector<double> &values);
  std::vector<double>
  unpack_doubles(const nlohmann::json &packed);
} // namespace suturesim::io
