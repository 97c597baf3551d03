// The Endo Stitch's double-pointed needle (seed 001 §5): its geometry, a straight half
// from the leading point to the middle where the suture is pinned; and in the world the
// pass to the other jaw, after which the other point leads, refused while a point
// touches the tissue or a hole is still on the needle.
#include <suturesim/realtime/free_needle.h>
#include <suturesim/realtime/world.h>
#include <suturesim/tools/surgical_pass.h>

#include <gtest/gtest.h>

#include <cmath>

#include "realtime/test_meshes.h"
#include "realtime/test_worlds.h"

using namespace suturesim;
using namespace suturesim::realtime;

TEST(DoublePointedNeedle, TheThreadRunsFromTheLeadingPointToTheMiddle)
{
  const auto needle = tools::CurvedNeedle::double_pointed(0.012, 4e-4);
  EXPECT_TRUE(needle.straight());
  EXPECT_DOUBLE_EQ(needle.length(), 0.006);
  // in a pose 30 degrees about x and moved: the tip 6 mm from the middle along the
  // frame's y, the swage at the middle, one tangent along y
  const tools::Pose pose{Vector3d(0.01, -0.02, 0.03), Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 6, Vector3d::UnitX()))};
  const Vector3d    y = pose.orientation * Vector3d::UnitY();
  EXPECT_LT((needle.tip(pose) - (pose.position + 0.006 * y)).norm(), 1e-16);
  EXPECT_LT((needle.swage(pose) - pose.position).norm(), 1e-16);
  for (const double zeta : {0.0, 0.002, 0.006})
    {
      EXPECT_LT((needle.tangent(pose, zeta) - y).norm(), 1e-15) << zeta;
      // a point 1 mm off the needle across it is nearest to the needle's point at zeta
      const Vector3d off = needle.point(pose, zeta) + 1e-3 * (pose.orientation * Vector3d::UnitZ());
      EXPECT_NEAR(needle.closest(pose, off), zeta, 1e-15) << zeta;
    }
  // beyond the tip and on the trailing half: the ends of the thread's needle part
  EXPECT_EQ(needle.closest(pose, pose.position + 0.01 * y), 0);
  EXPECT_EQ(needle.closest(pose, pose.position - 0.004 * y), 0.006);
  // the wire must be thinner than half the needle; it is never free, nor planned as an arc
  EXPECT_THROW(tools::CurvedNeedle::double_pointed(0.012, 0.006), std::invalid_argument);
  EXPECT_THROW(tools::CurvedNeedle::double_pointed(0, 4e-4), std::invalid_argument);
  EXPECT_THROW(FreeNeedle(needle, 7800, 1e-3), std::invalid_argument);
  EXPECT_THROW(tools::plan_pass(needle, tools::PassParameters()), std::invalid_argument);
}

TEST(DoublePointedNeedle, PassedAcrossTheOtherPointLeadsAboutThePinnedMiddle)
{
  // the needle tests' block (top at z = 10 mm), the needle upright over it pointing down,
  // its leading point 4 mm above the top; the suture leaves the middle upwards
  const auto        needle = tools::CurvedNeedle::double_pointed(0.012, 4e-4);
  const auto        mesh   = test_support::box_mesh(0.04, 0.04, 0.01, 10, 10, 3);
  const tools::Pose start{Vector3d(0.013, 0.02, 0.02), Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Vector3d::UnitX()))};
  World             world(test_support::needle_block(mesh, needle, start));
  world.fix_vertices(mesh::vertices_with_tag(mesh::extract_boundary(mesh), 1));
  world.add_needle(needle, test_support::needle_block_coupling(0.2), start, true);
  world.initialize();
  const auto              &x      = world.system().nodes.x;
  const auto               pin    = world.system().suture.begin;
  std::vector<tools::Pose> poses{start};
  world.step(poses);
  const Vector3d down = -Vector3d::UnitZ();
  EXPECT_LT((world.needle()->geometry().tip(world.needle()->pose()) - (start.position + 0.006 * down)).norm(), 1e-15);
  // passed across: the same jaw pose, the other point leads, up; the middle and the
  // suture pinned there stay
  world.reverse_needle();
  world.step(poses);
  const auto &geometry = world.needle()->geometry();
  EXPECT_LT((geometry.tip(world.needle()->pose()) - (start.position - 0.006 * down)).norm(), 1e-15);
  EXPECT_LT((geometry.swage(world.needle()->pose()) - start.position).norm(), 1e-15);
  EXPECT_LT((x.col(pin) - start.position).norm(), 1e-12);
  // and back: the first point leads again, down onto the block: 0.1 mm into its top
  // it presses (0.2 N, below the 0.5 N threshold) and cannot go to the other jaw
  const auto refusal = [&world]() -> std::string {
    try
      {
        world.reverse_needle();
      }
    catch (const std::invalid_argument &e)
      {
        return e.what();
      }
    return "";
  };
  world.reverse_needle();
  const auto move_down = [&](const double from, const double to) {
    for (int k = 1; k <= 100; ++k)
      {
        poses[0].position = start.position + (from + (to - from) * k / 100.0) * down;
        world.step(poses);
      }
  };
  move_down(0, 0.0041);
  ASSERT_NE(world.needle()->puncture_state().touch(), nullptr);
  EXPECT_NE(refusal().find("touches the tissue"), std::string::npos) << refusal();
  // on through the top to 4 mm deep: the tip in the tissue, its hole on the needle's
  // leading half (a hole left on the needle with the tip out: EndoStitch.Refuses…)
  move_down(0.0041, 0.008);
  const auto &points = world.needle()->pierce_points();
  ASSERT_EQ(points.size(), 1U) << "the top punctured";
  EXPECT_FALSE(points[0].on_suture);
  EXPECT_NE(refusal().find("its tip is in the tissue"), std::string::npos) << refusal();

  // a curved needle has one point only
  const tools::CurvedNeedle curved(0.008, 3 * M_PI / 4, 4e-4);
  World                     other(test_support::needle_block(mesh, curved, start));
  other.add_needle(curved, test_support::needle_block_coupling(0.2), start, true);
  other.initialize();
  EXPECT_THROW(other.reverse_needle(), std::invalid_argument);
}
