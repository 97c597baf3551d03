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
 * The first sweep of a step runs beside the contact detection
 * (sweep_beside_detection()): the first helper finds the projected contacts, on a copy
 * of the predicted positions, and then sweeps its slab, while the haptic thread starts
 * the multipliers and sweeps its own slab, the larger one (`Slab share`), so that both
 * reach the interface at about the same time. The contacts are needed only after the
 * tissue's sweep (by the suture's and the contacts' projections), so the detection no
 * longer waits alone: with the detection before the sweep instead, the haptic thread
 * waited 49 µs a tick for it on the seed-004-scale benchmark (docs/realtime.md). The
 * warm start stays on the haptic thread: in slabs it measured slower than there (its
 * first writes to the multipliers of the helper's slab each step move their cache lines
 * between the cores).
 */

#include <suturesim/core/worker_team.h>
#include <suturesim/realtime/system.h>

#include <chrono>
#include <vector>

namespace suturesim::realtime
{
  /// The axis (0, 1, 2) of the tissue's longest extent in @p s, along which threads cut
  /// it into slabs that meet at a plane only (here, and vbd_integrator.cc's colours).
  Eigen::Index
  longest_tissue_axis(const System &s);

  class SlabSweep
  {
  public:
    /// @p threads ≥ 2 threads: the caller and threads − 1 helpers; the caller's slab
    /// holds the fraction @p share of the tissue's nodes, the helpers' share the rest
    /// equally.
    SlabSweep(unsigned threads, double share);

    unsigned
    threads() const
    {
      return team.size();
    }

    /// Cuts the tissue of @p s into slabs and reorders its families (the interactions
    /// before System::first_suture_interaction); once, before the first sweep.
    void
    partition(System &s);

    /// One sweep over the tissue's families.
    void
    sweep(System &s, double dt);

    /// f = the constraint forces of the tissue's families (Interaction::
    /// add_constraint_forces()), each thread its slab's block on a copy of its nodes, then
    /// the interface and the families without blocks on the caller's (the warm start's
    /// refresh). The same forces as one thread's to round-off (another order of the sums
    /// at the slabs' nodes).
    void
    constraint_forces(System &s, double dt, Matrix3Xd &f);

    /// The first sweep of a step, beside the contact detection: the first helper runs
    /// System::detect_contacts(@p at, projected) and then sweeps its slab; the caller runs
    /// @p start() (the multipliers' start, which every slab needs first) and sweeps its
    /// own; the other helpers wait for start() and sweep theirs; then the caller sweeps
    /// the interface. Returns the time the caller waited for the helpers after its slab.
    template <typename Start>
    std::chrono::steady_clock::duration
    sweep_beside_detection(System &s, const double dt, const Matrix3Xd &at, const Start &start)
    {
      started.close();
      std::chrono::steady_clock::time_point own_done;
      team.run([&](const unsigned t) {
        if (t == 0)
          {
            try
              {
                start();
              }
            catch (...)
              {
                started.abandon(); // the helpers' parts return
                throw;
              }
            started.open();
          }
        else
          {
            if (t == 1)
              s.detect_contacts(at, System::Contacts::projected);
            if (!started.pass())
              return;
          }
        sweep_slab(s, dt, t);
        if (t == 0)
          own_done = std::chrono::steady_clock::now();
      });
      const auto waited = std::chrono::steady_clock::now() - own_done;
      sweep_interface(s, dt);
      return waited;
    }

  private:
    /// Thread @p t's block of each family, on a copy of its slab's nodes.
    void
    sweep_slab(System &s, double dt, unsigned t);
    /// The constraints between slabs, and the families without blocks (caller's thread).
    void
    sweep_interface(System &s, double dt);

    struct Slab
    {
      std::vector<std::uint32_t> nodes; ///< ascending: the copy streams through memory
      Matrix3Xd                  x;
      VectorXd                   w;
      Matrix3Xd                  f; ///< constraint_forces()
    };
    WorkerTeam        team;
    double            share; ///< the caller's slab's fraction of the tissue's nodes
    std::vector<Slab> slabs;
    SpinGate          started; ///< sweep_beside_detection(): the multipliers started
  };
} // namespace suturesim::realtime
