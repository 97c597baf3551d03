#pragma once
/**
 * @file
 * MPI for one process of this program (suturesim, the test and benchmark programs):
 * deal.II's MPI_InitFinalize, with Open MPI's singleton start made cheap and safe.
 *
 * A process started without a launcher (not under mpirun) is an Open MPI singleton.
 * - By default it forks a daemon (orted), which only MPI_Comm_spawn and connect/accept
 *   need; this program uses neither. The MCA parameter ess_singleton_isolated skips it,
 *   a third of a run's start-up (0.3 s of 0.9 s here; the 178 input-error tests, each a
 *   process, 196 s -> 167 s).
 * - An isolated singleton is always job [[0,1],0] (Open MPI 4.1), so every one on the
 *   node takes the same session directory <tmp>/ompi.<host>.<uid>/jf.0/1/0, and the one
 *   that finalizes removes it under the others. One that starts then fails in MPI_Init
 *   ("A call to mkdir was unable to create the desired directory ... jf.0/1", exit 1;
 *   open-mpi/ompi#8510 and #3818; the usual cure is a tmpdir base of one's own, e.g.
 *   idaholab/moose#24459). Measured 2026-12-05: 3 of 179 runs of a 1.7 s realtime scene,
 *   eight at a time, failed so; a study's case did in CI. So each singleton gets its own
 *   base, a fresh directory under the system's temporary directory (TMPDIR), removed
 *   after MPI_Finalize.
 *
 * Both are environment variables that MPI_Init reads; they are removed again after it,
 * so that the processes this one starts (the unit tests' runs of suturesim, and theirs)
 * make their own. Neither is set for a launcher's processes (their daemon owns the
 * session directory), nor when the user has set it (a base the user sets is shared by
 * all singletons again). Other MPIs ignore both.
 */

#include <memory>
#include <string>

namespace dealii::Utilities::MPI
{
  class MPI_InitFinalize;
}

namespace suturesim
{
  /// MPI (and, through deal.II, PETSc) for the lifetime of this object; one thread per
  /// process as the program asks of deal.II.
  class MpiSession
  {
  public:
    MpiSession(int &argc, char **&argv);
    /// MPI_Finalize, then the private session directory's removal.
    ~MpiSession();
    MpiSession(const MpiSession &) = delete;
    MpiSession &
    operator=(const MpiSession &) = delete;

  private:
    /// the session directory base made for this singleton, "" when none was (a
    /// launcher's process, a base set by the user, or none could be made)
    std::string                                               tmpdir;
    std::unique_ptr<dealii::Utilities::MPI::MPI_InitFinalize> mpi;
  };
} // namespace suturesim
