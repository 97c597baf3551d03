#pragma once
/**
 * @file
 * The fixed-rate loop a haptic device runs: every 1/rate seconds, step(tool poses) →
 * tool forces. Two times are measured (steady clock) against the deadline 1/rate: the
 * step alone (tick() to its return) and the whole tick, from begin_tick() (or the step's
 * start when the caller does not call it) to end_tick(), which the caller calls once the
 * haptic thread's other work for the tick is done (the closure measured, the row
 * recorded, a state written). Between begin_tick() and tick() the caller computes the
 * tool poses (prescribed paths, a knot planner reading the rope). The whole tick is
 * what a device waits for. Their statistics (median, 99th percentile, maximum, misses)
 * are what summary.json reports. With pacing on, the loop sleeps until the next tick, as a device
 * thread would; offline runs leave it off and step back to back.
 *
 * Haptic rendering wants ≥ 1 kHz ("1000 Hz is the gold standard", iMSTK documentation).
 */

#include <suturesim/realtime/world.h>

#include <chrono>
#include <vector>

namespace suturesim::realtime
{
  struct LoopStatistics
  {
    std::size_t steps            = 0;
    double      median_us        = 0;
    double      p99_us           = 0;
    double      max_us           = 0;
    double      mean_us          = 0;
    std::size_t deadline_misses  = 0;
    double      deadline_us      = 0;
  };

  /// The whole tick by phase: contact detection and collision responses (collision),
  /// the tools' poses computed before the step (between begin_tick() and tick()), the
  /// tools, prescribed motions, loads, the suture model's preparation of the step
  /// (SutureModel::before_step) and tool forces (coupling), the rest of the
  /// step (solve: the integrator's sweeps, the divergence guard), and what the haptic
  /// thread does after the step until end_tick() (recording: the closure measured, the
  /// row and any state handed to the writer).
  struct PhaseStatistics
  {
    LoopStatistics collision, solve, coupling, recording;
  };

  class HapticLoop
  {
  public:
    /// @p expected_steps reserves the timing record (no allocation while stepping).
    HapticLoop(World &world, double rate, std::size_t expected_steps, bool pacing = false);

    /// Begins a tick before the work that computes its tool poses (after the pacing
    /// sleep): the whole tick and its coupling phase count that work. A second call
    /// before tick() does nothing.
    void
    begin_tick();

    /// One tick: the world's step, timed; the tick itself runs on until end_tick().
    const std::vector<ToolForce> &
    tick(const std::vector<ToolPose> &poses);

    /// Ends the tick the last begin_tick() (or tick()) began: its time from then is the
    /// whole tick's (tick_times()).
    void
    end_tick();

    /// The step alone.
    LoopStatistics
    statistics() const;

    /// The whole tick (begin_tick() or tick() to end_tick()).
    LoopStatistics
    tick_statistics() const;

    /// The whole tick's phases (ticks ended by end_tick()).
    PhaseStatistics
    phase_statistics() const;

    /// Compute time of each step so far, µs.
    const std::vector<float> &
    step_times() const
    {
      return times;
    }

    /// Whole time of each tick ended so far, µs.
    const std::vector<float> &
    tick_times() const
    {
      return whole;
    }

  private:
    World                                &world;
    std::chrono::nanoseconds              period;
    bool                                  pacing;
    std::chrono::steady_clock::time_point next_tick;
    std::chrono::steady_clock::time_point begun;   ///< the current tick began
    std::chrono::steady_clock::time_point started; ///< the current tick's step began
    bool                                  open = false; ///< begin_tick() began this tick
    std::vector<float>                    times, whole;
    std::vector<float>                    collision, solve, coupling, recording; ///< µs, per tick
  };
} // namespace suturesim::realtime
