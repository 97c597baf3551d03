// Tools shared by both paths: keyframed poses (linear + slerp), the curved needle's
// geometry, and the planned surgical pass (tools/surgical_pass.h: the tip follows the
// needle's own circle through E and X at the planned times, bite depth and entry angle
// as the circle geometry gives them).
#include <suturesim/tools/surgical_pass.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

using namespace suturesim::tools;

TEST(Trajectory, InterpolatesLinearlyAndBySlerpAndHoldsOutside)
{
  Trajectory path;
  const Quaterniond turn(Eigen::AngleAxisd(M_PI / 2, Vector3d::UnitZ()));
  path.add(1, {Vector3d(0, 0, 0), Quaterniond::Identity()});
  path.add(3, {Vector3d(2, 4, 0), turn});
  EXPECT_LT((path.pose(0).position - Vector3d(0, 0, 0)).norm(), 1e-15);
  EXPECT_LT((path.pose(5).position - Vector3d(2, 4, 0)).norm(), 1e-15);
  const Pose mid = path.pose(2);
  EXPECT_LT((mid.position - Vector3d(1, 2, 0)).norm(), 1e-15);
  // halfway in time is halfway in angle (constant angular velocity)
  EXPECT_NEAR(Eigen::AngleAxisd(mid.orientation).angle(), M_PI / 4, 1e-14);
  EXPECT_LT((mid.apply(Vector3d::UnitX()) - Vector3d(1 + std::sqrt(0.5), 2 + std::sqrt(0.5), 0)).norm(), 1e-14);
  const auto [v, omega] = path.velocity(2);
  EXPECT_LT((v - Vector3d(1, 2, 0)).norm(), 1e-14);
  EXPECT_LT((omega - Vector3d(0, 0, M_PI / 4)).norm(), 1e-14);
  EXPECT_EQ(path.velocity(4).first, Vector3d::Zero());
}

TEST(Trajectory, KinksAreTheKeyframesWhereTheVelocityJumps)
{
  // from rest at 1 s a straight move (keyframe 2 s mid-way: not a kink), a steady turn
  // from 3 s (keyframe 4 s mid-way, as slerp keyframes are: not a kink), rest after 5 s
  Trajectory path;
  const auto about_z = [](const double angle) { return Quaterniond(Eigen::AngleAxisd(angle, Vector3d::UnitZ())); };
  path.add(1, {Vector3d(0, 0, 0), Quaterniond::Identity()});
  path.add(2, {Vector3d(1, 0, 0), Quaterniond::Identity()});
  path.add(3, {Vector3d(2, 0, 0), Quaterniond::Identity()});
  path.add(4, {Vector3d(2, 0, 0), about_z(M_PI / 4)});
  path.add(5, {Vector3d(2, 0, 0), about_z(M_PI / 2)});
  EXPECT_EQ(path.kinks(), (std::vector<double>{1, 3, 5}));
  // a keyframe that holds still is no kink either
  Trajectory still;
  still.add(0, {Vector3d(1, 2, 3), Quaterniond::Identity()});
  still.add(1, {Vector3d(1, 2, 3), Quaterniond::Identity()});
  EXPECT_TRUE(still.kinks().empty());
}

TEST(CurvedNeedle, TipSwageTangentAndClosestPoint)
{
  const CurvedNeedle needle(0.01, CurvedNeedle::arc_angle_of("3/8"), 4e-4);
  EXPECT_NEAR(needle.length(), 0.01 * 0.75 * M_PI, 1e-16);
  const Pose pose{Vector3d(1, 2, 3), Quaterniond(Eigen::AngleAxisd(0.7, Vector3d(1, 2, 2).normalized()))};
  EXPECT_LT((needle.swage(pose) - pose.apply(Vector3d(0.01, 0, 0))).norm(), 1e-15);
  EXPECT_LT((needle.tip(pose) - pose.apply(0.01 * Vector3d(std::cos(0.75 * M_PI), std::sin(0.75 * M_PI), 0))).norm(), 1e-15);
  for (const double zeta : {0.0, 0.004, 0.0123, needle.length()})
    {
      // the tangent points towards the tip: the point moves along −t as ζ grows
      const double   h  = 1e-7;
      const double   z  = std::clamp(zeta, h, needle.length() - h);
      const Vector3d fd = (needle.point(pose, z - h) - needle.point(pose, z + h)) / (2 * h);
      EXPECT_LT((fd - needle.tangent(pose, z)).norm(), 1e-7) << zeta;
      EXPECT_NEAR(needle.tangent(pose, zeta).norm(), 1, 1e-15);
      // points off the arc, radially and out of plane, project back to ζ
      const Vector3d radial = (needle.point(pose, zeta) - pose.position).normalized();
      const Vector3d off    = needle.point(pose, zeta) + 0.002 * radial + 0.001 * (pose.orientation * Vector3d::UnitZ());
      EXPECT_NEAR(needle.closest(pose, off), zeta, 1e-12) << zeta;
    }
  // beyond the ends: the nearer end
  EXPECT_NEAR(needle.closest(pose, pose.apply(Vector3d(0.01, -0.001, 0))), needle.length(), 1e-15);
  EXPECT_NEAR(needle.closest(pose, pose.apply(Vector3d(-0.01, -0.0001, 0))), 0, 1e-15);
  EXPECT_THROW(CurvedNeedle::arc_angle_of("5/8"), std::invalid_argument);
}

TEST(SurgicalPass, TipFollowsTheNeedleCircleThroughEntryAndExitAtThePlannedTimes)
{
  for (const std::string shape : {"3/8", "1/2"})
    for (const double depth : {0.004, 0.007})
      {
        const CurvedNeedle needle(0.008, CurvedNeedle::arc_angle_of(shape), 3e-4);
        PassParameters     p;
        p.entry          = Vector3d(0.01, -0.002, 0.006);
        p.normal         = Vector3d(0, 0, 2);
        p.bite_direction = Vector3d(-1, 0.1, 0.3); // not in the surface: projected
        p.bite_depth     = depth;
        p.start_time     = 0.5;
        p.angular_speed  = 2;
        p.pull           = Vector3d(0, 0, 0.03);
        p.pull_duration  = 2;
        const SurgicalPass pass = plan_pass(needle, p);
        const double       R    = needle.radius();
        EXPECT_NEAR(pass.bite_depth, depth, 1e-15);
        EXPECT_NEAR(std::cos(pass.entry_angle), 1 - depth / R, 1e-15);
        EXPECT_NEAR(pass.bite_width, 2 * R * std::sin(pass.entry_angle), 1e-15);
        const auto &path = pass.trajectory;
        EXPECT_LT((needle.tip(path.pose(pass.t_tip_entry)) - p.entry).norm(), 1e-12);
        EXPECT_LT((needle.tip(path.pose(pass.t_tip_exit)) - pass.exit).norm(), 1e-12);
        EXPECT_LT((needle.swage(path.pose(pass.t_swage_exit)) - pass.exit).norm(), 1e-12);
        EXPECT_NEAR(pass.exit[2], p.entry[2], 1e-15); // exit on the same surface
        // during the turn the centre stays put and the tip stays on the circle through
        // E and X; it is below the surface exactly between entry and exit, and the
        // lowest point is the bite depth
        double lowest = 0;
        for (double t = p.start_time; t <= pass.t_turn_end; t += 0.001)
          {
            const Pose     pose = path.pose(t);
            const Vector3d tip  = needle.tip(pose);
            EXPECT_LT((pose.position - pass.centre).norm(), 1e-15);
            EXPECT_NEAR((tip - pass.centre).norm(), R, 1e-12);
            const bool inside = t > pass.t_tip_entry + 1e-9 && t < pass.t_tip_exit - 1e-9;
            EXPECT_EQ(tip[2] < p.entry[2], inside) << t;
            lowest = std::min(lowest, tip[2] - p.entry[2]);
          }
        EXPECT_NEAR(lowest, -depth, 1e-6);
        // entry angle: between the tip's direction of advance and the surface
        const Vector3d t_in = needle.tangent(path.pose(pass.t_tip_entry), 0);
        EXPECT_NEAR(std::atan2(-t_in[2], t_in.head<2>().norm()), pass.entry_angle, 1e-12);
        // the pull translates the needle without turning it
        const Pose end = path.pose(pass.t_end), turned = path.pose(pass.t_turn_end);
        EXPECT_LT((end.position - turned.position - p.pull).norm(), 1e-15);
        EXPECT_LT(end.orientation.angularDistance(turned.orientation), 1e-15);
      }
}

TEST(SurgicalPass, RefusesImpossibleBites)
{
  const CurvedNeedle needle(0.008, M_PI, 3e-4);
  PassParameters     p;
  p.bite_depth = 0.009; // deeper than R
  EXPECT_THROW(plan_pass(needle, p), std::invalid_argument);
  p.bite_depth     = 0.004;
  p.bite_direction = Vector3d::UnitZ(); // along the normal
  EXPECT_THROW(plan_pass(needle, p), std::invalid_argument);
  // a half circle with a full-depth bite (2α + Φ = 2π) would re-enter at E as the
  // swage leaves at X
  p.bite_direction = Vector3d::UnitX();
  p.bite_depth     = 0.008;
  EXPECT_THROW(plan_pass(needle, p), std::invalid_argument);
}

TEST(SurgicalPass, ABiteStraddlesTheWoundCrossingSymmetricallyAndIsTheEquivalentEntryAndDepth)
{
  // b = 5 mm with R = 8 mm is the default stitch: E = (-5, 0, 6) mm, delta = R - sqrt(R^2 - b^2)
  // = 1.7550 mm; the entry and exit are b either side of the crossing, whatever Entry point
  // and Bite depth say, and the pass is the one planned from that entry and depth
  const CurvedNeedle needle(0.008, CurvedNeedle::arc_angle_of("3/8"), 4e-4);
  const double       R = needle.radius();
  for (const double b : {0.002, 0.005, 0.0075})
    {
      PassParameters p;
      p.bite           = b;
      p.crossing       = Vector3d(0.001, -0.003, 0.006);
      p.bite_direction = Vector3d(1, 0, 0.4); // projected into the surface
      p.entry          = Vector3d(7, 7, 7);   // not used
      p.bite_depth     = 0.0001;              // not used
      p.pull           = Vector3d(0, 0, 0.02);
      const auto pass  = plan_pass(needle, p);
      EXPECT_LT((pass.entry - (p.crossing - b * Vector3d::UnitX())).norm(), 1e-15) << b;
      EXPECT_LT((pass.exit - (p.crossing + b * Vector3d::UnitX())).norm(), 1e-15) << b;
      EXPECT_NEAR(pass.bite_depth, R - std::sqrt(R * R - b * b), 1e-15) << b;
      PassParameters same = p;
      same.bite           = 0;
      same.entry          = pass.entry;
      same.bite_depth     = R - std::sqrt(R * R - b * b);
      const auto twin     = plan_pass(needle, same);
      EXPECT_LT((twin.exit - pass.exit).norm(), 1e-15) << b;
      EXPECT_NEAR(twin.t_tip_exit, pass.t_tip_exit, 1e-12) << b;
    }
  // a series moves the crossing with the entry: pass k straddles crossing + k s
  PassParameters p;
  p.bite     = 0.004;
  p.crossing = Vector3d(0, -0.003, 0.006);
  p.pull     = Vector3d(0, 0, 0.02);
  SeriesParameters s;
  s.stitches        = 3;
  s.spacing         = Vector3d(0, 0.004, 0);
  const auto series = plan_series(needle, p, s);
  for (unsigned k = 0; k < 3; ++k)
    EXPECT_LT(((series.passes[k].entry + series.passes[k].exit) / 2 - p.crossing - k * s.spacing).norm(), 1e-15);
  p.bite = 0.0081; // wider than R
  EXPECT_THROW(plan_pass(needle, p), std::invalid_argument);
}

namespace
{
  /// The default stitch's pass (R = 8 mm, 3/8, delta = 1.755 mm, pulled 20 mm up and
  /// tightened), as the scene gives it, and a series of three, 5 mm apart along the
  /// wound (+y), carried over in 1.5 s.
  PassParameters
  default_stitch_pass()
  {
    PassParameters p;
    p.entry         = Vector3d(-0.005, 0, 0.006);
    p.bite_depth    = 0.001755;
    p.angular_speed = 2;
    p.pull          = Vector3d(0, 0.01, 0.02);
    p.tighten       = Vector3d(-0.03, -0.015, -0.03);
    return p;
  }
  SeriesParameters
  three_stitches(const bool interrupted)
  {
    SeriesParameters s;
    s.stitches          = 3;
    s.spacing           = Vector3d(0, 0.005, 0);
    s.transfer_duration = 1.5;
    s.interrupted       = interrupted;
    return s;
  }
} // namespace

TEST(SurgicalSeries, EachPassIsTheSinglePassAndTheNeedleIsOutsideTheSkinBetweenThem)
{
  // the default stitch's pass three times, 5 mm apart along the wound (+y): pass k is
  // plan_pass() at E_k and its own start, and outside the passes' cutting (tip entry to
  // swage exit) no point of the needle is below the skin, here the plane z = 6 mm, also
  // while it is carried over
  const CurvedNeedle   needle(0.008, CurvedNeedle::arc_angle_of("3/8"), 4e-4);
  PassParameters       p           = default_stitch_pass();
  const PassParameters stitch_pass = p;
  SeriesParameters     s           = three_stitches(false);
  const auto           series      = plan_series(needle, p, s);
  ASSERT_EQ(series.passes.size(), 3u);
  for (unsigned k = 0; k < 3; ++k)
    {
      const auto &pass = series.passes[k];
      EXPECT_LT((pass.entry - p.entry - k * s.spacing).norm(), 1e-15);
      PassParameters alone = p;
      alone.entry          = pass.entry;
      alone.start_time     = k == 0 ? 0 : series.passes[k - 1].t_end + s.transfer_duration;
      alone.tighten        = k == 2 ? p.tighten : Vector3d::Zero();
      const auto single    = plan_pass(needle, alone);
      EXPECT_DOUBLE_EQ(pass.t_tip_entry, single.t_tip_entry);
      for (double t = alone.start_time; t <= single.t_tightened; t += 0.01)
        {
          const Pose a = series.trajectory.pose(t), b = single.trajectory.pose(t);
          EXPECT_LT((a.position - b.position).norm(), 1e-15) << k << " " << t;
          EXPECT_LT(a.orientation.angularDistance(b.orientation), 1e-12) << k << " " << t;
        }
    }
  EXPECT_DOUBLE_EQ(series.t_tightened, series.passes[2].t_tightened);
  // (up to the last pull: the tightening draws the needle down beside the tissue)
  double lowest_outside = 1;
  for (double t = 0; t <= series.t_end; t += 0.002)
    {
      bool cutting = false;
      for (const auto &pass : series.passes)
        cutting = cutting || (t > pass.t_tip_entry && t < pass.t_swage_exit);
      if (cutting)
        continue;
      const Pose pose = series.trajectory.pose(t);
      for (int i = 0; i <= 40; ++i)
        lowest_outside = std::min(lowest_outside, needle.point(pose, needle.length() * i / 40)[2] - 0.006);
    }
  // the tip touches the skin at each entry's instant, nowhere lower
  EXPECT_GT(lowest_outside, -1e-9);
  // a shallow bite, 0.2 mm with no approach and a pull 1 mm up: the short way from one
  // pass's end to the next one's start is back through the tissue (Phi + 2 alpha < pi);
  // the series turns on instead, through the arc's part above the skin
  p.bite_depth         = 0.0002;
  p.approach           = 0;
  p.pull               = Vector3d(0, 0, 0.001);
  p.tighten            = Vector3d::Zero();
  const auto shallow   = plan_series(needle, p, s);
  double     lowest    = 1;
  for (double t = shallow.passes[0].t_swage_exit; t <= shallow.passes[1].t_tip_entry; t += 0.002)
    for (int i = 0; i <= 40; ++i)
      lowest = std::min(lowest, needle.point(shallow.trajectory.pose(t), needle.length() * i / 40)[2] - 0.006);
  EXPECT_GT(lowest, -1e-9);
  // one stitch is the single pass, bit for bit (a scene's one pass runs as it did)
  s.stitches       = 1;
  const auto one   = plan_series(needle, stitch_pass, s).trajectory.keyframes();
  const auto alone = plan_pass(needle, stitch_pass).trajectory.keyframes();
  ASSERT_EQ(one.size(), alone.size());
  for (auto a = one.begin(), b = alone.begin(); a != one.end(); ++a, ++b)
    {
      EXPECT_EQ(a->first, b->first);
      EXPECT_EQ(a->second.position, b->second.position);
      EXPECT_EQ(a->second.orientation.coeffs(), b->second.orientation.coeffs());
    }
}

TEST(SurgicalSeries, AnInterruptedSeriesTightensEachPassAndStopsWhereItsPullAndTighteningStop)
{
  // the default stitch's pass three times 5 mm apart, each tightened: pass k is the
  // single pass with its tightening, the next starting a transfer after it; the
  // tightening lowers the needle 10 mm below the pass, so a lift along the normal comes
  // first, and from the tightening's end to the next tip entry no point of the needle is
  // below the skin (z = 6 mm)
  const CurvedNeedle     needle(0.008, CurvedNeedle::arc_angle_of("3/8"), 4e-4);
  const PassParameters   p      = default_stitch_pass();
  const SeriesParameters s      = three_stitches(true);
  const auto             series = plan_series(needle, p, s);
  ASSERT_EQ(series.passes.size(), 3u);
  for (unsigned k = 0; k < 3; ++k)
    {
      const auto    &pass  = series.passes[k];
      PassParameters alone = p;
      alone.entry          = pass.entry;
      // each transfer after a tightening that lowered the needle: 1.5 times the duration
      alone.start_time  = k == 0 ? 0 : series.passes[k - 1].t_tightened + 1.5 * s.transfer_duration;
      const auto single = plan_pass(needle, alone);
      EXPECT_DOUBLE_EQ(pass.t_tip_entry, single.t_tip_entry) << k;
      EXPECT_DOUBLE_EQ(pass.t_tightened, single.t_tightened) << k;
      for (double t = alone.start_time; t <= single.t_tightened; t += 0.01)
        EXPECT_LT((series.trajectory.pose(t).position - single.trajectory.pose(t).position).norm(), 1e-15) << k;
      if (k == 2)
        break;
      // the lift: straight up by the 10 mm the pull and tightening lowered it
      const Pose   down = series.trajectory.pose(pass.t_tightened);
      const Pose   up   = series.trajectory.pose(pass.t_tightened + 0.5 * s.transfer_duration);
      EXPECT_LT((up.position - down.position - Vector3d(0, 0, 0.01)).norm(), 1e-15);
      // from the lift's end on, back at the pass's height, no point is below the skin
      double lowest = 1;
      for (double t = pass.t_tightened + 0.5 * s.transfer_duration; t <= series.passes[k + 1].t_tip_entry; t += 0.002)
        for (int i = 0; i <= 40; ++i)
          lowest = std::min(lowest, needle.point(series.trajectory.pose(t), needle.length() * i / 40)[2] - 0.006);
      EXPECT_GT(lowest, -1e-9) << k;
    }
  const double never = std::numeric_limits<double>::infinity();
  const std::vector<double> none(3, never);
  // without stops: the plan
  for (double t = 0; t < series.t_tightened + 1; t += 0.05)
    EXPECT_LT((series.pose(t, none, none).position - series.trajectory.pose(t).position).norm(), 1e-15);
  // pass 1's pull stopped halfway: the needle stays there to the pull's end, and the
  // tightening moves it by the planned tightening from there
  const auto  &first = series.passes[0];
  const double half  = 0.5 * (first.t_turn_end + first.t_end);
  const Pose   stop  = series.trajectory.pose(half);
  std::vector<double> pulls = none, ties = none;
  pulls[0]                  = half;
  EXPECT_LT((series.pose(first.t_end - 0.01, pulls, ties).position - stop.position).norm(), 1e-15);
  const double mid = 0.5 * (first.t_end + first.t_tightened);
  EXPECT_LT((series.pose(mid, pulls, ties).position - stop.position - 0.5 * p.tighten).norm(), 1e-12);
  // its tightening stopped at mid: held there until the tightening's planned end, then
  // carried to the second pass's start, which it reaches on time, the plan from there on
  ties[0]          = mid;
  const Pose tied  = series.pose(mid, pulls, ties);
  const double next = series.passes[1].trajectory.keyframes().begin()->first;
  EXPECT_LT((series.pose(first.t_tightened, pulls, ties).position - tied.position).norm(), 1e-15);
  EXPECT_LT((series.pose(next, pulls, ties).position - series.trajectory.pose(next).position).norm(), 1e-15);
  EXPECT_LT((series.pose(series.passes[1].t_tip_entry, pulls, ties).position -
             series.trajectory.pose(series.passes[1].t_tip_entry).position)
              .norm(),
            1e-15);
  // halfway through the transfer, half of the offset is left
  const double during = 0.5 * (first.t_tightened + next);
  EXPECT_LT((series.pose(during, pulls, ties).position - series.trajectory.pose(during).position -
             0.5 * (tied.position - series.trajectory.pose(first.t_tightened).position))
              .norm(),
            1e-12);
  // the last pass, tied early, stays where it was tied
  ties[2] = series.passes[2].t_end + 0.5;
  EXPECT_LT((series.pose(series.t_tightened + 3, pulls, ties).position -
             series.trajectory.pose(ties[2]).position)
              .norm(),
            1e-15);
}

TEST(SurgicalSeries, RefusesASeriesItCannotPlan)
{
  const CurvedNeedle needle(0.008, CurvedNeedle::arc_angle_of("3/8"), 4e-4);
  PassParameters     p;
  p.bite_depth = 0.002;
  p.pull       = Vector3d(0, 0, 0.02);
  SeriesParameters s;
  s.stitches = 2;
  s.spacing  = Vector3d(0, 0.005, 0);
  EXPECT_NO_THROW(plan_series(needle, p, s));
  p.pull = Vector3d(0, 0.03, -0.001); // lowers the needle
  EXPECT_THROW(plan_series(needle, p, s), std::invalid_argument);
  p.pull    = Vector3d(0, 0, 0.02);
  s.spacing = Vector3d(0, 0, 0.005); // out of the surface
  EXPECT_THROW(plan_series(needle, p, s), std::invalid_argument);
  s.spacing = Vector3d::Zero();
  EXPECT_THROW(plan_series(needle, p, s), std::invalid_argument);
  s.stitches = 0;
  EXPECT_THROW(plan_series(needle, p, s), std::invalid_argument);
}
