#include <suturesim/realtime/haptic_loop.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <thread>

namespace suturesim::realtime
{
  namespace
  {
    /// A steady-clock duration in µs, as the timing records keep it.
    template <typename Duration>
    float
    microseconds(const Duration d)
    {
      return std::chrono::duration<float, std::micro>(d).count();
    }
  } // namespace

  HapticLoop::HapticLoop(World &w, const double rate, const std::size_t expected_steps,
                         const bool pace)
    : world(w)
    , period(std::chrono::nanoseconds(static_cast<long long>(std::llround(1e9 / rate))))
    , pacing(pace)
    , next_tick(std::chrono::steady_clock::now())
  {
    for (auto *v : {&times, &whole, &collision, &solve, &coupling, &recording})
      v->reserve(expected_steps);
  }

  void
  HapticLoop::begin_tick()
  {
    // a tick already begun keeps its start (and a paced loop does not sleep twice)
    if (open)
      return;
    if (pacing)
      {
        next_tick += period;
        std::this_thread::sleep_until(next_tick);
      }
    begun = std::chrono::steady_clock::now();
    open  = true;
  }

  const std::vector<ToolForce> &
  HapticLoop::tick(const std::vector<ToolPose> &poses)
  {
    if (!open)
      begin_tick();
    open                                 = false;
    started                              = std::chrono::steady_clock::now();
    const std::vector<ToolForce> &result = world.step(poses);
    const auto                    spent  = std::chrono::steady_clock::now() - started;
    const auto                   &phases = world.phases();
    times.push_back(microseconds(spent));
    collision.push_back(microseconds(phases.collision));
    // the tools' poses computed before the step are part of the coupling
    coupling.push_back(microseconds(phases.coupling + (started - begun)));
    solve.push_back(microseconds(spent - phases.collision - phases.coupling));
    return result;
  }

  void
  HapticLoop::end_tick()
  {
    const auto now = std::chrono::steady_clock::now();
    whole.push_back(microseconds(now - begun));
    // after the step
    recording.push_back(microseconds(now - started) - times.back());
  }

  namespace
  {
    /// Median, nearest-rank 99th percentile, maximum and mean of @p times (µs), and the
    /// times over the deadline @p period.
    LoopStatistics
    summarise(const std::vector<float> &times, const std::chrono::nanoseconds period)
    {
      LoopStatistics s;
      s.steps           = times.size();
      s.deadline_us     = std::chrono::duration<double, std::micro>(period).count();
      s.deadline_misses = static_cast<std::size_t>(
        std::count_if(times.begin(), times.end(), [&](const float t) { return t > s.deadline_us; }));
      if (times.empty())
        return s;
      std::vector<float> sorted(times);
      std::sort(sorted.begin(), sorted.end());
      const auto at = [&](const double q) {
        // nearest rank
        const std::size_t k =
          std::min(sorted.size() - 1, std::size_t(std::ceil(q * sorted.size())) - (q > 0 ? 1 : 0));
        return double(sorted[k]);
      };
      s.median_us = sorted.size() % 2 ? sorted[sorted.size() / 2]
                                      : 0.5 * (double(sorted[sorted.size() / 2 - 1]) + sorted[sorted.size() / 2]);
      s.p99_us  = at(0.99);
      s.max_us  = sorted.back();
      s.mean_us = std::accumulate(sorted.begin(), sorted.end(), 0.0) / sorted.size();
      return s;
    }
  } // namespace

  LoopStatistics
  HapticLoop::statistics() const
  {
    return summarise(times, period);
  }

  LoopStatistics
  HapticLoop::tick_statistics() const
  {
    return summarise(whole, period);
  }

  PhaseStatistics
  HapticLoop::phase_statistics() const
  {
    return {summarise(collision, period), summarise(solve, period), summarise(coupling, period),
            summarise(recording, period)};
  }
} // namespace suturesim::realtime
