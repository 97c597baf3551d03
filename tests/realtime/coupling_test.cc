// The path-independent coupling rules: Coulomb stick-slip by return mapping and the
// order of pierce points along the thread.
#include <suturesim/coupling/coulomb_friction.h>
#include <suturesim/coupling/node_slip.h>
#include <suturesim/coupling/pierce_order.h>

#include <gtest/gtest.h>

#include <cmath>
#include <random>

using namespace suturesim::coupling;

TEST(CoulombFriction, SticksBelowMuNSlipsAboveAndFreeAtZeroMu)
{
  const FrictionParameters p{0.3, 1000, 0};
  const double             N = 2; // capacity μN = 0.6 N, reached at |ζ − ζ_a| = 0.6 mm
  // stick: the elastic force, anchor kept
  auto r = coulomb_friction(p, 0.0004, 0, N);
  EXPECT_FALSE(r.slipping);
  EXPECT_DOUBLE_EQ(r.force, -0.4);
  EXPECT_DOUBLE_EQ(r.derivative, -1000);
  EXPECT_DOUBLE_EQ(r.anchor, 0);
  // slip both ways: |f| = μN, opposite to the motion, anchor trailing by μN/k_t
  for (const double zeta : {0.002, -0.002})
    {
      r = coulomb_friction(p, zeta, 0, N);
      EXPECT_TRUE(r.slipping);
      EXPECT_DOUBLE_EQ(r.force, -std::copysign(0.6, zeta));
      EXPECT_DOUBLE_EQ(r.derivative, 0);
      EXPECT_DOUBLE_EQ(r.anchor, zeta - std::copysign(0.0006, zeta));
      // the new anchor puts the point exactly on the slip surface: a second evaluation
      // at the same ζ sticks with the same force
      const auto again = coulomb_friction(p, zeta, r.anchor, N);
      EXPECT_NEAR(again.force, r.force, 1e-15);
    }
  // μ = 0: no tangential force at all, whatever the normal force
  const auto free = coulomb_friction({0, 1000, 0}, 0.01, 0, 100);
  EXPECT_EQ(free.force, 0);
  EXPECT_TRUE(free.slipping);
}

TEST(CoulombFriction, AHeldBranchGivesOneSidedSlopesAtTheStickSlipKink)
{
  // At the kink |k_t (ζ − ζ_a)| = μN a central difference straddles both branches and
  // returns the mean of their slopes, −k_t/2, a derivative of neither. Held on the base
  // state's branch, the same difference is that branch's slope: −k_t in stick, 0 in slip.
  const FrictionParameters p{0.3, 1000, 0};
  const double             N = 2, h = 1e-7;
  const auto slope = [&](const double zeta, const FrictionBranch *branch) {
    return (coulomb_friction(p, zeta + h, 0, N, branch).force - coulomb_friction(p, zeta - h, 0, N, branch).force) /
           (2 * h);
  };
  const double kink = 0.0006; // μN/k_t
  EXPECT_NEAR(slope(kink, nullptr), -500, 1e-3);
  for (const double zeta : {kink - 1e-9, kink + 1e-9, -kink - 1e-9})
    {
      const FrictionResult base   = coulomb_friction(p, zeta, 0, N);
      const FrictionBranch branch = FrictionBranch::of(base, zeta);
      EXPECT_EQ(branch.slipping, std::abs(zeta) > kink);
      EXPECT_NEAR(slope(zeta, &branch), base.derivative, 1e-3) << zeta;
      // on its own branch the held law is the law
      EXPECT_DOUBLE_EQ(coulomb_friction(p, zeta, 0, N, &branch).force, base.force);
    }
  // Where a slipping step leaves a point (its anchor returned to k_t |ζ − ζ_a| = μN), the
  // next step starts on the kink and round-off would pick the tangent's branch: there it
  // is slip on either side of the kink within 1e-9 of μN (both carry μN), stick beyond.
  for (const double zeta : {0.001, 0.0013, -0.002, 0.0123})
    {
      const FrictionResult slipped = coulomb_friction(p, zeta, 0, N);
      ASSERT_TRUE(slipped.slipping);
      for (const double nudge : {-1e-12, 0.0, 1e-12})
        {
          const double         at   = zeta + (zeta > 0 ? nudge : -nudge) * kink;
          const FrictionResult next = coulomb_friction(p, at, slipped.anchor, N);
          EXPECT_TRUE(FrictionBranch::of(next, at - slipped.anchor).slipping) << zeta << ", nudge " << nudge;
        }
      const double         inside = zeta - (zeta > 0 ? 1e-8 : -1e-8) * kink;
      const FrictionResult next   = coulomb_friction(p, inside, slipped.anchor, N);
      EXPECT_FALSE(FrictionBranch::of(next, inside - slipped.anchor).slipping) << zeta;
    }
  // a held slip keeps its direction: f = −sign μN even where the gap has reversed
  const FrictionBranch forward{true, 1};
  EXPECT_DOUBLE_EQ(coulomb_friction(p, -0.001, 0, N, &forward).force, -0.6);
  // a held stick stays elastic beyond μN
  const FrictionBranch stick{false, 1};
  EXPECT_DOUBLE_EQ(coulomb_friction(p, 0.002, 0, N, &stick).force, -2.0);
}

TEST(CoulombFriction, SmoothedNormalForceIsExactFarFromZeroAndSmoothAtIt)
{
  const double grip = 0.05, eps = 0.005;
  // ε = 0: the plain N₀ + |f⊥|
  EXPECT_DOUBLE_EQ(normal_force(grip, 2.0, 0).value, 2.05);
  EXPECT_DOUBLE_EQ(normal_force(grip, 2.0, 0).rate, 1.0);
  // no tie force: the grip, and no slope (the kink of |f⊥| is gone)
  EXPECT_DOUBLE_EQ(normal_force(grip, 0, eps).value, grip);
  EXPECT_DOUBLE_EQ(normal_force(grip, 0, eps).rate, 0);
  double worst = 0;
  for (double f = 1e-6; f < 10; f *= 1.1)
    {
      const auto n = normal_force(grip, f, eps);
      worst        = std::max(worst, grip + f - n.value);
      EXPECT_GE(grip + f - n.value, 0) << f;
      // the rate is the derivative (central differences)
      const double h  = 1e-6 * f; // without the grip, so that round-off stays below h
      const double fd = (normal_force(0, f + h, eps).value - normal_force(0, f - h, eps).value) / (2 * h);
      EXPECT_NEAR(n.rate, fd, 1e-6 * std::max(1.0, fd)) << f;
    }
  EXPECT_LT(worst, 0.3003 * eps);
  EXPECT_GT(worst, 0.3 * eps); // the bound is reached (at f = 0.786 ε), not loose
  // far from zero, f − s(f) → ε²/(2f)
  EXPECT_NEAR(grip + 1.0 - normal_force(grip, 1.0, eps).value, eps * eps / 2, 1e-3 * eps * eps);
}

TEST(PierceOrder, PointsThatWouldSwapMoveTogetherAndNeverCross)
{
  // two points pulled towards each other's places
  std::vector<double> z{0.010, 0.004};
  EXPECT_TRUE(keep_order(z, 0.001, 0, 1));
  EXPECT_NEAR(z[0], 0.0065, 1e-15);
  EXPECT_NEAR(z[1], 0.0075, 1e-15);
  // already ordered: untouched
  std::vector<double> ordered{0.001, 0.003, 0.02};
  EXPECT_FALSE(keep_order(ordered, 0.001, 0, 1));
  EXPECT_EQ(ordered, (std::vector<double>{0.001, 0.003, 0.02}));
  // a hard constraint at the upper end stops a block
  std::vector<double> blocked{0.05, 0.2, 0.3};
  keep_order(blocked, 0.01, 0, 0.1);
  EXPECT_NEAR(blocked[2], 0.1, 1e-15);
  EXPECT_NEAR(blocked[1], 0.09, 1e-15);
  EXPECT_NEAR(blocked[0], 0.05, 1e-15);
  // random proposals: the result is always ordered with the gap, inside the bounds,
  // and the least-squares projection (no point moves when nothing is violated)
  std::mt19937                           rng(2);
  std::uniform_real_distribution<double> u(0, 0.1);
  for (int trial = 0; trial < 200; ++trial)
    {
      std::vector<double> p(5);
      for (auto &v : p)
        v = u(rng);
      keep_order(p, 0.002, 0.01, 0.09);
      for (std::size_t k = 0; k + 1 < p.size(); ++k)
        EXPECT_GE(p[k + 1] - p[k], 0.002 - 1e-15);
      EXPECT_GE(p.front(), 0.01 - 1e-15);
      EXPECT_LE(p.back(), 0.09 + 1e-15);
    }
  std::vector<double> crowded{0, 0, 0};
  EXPECT_THROW(keep_order(crowded, 0.1, 0, 0.1), std::invalid_argument);
}

TEST(NodeSlip, AJointHoldsUntilItsPullExceedsFrictionThenMovesOneNodeThatWay)
{
  // seed 001 section 4: joined to node 3; limit 0.1 N
  for (const double pull : {0.09, -0.09, 0.0})
    {
      std::vector<NodeSlipPoint> p{{3, pull, 0.1}};
      EXPECT_EQ(node_slip(p, 0, 10), 0u) << pull;
      EXPECT_EQ(p[0].node, 3);
    }
  for (const double pull : {0.11, 5.0, -0.11})
    {
      std::vector<NodeSlipPoint> p{{3, pull, 0.1}};
      EXPECT_EQ(node_slip(p, 0, 10), 1u) << pull;
      // one node per step, towards where the tissue pulls, however hard
      EXPECT_EQ(p[0].node, pull > 0 ? 4 : 2) << pull;
      EXPECT_EQ(p[0].moved, pull > 0 ? 1 : -1);
    }
  // the thread's ends are hard constraints: no node beyond them
  std::vector<NodeSlipPoint> at_end{{0, -1.0, 0.1}, {10, 1.0, 0.1}};
  EXPECT_EQ(node_slip(at_end, 0, 10), 0u);
  EXPECT_EQ(at_end[0].node, 0);
  EXPECT_EQ(at_end[1].node, 10);
}

TEST(NodeSlip, PointsOnOneNodeKeepTheirListOrderAndSlipAsAGroup)
{
  // seed 001 section 4.2 (Fig. 6): two tissue points on one suture node, in list order
  // (rear, front); forward is towards the front's side.
  // Fig. 6c/e: the front one is pulled forward past its friction: it slips alone,
  // leaving the rear one behind
  std::vector<NodeSlipPoint> c{{5, 0.05, 0.1}, {5, 0.3, 0.1}};
  EXPECT_EQ(node_slip(c, 0, 10), 1u);
  EXPECT_EQ(c[0].node, 5);
  EXPECT_EQ(c[1].node, 6);
  // Fig. 6d/f: the rear one is pulled forward past its friction but cannot pass the
  // front one; together they slip only when the combined pull exceeds the combined
  // friction: 0.25 + 0 < 0.1 + 0.2 holds them...
  std::vector<NodeSlipPoint> held{{5, 0.25, 0.1}, {5, 0.0, 0.2}};
  EXPECT_EQ(node_slip(held, 0, 10), 0u);
  EXPECT_EQ(held[0].node, 5);
  EXPECT_EQ(held[1].node, 5);
  // ...0.35 + 0 > 0.1 + 0.2 moves both, still in order
  std::vector<NodeSlipPoint> both{{5, 0.35, 0.1}, {5, 0.0, 0.2}};
  EXPECT_EQ(node_slip(both, 0, 10), 2u);
  EXPECT_EQ(both[0].node, 6);
  EXPECT_EQ(both[1].node, 6);
  // the same backwards, mirrored: the front one pulled back drags the rear one
  std::vector<NodeSlipPoint> back{{5, 0.0, 0.2}, {5, -0.35, 0.1}};
  EXPECT_EQ(node_slip(back, 0, 10), 2u);
  EXPECT_EQ(back[0].node, 4);
  EXPECT_EQ(back[1].node, 4);
  // pulled apart: each group leaves its own way
  std::vector<NodeSlipPoint> apart{{5, -0.3, 0.1}, {5, 0.3, 0.1}};
  EXPECT_EQ(node_slip(apart, 0, 10), 2u);
  EXPECT_EQ(apart[0].node, 4);
  EXPECT_EQ(apart[1].node, 6);
  // pushed into each other: the rear wants forward, the front back; neither passes
  std::vector<NodeSlipPoint> into{{5, 0.3, 0.1}, {5, -0.3, 0.1}};
  EXPECT_EQ(node_slip(into, 0, 10), 0u);
  // neighbouring nodes whose points would swap press on each other and hold
  std::vector<NodeSlipPoint> swap{{5, 0.3, 0.1}, {6, -0.3, 0.1}};
  EXPECT_EQ(node_slip(swap, 0, 10), 0u);
  EXPECT_EQ(swap[0].node, 5);
  EXPECT_EQ(swap[1].node, 6);
  // a list out of thread order is a caller's error
  std::vector<NodeSlipPoint> bad{{6, 0, 0.1}, {5, 0, 0.1}};
  EXPECT_THROW(node_slip(bad, 0, 10), std::invalid_argument);
}

#include <suturesim/coupling/needle_puncture.h>

#include "realtime/test_meshes.h"

TEST(NeedlePuncture, TouchPressPunctureInsideAndOutThroughTheFarSide)
{
  // a rigid box (the surface does not move): the tip comes down through the top face
  // (z = 0.01) and leaves through the bottom (z = 0); the touch force is k_c times the
  // tip's depth behind the touched point, and the puncture fires at the threshold
  const auto   mesh    = suturesim::test_support::box_mesh(0.04, 0.04, 0.01, 8, 8, 2);
  const auto   surface = suturesim::mesh::extract_boundary(mesh);
  const PunctureParameters p{0.5, 1000, 1e-3}; // threshold reached 0.5 mm behind the surface
  NeedlePuncture puncture(p, surface.triangles, mesh.vertices);
  const Eigen::Vector3d start(0.0213, 0.0187, 0.0102);
  int                   punctures = 0;
  for (int step = 0; step <= 1200; ++step)
    {
      const double          t   = step * 1e-3;
      const Eigen::Vector3d tip = start - Eigen::Vector3d(0, 0, 1e-5 * step); // 10 µm per step
      puncture.update(t, tip, -Eigen::Vector3d::UnitZ(), mesh.vertices);
      double force = 0;
      if (const auto *touch = puncture.touch())
        {
          const Eigen::Vector3d x = puncture.position(touch->point, mesh.vertices);
          force                   = puncture.normal_force(tip, x);
          // the force is the penalty of the depth behind the touched point
          const double depth = touch->exit ? tip[2] : tip[2] - 0.01; // < 0 behind the face
          EXPECT_NEAR(force, 1000 * std::max(0.0, -depth), 1e-9) << t;
          EXPECT_NEAR(touch->normal[2], touch->exit ? -1 : 1, 1e-12);
        }
      punctures += puncture.accept(t, force, tip);
    }
  ASSERT_EQ(punctures, 2);
  std::vector<std::string> kinds;
  for (const auto &e : puncture.events())
    kinds.push_back(e.kind);
  EXPECT_EQ(kinds, (std::vector<std::string>{"touch_entry", "puncture_entry", "touch_exit", "puncture_exit"}));
  const auto &entry = puncture.events()[1], &exit = puncture.events()[3];
  // within a step (10 µm, 0.01 N) of the threshold, 0.5 mm behind each face
  EXPECT_GE(entry.force, 0.5);
  EXPECT_LT(entry.force, 0.5 + 0.0101);
  EXPECT_NEAR(entry.position[2], 0.01 - 5e-4, 1.01e-5);
  EXPECT_NEAR(exit.position[2], -5e-4, 1.01e-5);
  // each puncture keeps the material point it pierced (on the face, under the tip), the
  // face's outward normal and the direction the tip advanced in
  EXPECT_NEAR(entry.reference[2], 0.01, 1e-15);
  EXPECT_NEAR(exit.reference[2], 0, 1e-15);
  EXPECT_NEAR(entry.reference[0], entry.position[0], 1e-15);
  EXPECT_NEAR(entry.normal[2], 1, 1e-12);
  EXPECT_NEAR(exit.normal[2], -1, 1e-12);
  EXPECT_EQ(entry.direction, -Eigen::Vector3d::UnitZ());
  EXPECT_EQ(puncture.events()[0].reference, Eigen::Vector3d::Zero()); // a touch has none
  EXPECT_EQ(puncture.phase(), NeedlePuncture::Phase::outside);
}

TEST(NeedlePuncture, ATouchTakesTheNeedlesDirectionWhereItsPathCrossedTheSurface)
{
  // between two looks the tip goes from 0.1 mm above the top face (z = 0.01) to 0.3 mm
  // below it, crossing at a quarter of its path, while the needle turns from 10 to 30
  // degrees off the vertical: the touch's direction is the path's at the crossing,
  // (3 d0 + d1) / 4 normalised (a needle turning about its centre: exact to second order)
  const auto       mesh    = suturesim::test_support::box_mesh(0.04, 0.04, 0.01, 8, 8, 2);
  const auto       surface = suturesim::mesh::extract_boundary(mesh);
  NeedlePuncture   puncture({0.5, 1000, 1e-3}, surface.triangles, mesh.vertices);
  const auto       at      = [](const double deg) {
    const double a = deg * M_PI / 180;
    return Eigen::Vector3d(std::sin(a), 0, -std::cos(a));
  };
  puncture.update(0, {0.0213, 0.0187, 0.0101}, at(10), mesh.vertices);
  EXPECT_EQ(puncture.phase(), NeedlePuncture::Phase::outside);
  puncture.update(1, {0.0213, 0.0187, 0.0097}, at(30), mesh.vertices);
  ASSERT_NE(puncture.touch(), nullptr);
  const Eigen::Vector3d expected = (0.75 * at(10) + 0.25 * at(30)).normalized();
  EXPECT_NEAR((puncture.touch()->direction - expected).norm(), 0, 1e-12);
  EXPECT_NEAR(puncture.touch()->reference[2], 0.01, 1e-15);
}

TEST(NeedlePuncture, ATipThatJumpsAThinGapInOneStepLeavesTheFirstBodyBeforeEnteringTheNext)
{
  // Two rigid boxes 0.1 mm apart along x, A on [0, 10] mm and B on [10.1, 20.1] mm, and
  // a tip moving +x by 0.3 mm per step: in one step it goes from 0.05 mm inside A's far
  // face to 0.15 mm inside B. Nearest-point tests alone see it behind B's face, inside,
  // and miss both the exit from A and the entry into B (the accurate path's implicit
  // steps through a gaping wound did: two punctures instead of four). The path's
  // crossing starts the exit at A's face, and the entry into B follows.
  auto       mesh = suturesim::test_support::box_mesh(0.01, 0.01, 0.01, 2, 2, 2);
  const auto a    = mesh;
  const auto n    = std::uint32_t(a.vertices.cols());
  mesh.vertices.conservativeResize(3, 2 * n);
  mesh.vertices.rightCols(n) = a.vertices.colwise() + Eigen::Vector3d(0.0101, 0, 0);
  for (auto t : a.tetrahedra)
    {
      for (auto &v : t)
        v += n;
      mesh.tetrahedra.push_back(t);
      mesh.tetrahedron_tags.push_back(1);
    }
  const auto surface = suturesim::mesh::extract_boundary(mesh);
  NeedlePuncture puncture({0.5, 1000, 1e-3}, surface.triangles, mesh.vertices); // 0.5 mm deep
  std::vector<double> touched_at; // x of each touched point
  for (int step = 0; step <= 80; ++step)
    {
      const Eigen::Vector3d tip(-0.00055 + 3e-4 * step, 0.0042, 0.0057);
      puncture.update(step, tip, Eigen::Vector3d::UnitX(), mesh.vertices);
      double force = 0;
      if (const auto *touch = puncture.touch())
        {
          const Eigen::Vector3d x = puncture.position(touch->point, mesh.vertices);
          if (touched_at.empty() || touched_at.back() != x[0])
            touched_at.push_back(x[0]);
          force = puncture.normal_force(tip, x);
        }
      puncture.accept(step, force, tip);
    }
  std::vector<std::string> kinds;
  for (const auto &e : puncture.events())
    kinds.push_back(e.kind);
  const std::vector<std::string> pass{"touch_entry", "puncture_entry", "touch_exit", "puncture_exit"};
  std::vector<std::string>       twice = pass;
  twice.insert(twice.end(), pass.begin(), pass.end());
  ASSERT_EQ(kinds, twice);
  // the faces touched, in turn: A's near and far faces, B's near and far faces
  ASSERT_EQ(touched_at.size(), 4u);
  EXPECT_NEAR(touched_at[0], 0, 1e-12);
  EXPECT_NEAR(touched_at[1], 0.01, 1e-12);
  EXPECT_NEAR(touched_at[2], 0.0101, 1e-12);
  EXPECT_NEAR(touched_at[3], 0.0201, 1e-12);
  // every puncture within one step (0.3 N) of the threshold
  unsigned punctures = 0;
  for (const auto &e : puncture.events())
    if (e.kind.rfind("puncture", 0) == 0)
      {
        EXPECT_GE(e.force, 0.5);
        EXPECT_LT(e.force, 0.8);
        ++punctures;
      }
  EXPECT_EQ(punctures, 4u); // two passes, each in and out
}

TEST(NeedlePuncture, ATipThatBacksOffReleasesTheTouch)
{
  const auto mesh    = suturesim::test_support::box_mesh(0.04, 0.04, 0.01, 4, 4, 1);
  const auto surface = suturesim::mesh::extract_boundary(mesh);
  NeedlePuncture puncture({1, 1000, 1e-3}, surface.triangles, mesh.vertices);
  const Eigen::Vector3d x0(0.013, 0.017, 0.0101);
  for (int step = 0; step < 80; ++step)
    {
      // down 0.4 mm (0.4 N, below the threshold), then back up
      const double          s   = step < 40 ? step : 80 - step;
      const Eigen::Vector3d tip = x0 - Eigen::Vector3d(0, 0, 1.25e-5 * s);
      puncture.update(step, tip, -Eigen::Vector3d::UnitZ(), mesh.vertices);
      const double f = puncture.touch() ? puncture.normal_force(tip, puncture.position(puncture.touch()->point, mesh.vertices)) : 0;
      EXPECT_FALSE(puncture.accept(step, f, tip));
    }
  EXPECT_EQ(puncture.phase(), NeedlePuncture::Phase::outside);
  ASSERT_EQ(puncture.events().size(), 2u);
  EXPECT_EQ(puncture.events()[1].kind, "release");
}
