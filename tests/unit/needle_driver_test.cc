// The needle-driver task as shipped (parameters/tasks/needle_driver.prm, issue 31 item 1):
// the pass, the driver letting go and taking the needle again by its tip, the suture
// drawn through; and the one-line refusals of what cannot let a needle go.
#include "run_scene.h"
#include "stitch_checks.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>

using namespace suturesim::test_support;

namespace
{
  const std::string driver_scene = "parameters/tasks/needle_driver.prm";

  Args
  driver_with(const Args &sets)
  {
    Args a = {source_path(driver_scene)};
    for (const auto &s : sets)
      {
        a.push_back("--set");
        a.push_back(s);
      }
    return a;
  }
} // namespace

TEST(NeedleDriver, LetsGoTakesTheTipAndDrawsTheSutureThroughAllFourHoles)
{
  const auto r = run_suturesim("needle_driver", driver_with({}));
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(r.has_summary);
  EXPECT_EQ(r.summary["status"], "completed");
  // the acceptance: each of the four punctures at the threshold within 5 %
  const auto kinds = event_kinds_punctures_at(r, 0.7); // N, Puncture/Threshold
  const auto at = [&](const std::string &kind) { return std::find(kinds.begin(), kinds.end(), kind) - kinds.begin(); };
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "puncture_entry"), 2);
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "puncture_exit"), 2);
  // let go after the fourth puncture, taken again before the suture reaches a hole
  const auto last_puncture = kinds.rend() - std::find(kinds.rbegin(), kinds.rend(), "puncture_exit") - 1;
  EXPECT_GT(at("needle_released"), last_puncture);
  EXPECT_GT(at("needle_grasped"), at("needle_released"));
  EXPECT_LT(at("needle_grasped"), at("onto_suture"));
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "onto_suture"), 4) << "the suture through all four holes";
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "released"), 0) << "and none left";

  const auto  &free = r.summary["metrics"]["free_needle"];
  const double move = free["largest_move"];
  std::printf("[ needle driver ] free %.3f s, the centroid moved %.3e m, held by %d pierce points\n",
              free["time_free"].get<double>(), move, free["pierce_points_at_grasp"][0].get<int>());
  EXPECT_NEAR(free["time_free"].get<double>(), 0.5, 1.5e-3); // s: Regrasp duration, to a step
  EXPECT_EQ(free["pierce_points_at_grasp"], nlohmann::json::array({4}));
  // it stayed in the tissue where it was let go, to a quarter of its wire's diameter
  EXPECT_LT(move, 4e-4 / 4);
}

TEST(NeedleDriver, RefusesWhatCannotLetTheNeedleGoInOneLine)
{
  const auto expect_refusal = [](const std::string &name, const Args &args, const std::string &key) {
    const auto r = run_suturesim(name, args);
    EXPECT_EQ(r.exit_code, 2) << r.output;
    EXPECT_FALSE(r.has_summary) << name;
    EXPECT_NE(r.output.find(key), std::string::npos) << r.output;
  };
  // the accurate path moves its needle as a kinematic tool
  expect_refusal("needle_driver_accurate", driver_with({"Model=accurate"}), "Needle/Pass/Regrasp exposure");
  // the free needle's law is the quasi-static one
  expect_refusal("needle_driver_xpbd", driver_with({"Realtime/Integrator=xpbd"}), "Needle/Pass/Regrasp exposure");
  // the planned regrasp and Jaws both
  expect_refusal("needle_driver_both", driver_with({"Needle/Jaws=1: open; 1.2: closed"}), "Needle/Jaws");
  // jaws closing inside the tissue: the driver of parameters/needle_pass.prm turns on by
  // 1 rad while open, its jaws along the needle's circle into the tissue
  const auto inside = run_suturesim("needle_pass_jaws_inside", {source_path("parameters/needle_pass.prm"), "--set",
                                                                "Needle/Jaws=0.8: open; 1.3: closed"});
  EXPECT_EQ(inside.exit_code, 2) << inside.output;
  EXPECT_NE(inside.output.find("the jaws close inside the tissue"), std::string::npos) << inside.output;
  // and where the needle is not: the driver pulled 5 mm on while open
  const auto away = run_suturesim("needle_pass_jaws_away", {source_path("parameters/needle_pass.prm"), "--set",
                                                            "Needle/Jaws=1.8: open; 2.3: closed"});
  EXPECT_EQ(away.exit_code, 2) << away.output;
  EXPECT_NE(away.output.find("m from the needle (they take it within its wire diameter"), std::string::npos)
    << away.output;
  // the jaws must be out of the tissue when they let go
  expect_refusal("needle_driver_grip_inside", driver_with({"Needle/Pass/Grip point=0.4"}), "Needle/Pass/Grip point");
}
