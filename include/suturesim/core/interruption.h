#pragma once
/**
 * @file
 * SIGINT and SIGTERM as a request to stop, not a kill: the handler only records the
 * signal; the run's step loops (core/cutback_stepper.h, the realtime haptic loop) ask at
 * each step boundary, keep the last accepted state as they do after a failed step, and
 * throw Interrupted; main() then writes summary.json with status "interrupted" and exits
 * 128 + the signal (130 for SIGINT, 143 for SIGTERM), the shells' convention. A second
 * signal of the same kind ends the process at once (the default action restored), so a
 * run that does not reach a step boundary can still be stopped.
 *
 * With several MPI processes every rank must stop at the same step: the request is
 * combined over MPI_COMM_WORLD (one integer all-reduce a step; the accurate path's steps
 * cost seconds). mpirun forwards SIGINT/SIGTERM to every rank and, a few seconds later,
 * kills them: a step longer than that cannot be interrupted cleanly under mpirun.
 */

#include <stdexcept>
#include <string>

namespace suturesim
{
  /// A run stopped at a step boundary on a signal; what() says "interrupted by SIGINT
  /// after the step to t = … s; the state is in <where>" (without the last part when
  /// @p where is empty).
  class Interrupted : public std::runtime_error
  {
  public:
    Interrupted(int signal, double t, const std::string &where);
    int signal; ///< SIGINT or SIGTERM
  };

  /// Installs the handlers of SIGINT and SIGTERM (main(), once, after MPI is initialised:
  /// whether the request must be combined among processes is settled here).
  void
  catch_stop_signals();

  /// The signal that asked this run to stop (0: none; always 0 before
  /// catch_stop_signals()), agreed among the MPI processes when there are several.
  /// Collective then: every rank calls it at the same step boundary. With one process an
  /// atomic read, cheap enough for every haptic tick.
  int
  stop_requested();

  /// The signal this process received (0: none), not combined among processes: for a
  /// wait on one rank only (gmsh meshing on rank 0), which then shares its outcome.
  int
  stop_received();
} // namespace suturesim
