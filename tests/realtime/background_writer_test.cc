// The writer thread that takes output off the haptic thread (core/background_writer.h):
// everything handed over is written, in order; with the writer stuck on a slow disk the
// haptic thread's calls return at once, allocate nothing and count what they drop.
#include <gtest/gtest.h>

#include <suturesim/core/background_writer.h>

#include "realtime/allocation_counter.h"

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace suturesim;

namespace
{
  /// A state as the realtime record hands over: a time and a block of numbers.
  struct State
  {
    double              time = 0;
    std::vector<double> values;
  };

  /// What the sinks saw, filled by the writer thread and read after finish().
  struct Written
  {
    std::vector<std::vector<double>> rows;
    std::vector<double>              state_times;
    std::size_t                      flushes = 0;
  };

  BackgroundWriter<State>::Sinks
  sinks_into(Written &w, const std::size_t width, const std::atomic<bool> *hold = nullptr)
  {
    return {[&w, width, hold](const double *row) {
              // a disk that does not answer until the test lets it
              while (hold != nullptr && hold->load())
                std::this_thread::sleep_for(std::chrono::microseconds(100));
              w.rows.emplace_back(row, row + width);
            },
            [&w](const State &s) { w.state_times.push_back(s.time); },
            [&w] { ++w.flushes; }};
  }
} // namespace

TEST(BackgroundWriter, WritesEveryRowAndStateInTheOrderHandedOver)
{
  Written                 written;
  const State             prototype{0, std::vector<double>(1000)};
  BackgroundWriter<State> writer(3, 64, prototype, 2, sinks_into(written, 3));
  std::size_t             states = 0;
  for (int k = 0; k < 1000; ++k)
    {
      const double row[3] = {double(k), 2.0 * k, -1.0 * k};
      while (!writer.push_row(row)) // the test may outrun the writer: wait here, not in a tick
        std::this_thread::yield();
      if (k % 100 == 0)
        if (State *s = writer.acquire_state())
          {
            s->time = k;
            writer.publish(s);
            ++states;
          }
    }
  writer.finish();
  ASSERT_EQ(written.rows.size(), 1000u);
  for (int k = 0; k < 1000; ++k)
    EXPECT_EQ(written.rows[k], (std::vector<double>{double(k), 2.0 * k, -1.0 * k})) << "row " << k;
  ASSERT_EQ(written.state_times.size(), states);
  EXPECT_GE(states, 1u);
  for (std::size_t k = 1; k < states; ++k)
    EXPECT_LT(written.state_times[k - 1], written.state_times[k]);
  EXPECT_GE(written.flushes, 1u); // at least the one at the end
}

TEST(BackgroundWriter, AStuckDiskNeitherBlocksNorAllocatesInTheHapticThread)
{
  Written                 written;
  std::atomic<bool>       hold{true};
  const State             prototype{0, std::vector<double>(1000)};
  BackgroundWriter<State> writer(2, 16, prototype, 2, sinks_into(written, 2, &hold));
  // 48 rows and 3 states while the writer is stuck in its first row: the ring takes 16
  // (the stuck one stays in it until written), the slots 2; the calls return at once
  test_support::start_counting_allocations();
  const auto  start    = std::chrono::steady_clock::now();
  std::size_t accepted = 0, states = 0;
  for (int k = 0; k < 48; ++k)
    {
      const double row[2] = {double(k), 0.5};
      accepted += writer.push_row(row);
    }
  for (int k = 0; k < 3; ++k)
    if (State *s = writer.acquire_state())
      {
        s->time = k;
        s->values.assign(1000, double(k)); // within the slot's capacity
        writer.publish(s);
        ++states;
      }
  const auto elapsed     = std::chrono::steady_clock::now() - start;
  const auto allocations = test_support::stop_counting_allocations();
  std::printf("[ writer ] stuck disk: %zu of 48 rows and %zu of 3 states taken in %.1f us, %zu allocations\n",
              accepted, states, std::chrono::duration<double, std::micro>(elapsed).count(), allocations.total());
  EXPECT_EQ(allocations.total(), 0u);
  EXPECT_EQ(accepted, 16u);
  EXPECT_EQ(writer.rows_dropped(), 32u);
  EXPECT_EQ(states, 2u);
  EXPECT_EQ(writer.states_dropped(), 1u);
  // the disk answers again: what was taken is written, in order
  hold = false;
  writer.finish();
  ASSERT_EQ(written.rows.size(), 16u);
  for (int k = 0; k < 16; ++k)
    EXPECT_EQ(written.rows[k][0], double(k));
  EXPECT_EQ(written.state_times, (std::vector<double>{0, 1}));
}

TEST(BackgroundWriter, ASinksErrorReachesTheHapticThreadAtFinish)
{
  const State             prototype{0, {}};
  BackgroundWriter<State> writer(
    1, 8, prototype, 1,
    {[](const double *) { throw std::runtime_error("forces.csv: No space left on device"); }, [](const State &) {},
     [] {}});
  const double row[1] = {1};
  EXPECT_TRUE(writer.push_row(row));
  EXPECT_THROW(
    {
      try
        {
          writer.finish();
        }
      catch (const std::runtime_error &e)
        {
          EXPECT_STREQ(e.what(), "forces.csv: No space left on device");
          throw;
        }
    },
    std::runtime_error);
}
