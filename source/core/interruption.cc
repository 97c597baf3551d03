#include <suturesim/core/interruption.h>

#include <deal.II/base/mpi.h>

#include <csignal>

namespace suturesim
{
  namespace
  {
    volatile std::sig_atomic_t received = 0;

    extern "C" void
    record_signal(const int signal)
    {
      received = signal;
    }
  } // namespace

  Interrupted::Interrupted(const int signal, const std::string &what)
    : std::runtime_error(what)
    , signal(signal)
  {}

  void
  catch_stop_signals()
  {
    struct sigaction action = {};
    action.sa_handler       = record_signal;
    sigemptyset(&action.sa_mask);
    // SA_RESTART: a write or wait under way when the signal arrives is resumed, not
    // failed; SA_RESETHAND: the next signal of the kind is not caught and ends the process
    action.sa_flags = SA_RESTART | SA_RESETHAND;
    sigaction(SIGINT, &action, nullptr);
    sigaction(SIGTERM, &action, nullptr);
  }

  int
  stop_requested()
  {
    int initialized = 0;
    MPI_Initialized(&initialized);
    int finalized = 0;
    MPI_Finalized(&finalized);
    const int local = received;
    if (!initialized || finalized || dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) == 1)
      return local;
    return dealii::Utilities::MPI::max(local, MPI_COMM_WORLD);
  }

  std::string
  signal_name(const int signal)
  {
    if (signal == SIGINT)
      return "SIGINT";
    if (signal == SIGTERM)
      return "SIGTERM";
    return "signal " + std::to_string(signal);
  }
} // namespace suturesim
