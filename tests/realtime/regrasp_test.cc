// The needle driver's planned regrasp (tools/surgical_pass.h, seed 001 §5–6): when the
// jaws let go and take again, where they take the needle, and that the needle, taken
// by its tip, goes on along the pass without the regrasp, later by the regrasp's
// duration; in a running suture, the reload between passes.
#include <suturesim/tools/surgical_pass.h>

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <cmath>

using namespace suturesim;
using namespace suturesim::tools;

namespace
{
  PassParameters
  stitch_pass()
  {
    // parameters/tasks/needle_driver.prm's pass
    PassParameters p;
    p.entry          = Vector3d(-0.005, 0, 0.006);
    p.normal         = Vector3d::UnitZ();
    p.bite_direction = Vector3d::UnitX();
    p.bite_depth     = 0.001755;
    p.angular_speed  = 2;
    p.approach       = 0.001;
    p.pull           = Vector3d(0, 0.01, 0.02);
    p.grip           = 0.15; // 2.8 mm from the swage: out of the tissue when the jaws let go
    return p;
  }

  /// The needle's pose while the driver holds it at angle @p beta along the arc from
  /// where it held it at the start: the driver's frame turned back by β about the
  /// arc's axis (body z through the arc centre, the body origin).
  Pose
  needle_in(const Pose &driver, const double beta)
  {
    return {driver.position, driver.orientation * Quaterniond(Eigen::AngleAxisd(-beta, Vector3d::UnitZ()))};
  }
} // namespace

TEST(Regrasp, JawsLetGoWithTheTipOutAndTakeItAtTheMiddleOfItsExposedPart)
{
  const CurvedNeedle needle(0.008, 3 * M_PI / 4, 4e-4);
  PassParameters     p = stitch_pass();
  const SurgicalPass plain = plan_pass(needle, p);
  EXPECT_TRUE(plain.jaws.empty());
  p.regrasp_exposure       = 0.004;
  p.regrasp_duration       = 0.5;
  const SurgicalPass pass  = plan_pass(needle, p);
  ASSERT_EQ(pass.jaws.size(), 2u);
  const auto [t_open, opens]   = pass.jaws[0];
  const auto [t_close, closes] = pass.jaws[1];
  EXPECT_TRUE(opens);
  EXPECT_FALSE(closes);
  EXPECT_NEAR(t_close - t_open, 0.5, 1e-12);
  // let go with the tip 4 mm (arc length) out of the exit X
  const Pose   released = pass.trajectory.pose(t_open);
  const double R        = needle.radius();
  const double chord    = (needle.tip(released) - pass.exit).norm();
  EXPECT_NEAR(2 * R * std::asin(chord / (2 * R)), 0.004, 1e-9);
  EXPECT_NEAR(t_open, plain.t_tip_exit + 0.004 / (R * p.angular_speed), 1e-12);
  // the jaws (the driver's body point 0.15 of the arc from the swage) end at the
  // needle, lying where it was let go, 2 mm from its tip
  const double   L    = needle.length();
  const Vector3d jaws = pass.trajectory.pose(t_close).apply(needle.body_point(0.85 * L));
  EXPECT_LT((jaws - needle.point(released, 0.002)).norm(), 1e-12);
  // the needle taken there goes on as the pass without a regrasp, 0.5 s later
  const double beta = (0.85 * L - 0.002) / R;
  for (const double tau : {0.0, 0.2, 0.4, plain.t_turn_end - t_open, plain.t_end - t_open})
    {
      const Pose moved = needle_in(pass.trajectory.pose(t_close + tau), beta);
      const Pose as    = plain.trajectory.pose(t_open + tau);
      EXPECT_LT((needle.tip(moved) - needle.tip(as)).norm(), 1e-9) << tau;
      EXPECT_LT((needle.swage(moved) - needle.swage(as)).norm(), 1e-9) << tau;
    }
  EXPECT_NEAR(pass.t_turn_end, plain.t_turn_end + 0.5, 1e-12);
  EXPECT_NEAR(pass.t_end, plain.t_end + 0.5, 1e-12);
  EXPECT_NEAR(pass.t_swage_exit, plain.t_swage_exit + 0.5, 1e-12);
  EXPECT_NEAR(pass.t_tip_exit, plain.t_tip_exit, 1e-12);
}

TEST(Regrasp, RefusesWhatTheExposedTipCannotGive)
{
  const CurvedNeedle needle(0.008, 3 * M_PI / 4, 4e-4);
  PassParameters     p = stitch_pass();
  p.regrasp_exposure   = 0.02; // the turn ends before the tip is out this far
  EXPECT_THROW(plan_pass(needle, p), std::invalid_argument);
  p.regrasp_exposure = 0.004;
  p.grip             = 1; // at the tip
  EXPECT_THROW(plan_pass(needle, p), std::invalid_argument);
  p.grip             = 0.9; // 1.9 mm from the tip: not beyond the middle of 4 mm exposed
  EXPECT_THROW(plan_pass(needle, p), std::invalid_argument);
  p.grip = 1.0 / 3; // 12.6 mm from the tip: in the tissue when they would let go
  EXPECT_THROW(plan_pass(needle, p), std::invalid_argument);
  p.grip             = 0.15;
  p.regrasp_duration = 0;
  EXPECT_THROW(plan_pass(needle, p), std::invalid_argument);
}

// A running suture with the regrasp: after the first pass's pull the other hand holds
// the needle still while the driver's jaws go back to the grip point; the second pass
// then goes as in the series without a regrasp, later by the regrasp and the reload.
TEST(Regrasp, TheReloadHoldsTheNeedleStillAndTheNextPassGoesAsWithoutARegrasp)
{
  const CurvedNeedle needle(0.008, 3 * M_PI / 4, 4e-4);
  PassParameters     p = stitch_pass();
  SeriesParameters   series;
  series.stitches             = 2;
  series.spacing              = Vector3d(0, 0.005, 0);
  series.transfer_duration    = 1;
  const SurgicalSeries plain  = plan_series(needle, p, series);
  p.regrasp_exposure          = 0.004;
  p.regrasp_duration          = 0.5;
  const SurgicalSeries series_r = plan_series(needle, p, series);
  ASSERT_EQ(series_r.passes.size(), 2u);
  ASSERT_EQ(series_r.reloads.size(), 1u); // none after the last pass
  ASSERT_EQ(series_r.jaws.size(), 6u);    // regrasp, reload, regrasp
  const auto [t_a, t_b] = series_r.reloads[0];
  const SurgicalPass &first = series_r.passes[0];
  EXPECT_NEAR(t_a, first.t_end, 1e-12);
  EXPECT_NEAR(t_b - t_a, 0.5, 1e-12);
  EXPECT_EQ(series_r.jaws[2], std::make_pair(t_a, true));
  EXPECT_EQ(series_r.jaws[3], std::make_pair(t_b, false));
  // held by the other hand: the needle where the driver left it, whose frame is back
  // on the needle's own at the end (β = 0: the grip point at the start)
  const double beta = first.regrasp_turn;
  EXPECT_NEAR(beta, (0.85 * needle.length() - 0.002) / needle.radius(), 1e-12);
  const Pose held = needle_in(series_r.trajectory.pose(t_a), beta);
  const Pose back = series_r.trajectory.pose(t_b);
  EXPECT_LT((needle.tip(back) - needle.tip(held)).norm(), 1e-12);
  EXPECT_LT((needle.swage(back) - needle.swage(held)).norm(), 1e-12);
  EXPECT_LT((series_r.trajectory.pose(t_b).apply(needle.body_point(0.85 * needle.length())) -
             needle.point(held, 0.85 * needle.length())) // arc length from the tip
              .norm(),
            1e-12);
  // the transfer and the second pass up to its regrasp, as without one, later by 1 s
  const SurgicalPass &second = series_r.passes[1];
  const double        shift  = second.t_tip_entry - plain.passes[1].t_tip_entry;
  EXPECT_NEAR(shift, 1.0, 1e-12);
  ASSERT_EQ(second.jaws.size(), 2u);
  for (double t = t_b; t < second.jaws[0].first; t += 0.05)
    {
      const Pose as = plain.trajectory.pose(t - shift);
      const Pose is = series_r.trajectory.pose(t);
      EXPECT_LT((needle.tip(is) - needle.tip(as)).norm(), 1e-9) << t;
      EXPECT_LT((needle.swage(is) - needle.swage(as)).norm(), 1e-9) << t;
    }
}
