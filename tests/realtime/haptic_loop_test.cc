// The haptic loop's clocks (realtime/haptic_loop.h): the whole tick runs from
// begin_tick(), before the tools' poses are computed, to end_tick(), and its phases add
// up to it.
#include <suturesim/realtime/haptic_loop.h>

#include <gtest/gtest.h>

#include "realtime/test_worlds.h"

#include <chrono>
#include <thread>

using namespace suturesim;
using namespace suturesim::realtime;

TEST(HapticLoop, TheWholeTickCountsThePosesComputedBeforeTheStep)
{
  WorldSetup w;
  w.suture          = test_support::make_model<SutureModel::Registry>("xpbd-rod");
  w.suture_geometry = test_support::straight_suture(20, 0.1, Vector3d::Zero(), -Vector3d::UnitZ(), 118, 3.7e-7,
                                                    1.12e-4, 1140);
  w.integrator      = test_support::make_model<Integrator::Registry>("xpbd");
  World world(std::move(w));
  world.add_tool("grasper", {world.system().suture.begin}, {});
  world.initialize();
  HapticLoop            loop(world, 1000, 4);
  std::vector<ToolPose> poses(1);
  // the work around the step, long against a step of this 21-node suture (microseconds) so
  // that a descheduled thread cannot blur the comparisons below
  constexpr double      before_us = 20000, after_us = 10000;
  for (int k = 0; k < 2; ++k)
    {
      loop.begin_tick();
      std::this_thread::sleep_for(std::chrono::microseconds(static_cast<long>(before_us))); // the poses
      loop.begin_tick(); // a second call keeps the tick's start
      loop.tick(poses);
      std::this_thread::sleep_for(std::chrono::microseconds(static_cast<long>(after_us))); // the recording
      loop.end_tick();
    }
  // a tick without begin_tick() starts at the step, as before
  loop.tick(poses);
  loop.end_tick();
  const auto &whole = loop.tick_times(), &step = loop.step_times();
  ASSERT_EQ(whole.size(), 3u);
  for (std::size_t k = 0; k < 2; ++k)
    {
      EXPECT_GE(whole[k], before_us + after_us + step[k]) << k;
      EXPECT_LT(step[k], before_us) << k << ": the step alone leaves the poses out";
    }
  EXPECT_LT(whole[2], before_us) << "no poses timed: the tick began at the step";
  // the phases (median over the three ticks) include the work before the step in the
  // coupling and the work after it in the recording; none exceeds the whole tick
  const auto phases = loop.phase_statistics();
  EXPECT_GE(phases.coupling.max_us, before_us);
  EXPECT_GE(phases.recording.max_us, after_us);
  EXPECT_LE(phases.coupling.max_us, loop.tick_statistics().max_us);
}
