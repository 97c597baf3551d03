// Knots tied by seed 002's planner in a shipped scene (issue 30, item 3): the overhand
// knot in the realtime path, read back from the suture's last state as its Gauss code
// in the planner's projection.
#include "run_scene.h"

#include <gtest/gtest.h>

#include <string>

using namespace suturesim::test_support;

TEST(KnotScene, TheOverhandIsTiedWithTheTrefoilsCrossings)
{
  const auto r = run_suturesim("knot_overhand", {source_path("parameters/knots/overhand.prm")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_TRUE(r.has_summary);
  const auto &knot = r.summary["metrics"]["knot"];
  EXPECT_EQ(knot["phase"], "done") << knot.dump();
  EXPECT_EQ(knot["instructions_done"], 3);
  // read from the last state, not from the planner: the trefoil cut open
  // (tests/realtime/knot_diagram_test.cc draws it from its parametric curve)
  EXPECT_EQ(knot["gauss_code"], "O1 U2 O3 U1 O2 U3");
  EXPECT_EQ(knot["crossings"], 3);
  EXPECT_EQ(knot["raw_gauss_code"], knot["gauss_code"]) << "no wiggle to reduce";
  EXPECT_TRUE(knot["tied"].get<bool>());
  // one event per instruction, in order, each adding the crossing it made
  std::vector<std::string> codes;
  double                   last = 0;
  for (const auto &e : r.summary["events"])
    if (e["kind"] == "knot_crossing")
      {
        EXPECT_GT(e["time"].get<double>(), last);
        last = e["time"].get<double>();
        codes.push_back(e["gauss_code"]);
      }
  EXPECT_EQ(codes, (std::vector<std::string>{"O1 U1", "O1 U2 U1 O2", "O1 U2 O3 U1 O2 U3"}));
  // the rope followed its end (the planner fails at 10 % stretch of the end's link) and
  // the transient collision constraints acted where strands touched: after their
  // correction no two segments are closer than the suture's diameter (to 1 %)
  EXPECT_LT(r.summary["metrics"]["suture_stretch_max"].get<double>(), 0.05);
  const auto &self = r.summary["metrics"]["self_collision"];
  EXPECT_GT(self["pair_steps"].get<double>(), 0);
  EXPECT_GT(self["min_distance"].get<double>(), 0.99 * self["reach"].get<double>());
}
