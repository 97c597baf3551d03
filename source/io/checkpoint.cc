#include <suturesim/core/error.h>
#include <suturesim/io/checked_output.h>
#include <suturesim/io/checkpoint.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

namespace suturesim::io
{
  namespace fs = std::filesystem;

  namespace
  {
    std::string
    rank_file(const unsigned rank)
    {
      return "rank-" + std::to_string(rank) + ".cbor";
    }

    /// The folder's checkpoint: checkpoint/, or checkpoint.old/ when a run stopped
    /// between the two renames of write_checkpoint().
    fs::path
    existing(const std::string &directory)
    {
      const fs::path  current = fs::path(directory) / "checkpoint";
      std::error_code error;
      return fs::exists(current, error) || !fs::exists(fs::path(directory) / "checkpoint.old", error)
               ? current
               : fs::path(directory) / "checkpoint.old";
    }

    /// Renames @p from to @p to, WriteError naming @p to when it fails.
    void
    rename_checked(const fs::path &from, const fs::path &to)
    {
      std::error_code error;
      fs::rename(from, to, error);
      if (error)
        throw WriteError(to.string() + ": cannot be written (" + error.message() + ")");
    }
  } // namespace

  CheckpointSchedule::CheckpointSchedule(const unsigned s, const double m, MPI_Comm c)
    : steps(s)
    , minutes(m)
    , comm(c)
    , last(std::chrono::steady_clock::now())
  {}

  bool
  CheckpointSchedule::due()
  {
    if (!enabled())
      return false;
    ++since;
    int by_clock = 0;
    if (minutes > 0)
      {
        by_clock = std::chrono::duration<double>(std::chrono::steady_clock::now() - last).count() >= 60 * minutes;
        by_clock = dealii::Utilities::MPI::broadcast(comm, by_clock, 0);
      }
    if (!by_clock && !(steps > 0 && since >= steps))
      return false;
    since = 0;
    last  = std::chrono::steady_clock::now();
    return true;
  }

  void
  write_checkpoint(const std::string &directory, const nlohmann::json &shared, const nlohmann::json &local,
                   MPI_Comm comm)
  {
    const unsigned rank  = dealii::Utilities::MPI::this_mpi_process(comm);
    const fs::path fresh = fs::path(directory) / "checkpoint.new";
    if (rank == 0)
      {
        std::error_code error;
        fs::remove_all(fresh, error);
        fs::create_directories(fresh, error);
        if (error)
          throw WriteError(fresh.string() + ": cannot be written (" + error.message() + ")");
      }
    MPI_Barrier(comm);
    const auto write = [&](const std::string &name, const nlohmann::json &state) {
      const std::vector<std::uint8_t> bytes = nlohmann::json::to_cbor(state);
      write_whole((fresh / name).string(), std::string(bytes.begin(), bytes.end()));
    };
    if (rank == 0)
      write("shared.cbor", shared);
    write(rank_file(rank), local);
    MPI_Barrier(comm);
    if (rank == 0)
      {
        // the last complete one stays until the new one is in its place; a run stopped
        // between the two renames left it as checkpoint.old
        const fs::path  current = fs::path(directory) / "checkpoint", old = fs::path(directory) / "checkpoint.old";
        std::error_code error;
        if (!fs::exists(current, error) && fs::exists(old, error))
          rename_checked(old, current);
        fs::remove_all(old, error);
        if (fs::exists(current, error))
          rename_checked(current, old);
        rename_checked(fresh, current);
        fs::remove_all(old, error);
      }
    MPI_Barrier(comm);
  }

  std::pair<nlohmann::json, nlohmann::json>
  read_checkpoint(const std::string &directory, MPI_Comm comm)
  {
    const fs::path folder = existing(directory);
    const auto     read   = [&](const std::string &name) {
      const fs::path file = folder / name;
      std::ifstream  in(file, std::ios::binary);
      if (!in)
        throw InputError("--restart " + directory + ": no checkpoint " + file.string() +
                         " (a run writes one with Time/Checkpoint steps or Time/Checkpoint minutes, and when it is "
                         "interrupted)");
      const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
      try
        {
          return nlohmann::json::from_cbor(bytes);
        }
      catch (const nlohmann::json::exception &e)
        {
          throw InputError("--restart " + directory + ": " + file.string() + " is not a checkpoint (" + e.what() + ")");
        }
    };
    // every process reads, and all refuse together (none left waiting in a collective)
    std::pair<nlohmann::json, nlohmann::json> state;
    std::string                               failure;
    try
      {
        state.first          = read("shared.cbor");
        const unsigned count = dealii::Utilities::MPI::n_mpi_processes(comm);
        if (state.first.value("processes", 0u) != count)
          throw InputError("--restart " + directory + ": MPI processes: " +
                           std::to_string(state.first.value("processes", 0u)) + " in the checkpoint, " +
                           std::to_string(count) + " in this run (the tissue's partition must be the same)");
        state.second = read(rank_file(dealii::Utilities::MPI::this_mpi_process(comm)));
      }
    catch (const InputError &e)
      {
        failure = e.what();
      }
    if (dealii::Utilities::MPI::max(int(!failure.empty()), comm))
      throw InputError(failure.empty() ? "--restart " + directory + ": another process could not read its checkpoint"
                                       : failure);
    return state;
  }

  void
  remove_checkpoint(const std::string &directory)
  {
    std::error_code error;
    for (const char *name : {"checkpoint", "checkpoint.new", "checkpoint.old"})
      fs::remove_all(fs::path(directory) / name, error);
  }

  nlohmann::json
  pack_doubles(const std::vector<double> &values)
  {
    std::vector<std::uint8_t> bytes(values.size() * sizeof(double));
    if (!values.empty())
      std::memcpy(bytes.data(), values.data(), bytes.size());
    return nlohmann::json::binary(std::move(bytes));
  }

  std::vector<double>
  unpack_doubles(const nlohmann::json &packed)
  {
    const auto         &bytes = packed.get_binary();
    std::vector<double> values(bytes.size() / sizeof(double));
    if (!values.empty())
      std::memcpy(values.data(), bytes.data(), values.size() * sizeof(double));
    return values;
  }
} // namespace suturesim::io
