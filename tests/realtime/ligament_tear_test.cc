// Seed 003's realtime tearing: the weakest-ligament rule (tearing/ligament_tear.h) on a
// slit whose distances are known, the tear's surface, the wound's ray and separation
// tests, and the springs a tear removes (SpringSet::remove_if).
#include <suturesim/realtime/spring_set.h>
#include <suturesim/tearing/ligament_tear.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace suturesim;
using Eigen::Vector3d;

namespace
{
  constexpr double gap = 0.0004, top = 0.006;

  /// Two faces, x = 0 (lip A) and x = gap (lip B), y in [-10, 10] mm, z in [0, top].
  tearing::Wound
  slit()
  {
    Eigen::Matrix3Xd X(3, 8);
    X << 0, 0, 0, 0, gap, gap, gap, gap,                    //
        -0.01, 0.01, 0.01, -0.01, -0.01, 0.01, 0.01, -0.01, //
        0, 0, top, top, 0, 0, top, top;
    return tearing::Wound(X, {{{0, 1, 2}}, {{0, 2, 3}}, {{4, 5, 6}}, {{4, 6, 7}}}, {1, 1, 1, 1});
  }
} // namespace

TEST(LigamentTear, TheWoundsRayAndSeparationAreItsFacesDistances)
{
  const auto wound = slit();
  // from lip A toward the wound: the first face, A's, at 3 mm
  EXPECT_NEAR(wound.ray({-0.003, 0.002, 0.005}, Vector3d::UnitX()), 0.003, 1e-15);
  // obliquely: 3 mm / cos 60°
  EXPECT_NEAR(wound.ray({-0.003, 0, 0.005}, Vector3d(0.5, std::sqrt(0.75), 0)), 0.006, 1e-15);
  // away from it, or past the faces' end (y > 10 mm), or above them: none
  EXPECT_TRUE(std::isinf(wound.ray({-0.003, 0, 0.005}, -Vector3d::UnitX())));
  EXPECT_TRUE(std::isinf(wound.ray({-0.003, 0.011, 0.005}, Vector3d::UnitX())));
  EXPECT_TRUE(std::isinf(wound.ray({-0.003, 0, 0.0065}, Vector3d::UnitX())));
  // two points on one lip are not separated; across the slit they are
  EXPECT_FALSE(wound.separates({-0.003, 0, 0.005}, {-0.001, 0.004, 0.005}));
  EXPECT_TRUE(wound.separates({-0.003, 0, 0.005}, {0.003, 0, 0.005}));
  EXPECT_FALSE(tearing::Wound().separates({-0.003, 0, 0.005}, {0.003, 0, 0.005}));
}

TEST(LigamentTear, TheTearFollowsTheShorterOfTheLigamentsToTheWoundAndToANeighbour)
{
  const auto     wound = slit();
  const Vector3d X(-0.003, 0, 0.005), toward = Vector3d::UnitX();
  // alone: to the wound, 3 mm ahead; the path ends on A's face and crosses the wound
  auto l = tearing::weakest_ligament(wound, X, toward, {});
  EXPECT_NEAR(l.length, 0.003, 1e-15);
  EXPECT_TRUE(l.to_wound);
  EXPECT_EQ(l.insertion, -1);
  EXPECT_NEAR((l.end - Vector3d(0, 0, 0.005)).norm(), 0, 1e-15);
  // a neighbour 2 mm along the wound is nearer: the tear joins the two holes
  const std::vector<Vector3d> insertions{{0.003, 0.001, 0.005},   // across the wound: not a ligament
                                         {-0.003, 0.0035, 0.005}, // 3.5 mm: farther than the wound
                                         {-0.003, -0.002, 0.005}, // 2 mm: the weakest
                                         X};                      // the point itself: skipped
  l = tearing::weakest_ligament(wound, X, toward, insertions);
  EXPECT_NEAR(l.length, 0.002, 1e-15);
  EXPECT_FALSE(l.to_wound);
  EXPECT_EQ(l.insertion, 2);
  EXPECT_EQ(l.end, insertions[2]);
  // pulled away from the wound, no face lies ahead: the nearest neighbour
  l = tearing::weakest_ligament(wound, X, -toward, {insertions[1]});
  EXPECT_NEAR(l.length, 0.0035, 1e-15);
  EXPECT_FALSE(l.to_wound);
  // nothing at all: no tear path
  EXPECT_TRUE(std::isinf(tearing::weakest_ligament(wound, X, -toward, {}).length));
  EXPECT_EQ(tearing::tear_kind(tearing::TractEnd::groove), "tear_into");
  EXPECT_EQ(tearing::tear_kind(tearing::TractEnd::top), "tear_into");
  EXPECT_EQ(tearing::tear_kind(tearing::TractEnd::bottom), "tear_through");
}

TEST(LigamentTear, TheTearSurfaceCutsTheSegmentsAcrossItOnly)
{
  // the tract from the skin (z = 0) 1 mm down, swept 2 mm along x; a 5 % margin
  const tearing::TearSurface s({0, 0, 0}, {0, 0, -0.001}, {0.002, 0, 0}, 0.05);
  const auto across = [&](const double x, const double z) { return s.crosses({x, -0.0005, z}, {x, 0.0005, z}); };
  EXPECT_TRUE(across(0.001, -0.0005));                                // through its middle
  EXPECT_TRUE(across(0.00205, -0.0005));                              // within the margin past the path's end
  EXPECT_FALSE(across(0.0022, -0.0005));                              // beyond it
  EXPECT_FALSE(across(-0.0001, -0.0005));                             // behind the tract: the path runs forward only
  EXPECT_TRUE(across(0.001, 0.00004));                                // in the skin's plane, within the margin above it
  EXPECT_FALSE(across(0.001, 0.0001));                                // above it
  EXPECT_FALSE(across(0.001, -0.0012));                               // below the tract's end and its margin
  EXPECT_FALSE(s.crosses({0.001, 0, -0.0002}, {0.0015, 0, -0.0003})); // in its plane
  EXPECT_FALSE(s.crosses({0.001, 0.0001, -0.0005}, {0.001, 0.0005, -0.0005})); // short of it
}

TEST(LigamentTear, RemovingSpringsLeavesTheOthersForcesBitForBit)
{
  // a chain of six nodes with springs between neighbours and next-but-one neighbours;
  // the tear removes those crossing x = 2.5: the rest act as a set built without them
  realtime::Matrix3Xd x(3, 6);
  for (int i = 0; i < 6; ++i)
    x.col(i) << i * 1.1, 0.1 * i * i, 0;
  realtime::SpringSet whole("tissue springs"), kept("tissue springs");
  for (std::uint32_t i = 0; i < 6; ++i)
    for (std::uint32_t j = i + 1; j < std::min(6u, i + 3); ++j)
      {
        whole.add(i, j, 1.0, 10.0 + i + j);
        if (!(i <= 2 && j >= 3))
          kept.add(i, j, 1.0, 10.0 + i + j);
      }
  whole.sort();
  kept.sort();
  const std::size_t before = whole.revision();
  EXPECT_EQ(whole.remove_if([](const std::uint32_t i, const std::uint32_t j) { return i <= 2 && j >= 3; }), 3u);
  EXPECT_EQ(whole.size(), kept.size());
  EXPECT_GT(whole.revision(), before);
  realtime::Matrix3Xd f1 = realtime::Matrix3Xd::Zero(3, 6), f2 = f1;
  whole.add_forces(x, f1);
  kept.add_forces(x, f2);
  EXPECT_EQ((f1 - f2).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(whole.energy(x), kept.energy(x));
  EXPECT_EQ(whole.remove_if([](std::uint32_t, std::uint32_t) { return false; }), 0u);
}
