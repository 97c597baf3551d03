#include <suturesim/core/worker_team.h>

#include <chrono>
#include <stdexcept>
#include <utility>

#if defined(__x86_64__) || defined(__i386__)
#  include <immintrin.h>
#endif

namespace suturesim
{
  namespace
  {
    /// The processor's spin-wait hint: frees the pipeline for a sibling hyperthread and
    /// spares the memory-order flush when the awaited store arrives.
    inline void
    pause()
    {
#if defined(__x86_64__) || defined(__i386__)
      _mm_pause();
#endif
    }
  } // namespace

  bool
  SpinGate::pass() const
  {
    unsigned s;
    while ((s = state.load(std::memory_order_acquire)) == closed)
      pause();
    return s == opened;
  }

  WorkerTeam::WorkerTeam(const unsigned threads)
  {
    if (threads == 0)
      throw std::invalid_argument("a worker team of 0 threads");
    finished.store(threads - 1, std::memory_order_relaxed); // nothing posted: nothing to wait for
    helpers.reserve(threads - 1);
    try
      {
        for (unsigned t = 1; t < threads; ++t)
          helpers.emplace_back([this, t] { serve(t); });
      }
    catch (...)
      {
        stop(); // the started helpers use this object
        throw;
      }
  }

  WorkerTeam::~WorkerTeam()
  {
    stop();
  }

  void
  WorkerTeam::stop()
  {
    stopping.store(true, std::memory_order_release);
    epoch.fetch_add(1, std::memory_order_release);
    for (auto &h : helpers)
      h.join();
    helpers.clear();
  }

  void
  WorkerTeam::settle()
  {
    while (finished.load(std::memory_order_acquire) != helpers.size())
      pause();
    failed.store(false, std::memory_order_relaxed);
    failure = nullptr;
  }

  void
  WorkerTeam::post(const Call f, const void *job, const unsigned helper)
  {
    job_call    = f;
    job_context = job;
    job_helper  = helper;
    finished.store(0, std::memory_order_relaxed);
    epoch.fetch_add(1, std::memory_order_release); // publishes the job
  }

  void
  WorkerTeam::wait()
  {
    while (finished.load(std::memory_order_acquire) != helpers.size())
      pause();
    if (failed.load(std::memory_order_relaxed))
      {
        failed.store(false, std::memory_order_relaxed);
        std::rethrow_exception(std::exchange(failure, nullptr));
      }
  }

  void
  WorkerTeam::serve(const unsigned t)
  {
    using clock         = std::chrono::steady_clock;
    std::uint64_t seen  = 0;
    auto          since = clock::now(); // idle since
    unsigned      spins = 0;
    for (;;)
      {
        const std::uint64_t e = epoch.load(std::memory_order_acquire);
        if (stopping.load(std::memory_order_acquire))
          return;
        if (e == seen)
          {
            // idle: spin, then yield after 1 ms, then nap after 10 ms (the clock read
            // only every 256 spins: it costs about as much as the hand-over)
            pause();
            if (++spins % 256 == 0)
              {
                const auto idle = clock::now() - since;
                if (idle > std::chrono::milliseconds(10))
                  std::this_thread::sleep_for(std::chrono::microseconds(100));
                else if (idle > std::chrono::milliseconds(1))
                  std::this_thread::yield();
              }
            continue;
          }
        seen = e;
        if (job_helper == all || job_helper == t)
          try
            {
              job_call(job_context, t);
            }
          catch (...)
            {
              bool first = false;
              if (failed.compare_exchange_strong(first, true))
                failure = std::current_exception();
            }
        finished.fetch_add(1, std::memory_order_release);
        since = clock::now();
        spins = 0;
      }
  }
} // namespace suturesim
