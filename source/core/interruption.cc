#include <suturesim/core/interruption.h>

#include <deal.II/base/mpi.h>

#include <csignal>
#include <sstream>

namespace suturesim
{
  namespace
  {
    volatile std::sig_atomic_t received = 0;
    /// several MPI processes: the request is combined (settled by catch_stop_signals())
    bool several = false;

    std::string
    signal_name(const int signal)
    {
      if (signal == SIGINT)
        return "SIGINT";
      if (signal == SIGTERM)
        return "SIGTERM";
      return "signal " + std::to_string(signal);
    }

    std::string
    describe(const int signal, const double t, const std::string &where)
    {
      std::ostringstream s;
      s << "interrupted by " << signal_name(signal) << " after the step to t = " << t << " s";
      if (!where.empty())
        s << "; the state is in " << where;
      return s.str();
    }

    extern "C" void
    record_signal(const int signal)
    {
      received = signal;
    }
  } // namespace

  Interrupted::Interrupted(const int signal, const double t, const std::string &where)
    : std::runtime_error(describe(signal, t, where))
    , signal(signal)
  {}

  void
  catch_stop_signals()
  {
    int initialized = 0;
    MPI_Initialized(&initialized);
    several = initialized && dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD) > 1;
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
  stop_received()
  {
    return received;
  }

  int
  stop_requested()
  {
    const int local = received;
    return several ? dealii::Utilities::MPI::max(local, MPI_COMM_WORLD) : local;
  }
} // namespace suturesim
