#pragma once
/**
 * @file
 * The tissue's XPBD sweeps on several threads (integrator xpbd, `Threads` ≥ 2), by
 * domain decomposition: the tissue's nodes are cut into one slab per thread along the
 * tissue's longest extent, each family with blocks (Interaction::partition) is reordered
 * so that block p holds its constraints within slab p, and a sweep is then
 *   1. every thread p: its slab's nodes copied out, block p of each family swept on the
 *      copy (Gauss–Seidel), the copy written back;
 *   2. the haptic thread: each family's interface (constraints spanning slabs), and the
 *      families without blocks.
 * Blocks of different slabs share no node, so step 1 is race-free, and the result is
 * the same for any timing: a sequential Gauss–Seidel sweep in the order (block 0,
 * block 1, …, interface), a different order from one thread's (the same converged
 * step). Working on a copy matters: the system numbers nodes as the mesh generator did,
 * which interleaves the slabs, so most cache lines of the shared positions hold nodes of
 * both slabs (52 % on the seed-004-scale block), and sweeping them in place moves those
 * lines between the cores at every write (on that benchmark 2.5 times as slow as one
 * thread; splitting each colour group instead of slabs, 2.7: measured with development
 * builds of those designs, which were not kept).
 *
 * Between the prediction and the sweeps the first helper finds the projected contacts,
 * on a copy of the predicted positions, while the haptic thread starts the multipliers
 * (detect_contacts_beside()). The warm start stays on the haptic thread: in slabs it
 * measured slower than there (its first writes to the multipliers of the helper's slab
 * each step move their cache lines between the cores).
 */

#include <suturesim/core/worker_team.h>
#include <suturesim/realtime/system.h>

#include <chrono>
#include <vector>

namespace suturesim::realtime
{
  class SlabSweep
  {
  public:
    /// @p threads ≥ 2 threads: the caller and threads − 1 helpers.
    explicit SlabSweep(unsigned threads);

    unsigned
    threads() const
    {
      return team.size();
    }

    /// Cuts the tissue of @p s into slabs and reorders its families (the interactions
    /// before System::first_suture_interaction); once, before the first sweep.
    void
    partition(System &s);

    /// Runs System::detect_contacts(@p at, projected) on the first helper while the
    /// caller runs @p work(); returns the time the caller then waited for the helper.
    template <typename Work>
    std::chrono::steady_clock::duration
    detect_contacts_beside(System &s, const Matrix3Xd &at, const Work &work)
    {
      const auto detect = [&](unsigned) { s.detect_contacts(at, System::Contacts::projected); };
      team.start(detect);
      try
        {
          work();
        }
      catch (...)
        {
          team.wait(); // the helper's job refers to this frame
          throw;
        }
      const auto start = std::chrono::steady_clock::now();
      team.wait();
      return std::chrono::steady_clock::now() - start;
    }

    /// One sweep over the tissue's families.
    void
    sweep(System &s, double dt);

  private:
    struct Slab
    {
      std::vector<std::uint32_t> nodes; ///< ascending: the copy streams through memory
      Matrix3Xd                  x;
      VectorXd                   w;
    };
    WorkerTeam        team;
    std::vector<Slab> slabs;
  };
} // namespace suturesim::realtime
