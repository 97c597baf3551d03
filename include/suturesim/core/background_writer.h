#pragma once
/**
 * @file
 * Output off the haptic thread: a writer thread drains what the haptic thread hands it,
 * rows of numbers (forces.csv) through a bounded single-producer, single-consumer ring
 * and whole states (the .vtu files' data) through a few preallocated slots, and calls the
 * sinks that format and write them. The producer's calls allocate nothing, take no lock
 * and never wait: a full ring drops the row and a state without a free slot is dropped,
 * both counted (the record reports the counts; a run that drops has a disk slower than
 * its output rate). The writer polls and sleeps 1 ms when idle, so the haptic thread
 * makes no system call to wake it.
 *
 * The ring is Lamport's single-producer, single-consumer queue with acquire/release
 * indices (Lamport 1983, "Specifying concurrent program modules", ACM TOPLAS 5(2):190;
 * the C++ memory-model form as in Boost.Lockfree's spsc_queue).
 */

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <exception>
#include <functional>
#include <stdexcept>
#include <thread>
#include <vector>

namespace suturesim
{
  template <typename State>
  class BackgroundWriter
  {
  public:
    /// What the writer thread calls: a row of row_width numbers, a state, and a flush
    /// of what the row sink buffered (at most every 100 ms, and at the end). A sink that
    /// throws stops the writer; finish() rethrows its exception.
    struct Sinks
    {
      std::function<void(const double *row)> row;
      std::function<void(const State &)>     state;
      std::function<void()>                  flush;
    };

    /// @p row_capacity rows of @p row_width numbers (rounded up to a power of two) and
    /// @p n_slots copies of @p prototype, sized as every state will be (assigning a state
    /// of the same sizes into a slot then allocates nothing). Starts the writer thread.
    BackgroundWriter(const std::size_t row_width, const std::size_t row_capacity, const State &prototype,
                     const std::size_t n_slots, Sinks sinks)
      : width(row_width)
      , capacity(round_up(row_capacity))
      , rows(capacity * row_width)
      , slots(n_slots)
      , sink(std::move(sinks))
    {
      if (row_width == 0 || n_slots == 0 || !sink.row || !sink.state || !sink.flush)
        throw std::invalid_argument("BackgroundWriter: no columns, no state slot or a sink missing");
      for (auto &s : slots)
        s.state = prototype;
      thread = std::thread([this] { run(); });
    }

    BackgroundWriter(const BackgroundWriter &) = delete;
    BackgroundWriter &
    operator=(const BackgroundWriter &) = delete;

    /// Drains and joins if finish() was not called (an exception unwinding the run):
    /// what was handed over is still written, and a sink's error is dropped.
    ~BackgroundWriter()
    {
      if (thread.joinable())
        {
          stop.store(true, std::memory_order_release);
          thread.join();
        }
    }

    /// Hands over a row of row_width numbers; false when the ring is full (the row is
    /// dropped and counted). Haptic thread only.
    bool
    push_row(const double *row) noexcept
    {
      const std::uint64_t h = head.load(std::memory_order_relaxed);
      if (h - tail.load(std::memory_order_acquire) == capacity)
        {
          ++row_drops;
          return false;
        }
      std::memcpy(rows.data() + (h & (capacity - 1)) * width, row, width * sizeof(double));
      head.store(h + 1, std::memory_order_release);
      return true;
    }

    /// A free slot to fill, or nullptr when the writer holds them all (the state is
    /// dropped and counted). Haptic thread only; publish() the slot after filling it.
    State *
    acquire_state() noexcept
    {
      for (auto &s : slots)
        if (s.status.load(std::memory_order_acquire) == free)
          {
            s.status.store(filling, std::memory_order_relaxed);
            return &s.state;
          }
      ++state_drops;
      return nullptr;
    }

    /// A free slot, waiting for the writer to free one; nullptr if the writer stopped on
    /// an error. For a state that must be written (the run's last), never in a tick.
    State *
    wait_for_state()
    {
      for (;;)
        {
          if (stopped.load(std::memory_order_acquire))
            return nullptr;
          for (auto &s : slots)
            if (s.status.load(std::memory_order_acquire) == free)
              {
                s.status.store(filling, std::memory_order_relaxed);
                return &s.state;
              }
          std::this_thread::sleep_for(std::chrono::milliseconds(1));
        }
    }

    /// Hands the slot @p state (from acquire_state()) to the writer, which writes the
    /// states in the order they were published.
    void
    publish(State *state) noexcept
    {
      for (auto &s : slots)
        if (&s.state == state)
          {
            s.sequence = next_sequence++;
            s.status.store(ready, std::memory_order_release);
          }
    }

    /// Writes everything handed over, joins the writer thread and rethrows a sink's
    /// exception. Call once, from the haptic thread, after the last hand-over.
    void
    finish()
    {
      if (!thread.joinable())
        return;
      stop.store(true, std::memory_order_release);
      thread.join();
      if (error)
        std::rethrow_exception(error);
    }

    /// The writer thread's time in its sinks (formatting, compressing, writing), s; read
    /// after finish().
    double
    busy_seconds() const
    {
      return std::chrono::duration<double>(busy).count();
    }

    /// Whether a sink failed (finish() rethrows why): the writer takes nothing more.
    bool
    failed() const noexcept
    {
      return stopped.load(std::memory_order_acquire);
    }

    std::size_t
    rows_dropped() const
    {
      return row_drops;
    }
    std::size_t
    states_dropped() const
    {
      return state_drops;
    }

  private:
    enum Status : int
    {
      free,
      filling,
      ready
    };
    struct Slot
    {
      State             state;
      std::atomic<int>  status{free};
      std::uint64_t     sequence = 0; ///< written by the producer before status = ready
    };

    static std::size_t
    round_up(const std::size_t n)
    {
      std::size_t p = 1;
      while (p < n)
        p *= 2;
      return p;
    }

    /// Writes what is there; true if there was anything.
    bool
    drain()
    {
      bool                did = false;
      const std::uint64_t h   = head.load(std::memory_order_acquire);
      for (std::uint64_t t = tail.load(std::memory_order_relaxed); t != h; ++t)
        {
          sink.row(rows.data() + (t & (capacity - 1)) * width);
          tail.store(t + 1, std::memory_order_release);
          did = true;
        }
      // the states in the order published: the next one only (a slot published later
      // may be seen ready before it)
      for (;;)
        {
          Slot *next = nullptr;
          for (auto &s : slots)
            if (s.status.load(std::memory_order_acquire) == ready && s.sequence == next_to_write)
              next = &s;
          if (!next)
            break;
          sink.state(next->state);
          next->status.store(free, std::memory_order_release);
          ++next_to_write;
          did = true;
        }
      return did;
    }

    void
    run()
    {
      using clock     = std::chrono::steady_clock;
      auto last_flush = clock::now();
      bool unflushed  = false;
      try
        {
          for (;;)
            {
              // read before draining: whatever was handed over before stop is drained below
              const bool stopping = stop.load(std::memory_order_acquire);
              const auto start    = clock::now();
              const bool did      = drain();
              unflushed           = unflushed || did;
              if (unflushed && (stopping || clock::now() - last_flush > std::chrono::milliseconds(100)))
                {
                  sink.flush();
                  unflushed  = false;
                  last_flush = clock::now();
                }
              busy += clock::now() - start;
              if (stopping)
                return;
              if (!did)
                std::this_thread::sleep_for(std::chrono::milliseconds(1));
            }
        }
      catch (...)
        {
          error = std::current_exception();
          stopped.store(true, std::memory_order_release);
        }
    }

    const std::size_t          width, capacity;
    std::vector<double>        rows;
    std::vector<Slot>          slots;
    Sinks                      sink;
    std::atomic<std::uint64_t> head{0}, tail{0};
    std::atomic<bool>          stop{false}, stopped{false}; ///< stopped: the writer gave up on an error
    std::uint64_t              next_sequence = 0; ///< producer: of the next state published
    std::uint64_t              next_to_write = 0; ///< writer: of the next state to write
    std::size_t                row_drops = 0, state_drops = 0;
    std::exception_ptr         error;
    std::chrono::steady_clock::duration busy{0};
    std::thread                thread;
  };
} // namespace suturesim
