#include <suturesim/core/error.h>
#include <suturesim/scene/run_summary.h>
#include <suturesim/scene/timed_run.h>

#include <iostream>

namespace suturesim::scene
{
  using namespace dealii;

  void
  run_timed(io::Recorder &recorder, const std::function<void(TimerOutput &, ConditionalOStream &)> &body)
  {
    // A failure is rethrown only after the timer has printed its table (its destructor
    // refuses to communicate while an exception is in flight).
    std::exception_ptr failure;
    {
      MPI_Comm           comm = MPI_COMM_WORLD;
      ConditionalOStream pcout(std::cout, Utilities::MPI::this_mpi_process(comm) == 0);
      TimerOutput        timer(comm, pcout, TimerOutput::never, TimerOutput::wall_times);
      try
        {
          body(timer, pcout);
          RunSummary(recorder.summary()).timings(timer);
          timer.print_summary();
        }
      catch (const SolverError &)
        {
          timer.print_summary();
          failure = std::current_exception();
        }
      catch (...)
        {
          failure = std::current_exception();
        }
    }
    if (failure)
      std::rethrow_exception(failure);
  }
} // namespace suturesim::scene
