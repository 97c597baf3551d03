// Bounding-sphere hierarchy (seed 000, Algorithm 1) and rod self-contact.
#include <suturesim/collision/sphere_tree.h>
#include <suturesim/rod/rod_parameters.h>

#include <gtest/gtest.h>

#include <random>
#include <set>

using namespace suturesim;
using suturesim::rod::Vec3;

namespace
{
  std::vector<Eigen::Vector3d>
  helix(const std::size_t n, const double phase)
  {
    std::vector<Eigen::Vector3d> p;
    for (std::size_t i = 0; i < n; ++i)
      {
        const double s = 0.05 * i;
        p.emplace_back(std::cos(s + phase), std::sin(s), 0.01 * s);
      }
    return p;
  }

  /// Every node bounds its children and every leaf bounds its segment's tube.
  void
  expect_bounding(const collision::SphereTree &tree, const std::vector<Eigen::Vector3d> &p, const double tube)
  {
    const auto &s = tree.spheres();
    for (std::size_t node = 0; node < s.size(); ++node)
      {
        if (node < tree.n_segments())
          {
            for (const auto &end : {p[node], p[node + 1]})
              EXPECT_TRUE(s[node].contains({end, tube})) << "leaf " << node;
            continue;
          }
        for (const int c : {tree.left_child(node), tree.right_child(node)})
          if (c >= 0)
            {
              EXPECT_TRUE(s[node].contains(s[c])) << "node " << node << " child " << c;
            }
      }
  }
} // namespace

// After large deformations the bottom-up refit bounds every segment and equals a full
// rebuild sphere for sphere; a refit after moving a few points touches only their
// ancestors (Algorithm 1 updates each dirty node once).
TEST(SphereTree, RefitBoundsEveryPrimitiveAndMatchesRebuild)
{
  const double tube = 0.02;
  auto         points = helix(513, 0);
  collision::SphereTree tree;
  tree.build(points, tube);
  std::mt19937                           rng(7);
  std::uniform_real_distribution<double> u(-0.5, 0.5);
  for (int round = 0; round < 5; ++round)
    {
      // large deformation: rigid rotation, bending and noise
      for (auto &x : points)
        x = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 1, 0).normalized()) * x +
            Eigen::Vector3d(u(rng), u(rng), u(rng)) * 0.3 + Eigen::Vector3d(0, 0, 0.5 * x[0] * x[0]);
      tree.refit(points);
      expect_bounding(tree, points, tube);
      collision::SphereTree rebuilt;
      rebuilt.build(points, tube);
      ASSERT_EQ(rebuilt.spheres().size(), tree.spheres().size());
      for (std::size_t n = 0; n < tree.spheres().size(); ++n)
        {
          EXPECT_LT((tree.spheres()[n].centre - rebuilt.spheres()[n].centre).norm(), 1e-12);
          EXPECT_NEAR(tree.spheres()[n].radius, rebuilt.spheres()[n].radius, 1e-12);
        }
      std::vector<std::pair<std::uint32_t, std::uint32_t>> a, b;
      tree.self_overlaps(0.01, a);
      rebuilt.self_overlaps(0.01, b);
      EXPECT_EQ(std::set(a.begin(), a.end()), std::set(b.begin(), b.end()));
    }
  // one point moved: its two leaves and their ancestors, about 2 + 2 log2(512) nodes
  points[100] += Eigen::Vector3d(0.3, 0, 0);
  const std::size_t updated = tree.refit(points);
  EXPECT_GE(updated, 2u + 9u);
  EXPECT_LE(updated, 2u + 2u * 10u);
  expect_bounding(tree, points, tube);
}

// The broad phase finds every pair of segments within reach (checked against all pairs).
TEST(SphereTree, SelfOverlapsFindsAllClosePairs)
{
  auto points = helix(300, 0.3);
  for (std::size_t i = 150; i < 300; ++i) // fold the second half back onto the first
    points[i] = points[299 - i] + Eigen::Vector3d(0.01, 0.02, 0);
  collision::SphereTree tree;
  tree.build(points, 0.01);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;
  tree.self_overlaps(0.02, pairs);
  const std::set<std::pair<std::uint32_t, std::uint32_t>> found(pairs.begin(), pairs.end());
  for (std::uint32_t a = 0; a + 1 < points.size(); ++a)
    for (std::uint32_t b = a + 1; b + 1 < points.size(); ++b)
      {
        const auto [s, t] = rod::SelfContact::closest_parameters(points[a], points[a + 1], points[b], points[b + 1]);
        const double d = ((1 - s) * points[a] + s * points[a + 1] - (1 - t) * points[b] - t * points[b + 1]).norm();
        if (d < 0.02 + 2 * 0.01)
          {
            EXPECT_TRUE(found.count({a, b})) << a << " " << b << " at distance " << d;
          }
      }
}

namespace
{
  /// One rod whose two strands cross: strand A along x at z = +h, then a loop, then
  /// strand B along y at z = −h under A; both ends clamped. Forces push A down and B up
  /// at the crossing. Returns the signed smallest centreline distance between the
  /// strands' middle parts after the load (negative when A passed below B), in units of r.
  double
  pressed_strands(const bool contact)
  {
    const double a = 0.02, h = 0.002, r = 0.5e-3;
    rod::RodParameters p;
    p.centreline = "polyline";
    p.polyline   = {Vec3(-a, 0, h), Vec3(a, 0, h), Vec3(a, a, 0), Vec3(0, a, -h), Vec3(0, -a, -h)};
    p.elements   = 120;
    p.section.radius = r;
    p.section.E      = 1e8;
    p.start_end.type = p.last_end.type = "clamped";
    p.contact        = {contact, 2e3, 0.2 * r, r};
    rod::RodModel model = p.create_model();
    // node sets of the two straight strands (by position along the resampled polyline)
    std::vector<std::size_t> a_nodes, b_nodes;
    for (std::size_t i = 0; i < model.n_nodes(); ++i)
      {
        const Vec3 &x = model.positions()[i];
        if (std::abs(x[2] - h) < 1e-9 && std::abs(x[0]) < a / 2)
          a_nodes.push_back(i);
        if (std::abs(x[2] + h) < 1e-9 && std::abs(x[1]) < a / 2)
          b_nodes.push_back(i);
      }
    EXPECT_GT(a_nodes.size(), 10u);
    EXPECT_GT(b_nodes.size(), 10u);
    rod::NewtonParameters newton;
    const int steps = 40;
    for (int step = 1; step <= steps; ++step)
      {
        for (const auto i : a_nodes)
          model.forces()[i] = Vec3(0, 0, -8e-4 * step / steps);
        for (const auto i : b_nodes)
          model.forces()[i] = Vec3(0, 0, 8e-4 * step / steps);
        const auto result = model.solve(newton);
        EXPECT_TRUE(result.converged) << "step " << step << ": " << result.reason;
        if (!result.converged)
          return 0;
      }
    // signed separation at the crossing: the closest centreline distance between the
    // strands' middle parts, negative once strand A has gone below strand B
    const auto &x = model.positions();
    double      d = 1e9, dz = 0;
    for (std::size_t i = a_nodes.front(); i < a_nodes.back(); ++i)
      for (std::size_t j = b_nodes.front(); j < b_nodes.back(); ++j)
        {
          const auto [s, t] = rod::SelfContact::closest_parameters(x[i], x[i + 1], x[j], x[j + 1]);
          const Vec3 gap    = (1 - s) * x[i] + s * x[i + 1] - (1 - t) * x[j] - t * x[j + 1];
          if (gap.norm() < d)
            {
              d  = gap.norm();
              dz = gap[2];
            }
        }
    d = dz < 0 ? -d : d;
    return d / r;
  }
} // namespace

// Two strands pressed across each other: without contact they pass through each other,
// with the penalty they stay apart (centreline distance ≥ 1.9 r; contact at 2 r).
TEST(RodSelfContact, PressedStrandsDoNotPassThrough)
{
  const double without = pressed_strands(false);
  const double with    = pressed_strands(true);
  std::printf("min centreline distance / r: without contact %.3f, with contact %.3f\n", without, with);
  EXPECT_LT(without, 0.0) << "the load must push the strands through each other";
  EXPECT_GE(with, 1.9);
}

TEST(EndCondition, WorldKeyframesAreReachedInAStraightLineFromTheGrasp)
{
  // grasp frame: the keyframes displace the end from where it was held; world frame:
  // they are positions, the first after the grasp reached on a straight line from the
  // hold, so that two model paths whose ends hang in different places pull from one
  rod::EndCondition end;
  end.type       = "prescribed";
  end.grasp_time = 2.5;
  end.keyframes  = {{3.0, {0.004, 0.005, 0.006}}, {8.5, {0.010, 0.005, 0.006}}};
  const rod::Vec3 held(0.001, 0.002, 0.003);
  EXPECT_LT((end.position(5.75, held) - (held + rod::Vec3(0.007, 0.005, 0.006))).norm(), 1e-15);
  end.frame = "world";
  EXPECT_LT((end.position(2.5, held) - held).norm(), 1e-15);
  EXPECT_LT((end.position(2.75, held) - rod::Vec3(0.0025, 0.0035, 0.0045)).norm(), 1e-15);
  EXPECT_LT((end.position(3.0, held) - rod::Vec3(0.004, 0.005, 0.006)).norm(), 1e-15);
  EXPECT_LT((end.position(5.75, held) - rod::Vec3(0.007, 0.005, 0.006)).norm(), 1e-15);
  EXPECT_LT((end.position(9.0, held) - rod::Vec3(0.010, 0.005, 0.006)).norm(), 1e-15);
}
