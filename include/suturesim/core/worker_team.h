#pragma once
/**
 * @file
 * A team of helper threads that one thread (the haptic thread) drives through short
 * parallel phases inside a tick: run() gives every thread its part of a job and returns
 * when all parts are done; start() and wait() run a job on the first helper beside the
 * caller's own work. A phase costs two cache-line hand-overs, not a system call: the
 * helpers spin on an atomic epoch with the processor's pause hint, the way OpenMP's
 * active wait policy does (OMP_WAIT_POLICY=active), since waking a sleeping thread takes
 * 10-100 µs on a virtual machine, a third of the tick. An idle helper yields after
 * 1 ms and sleeps in 100 µs naps after 10 ms, so a team left idle between runs costs
 * little. Jobs must not allocate; an exception in a helper's part is rethrown by run()
 * or wait() in the calling thread.
 */

#include <atomic>
#include <cstdint>
#include <exception>
#include <thread>
#include <vector>

namespace suturesim
{
  /// A one-shot gate inside a team's job: the parts that need the caller's earlier work
  /// pass() it (spinning with the pause hint, no system call) once the caller open()s it;
  /// abandon() opens it for a caller whose work failed, and pass() then returns false.
  class SpinGate
  {
  public:
    /// Closes the gate; before the job that passes it is posted.
    void
    close()
    {
      state.store(closed, std::memory_order_relaxed);
    }
    /// Opens it: what the caller wrote before is visible to the parts that pass.
    void
    open()
    {
      state.store(opened, std::memory_order_release);
    }
    void
    abandon()
    {
      state.store(abandoned, std::memory_order_release);
    }
    /// Waits until the gate is open or abandoned; true if opened.
    bool
    pass() const;

  private:
    enum : unsigned
    {
      closed,
      opened,
      abandoned
    };
    alignas(64) std::atomic<unsigned> state{closed};
  };

  class WorkerTeam
  {
  public:
    /// A team of @p threads threads in all: the caller and threads − 1 helpers.
    explicit WorkerTeam(unsigned threads);
    ~WorkerTeam();
    WorkerTeam(const WorkerTeam &) = delete;
    WorkerTeam &
    operator=(const WorkerTeam &) = delete;

    /// Threads in the team, the caller included.
    unsigned
    size() const
    {
      return static_cast<unsigned>(helpers.size()) + 1;
    }

    /// Calls @p job(t) on every thread t of the team (t = 0 the caller) and returns once
    /// all have returned.
    template <typename Job>
    void
    run(const Job &job)
    {
      post(&call<Job>, &job, all);
      try
        {
          job(0);
        }
      catch (...)
        {
          settle(); // the helpers' parts refer to this frame
          throw;
        }
      wait();
    }

    /// Calls @p job(1) on the first helper (the caller's own when the team has none) and
    /// returns at once; @p job must live until wait().
    template <typename Job>
    void
    start(const Job &job)
    {
      if (helpers.empty())
        job(1);
      else
        post(&call<Job>, &job, 1);
    }

    /// Waits until the helpers have finished the job of the last run() or start().
    void
    wait();

  private:
    using Call = void (*)(const void *, unsigned);
    template <typename Job>
    static void
    call(const void *job, const unsigned t)
    {
      (*static_cast<const Job *>(job))(t);
    }
    static constexpr unsigned all = 0;

    void
    post(Call f, const void *job, unsigned helper);
    /// Waits for the helpers' parts and drops their exception (the caller's own is thrown).
    void
    settle();
    void
    serve(unsigned t);
    /// Stops and joins the helpers.
    void
    stop();

    // the job of the current epoch, written by the caller before it bumps the epoch
    Call        job_call    = nullptr;
    const void *job_context = nullptr;
    unsigned    job_helper  = all; ///< all, or the one helper that runs it

    alignas(64) std::atomic<std::uint64_t> epoch{0};
    alignas(64) std::atomic<unsigned> finished{0};
    alignas(64) std::atomic<bool> stopping{false};
    std::exception_ptr       failure; ///< the first helper's exception of the epoch
    std::atomic<bool>        failed{false};
    std::vector<std::thread> helpers;
  };
} // namespace suturesim
