// Seed 004's node-access constraint (realtime/node_access.h): its gradient against central
// differences, its XPBD forces against its penalty forces, the segment that holds the
// access point as a straight suture slides, and the equilibrium of a suture pulled over
// the access point against the closed form of a thread over a frictionless peg; then the
// same through a world (World::add_access), which leaves out the suture's spring on the
// link that holds the access and gives it back as the thread slides on.
#include <suturesim/realtime/node_access.h>
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/world.h>

#include "realtime/test_worlds.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <stdexcept>
#include <vector>

using namespace suturesim;
using namespace suturesim::realtime;

namespace
{
  /// A straight suture of @p segments links of @p link along x from the origin.
  Matrix3Xd
  straight(const unsigned segments, const double link, const double shift = 0)
  {
    Matrix3Xd x = Matrix3Xd::Zero(3, segments + 1);
    for (unsigned j = 0; j <= segments; ++j)
      x(0, j) = j * link + shift;
    return x;
  }
} // namespace

TEST(NodeAccess, GradientMatchesCentralDifferences)
{
  const double l = 1e-3;
  Matrix3Xd    x(3, 3);
  x << 0.0, 0.9e-3, 1.7e-3, 0.0, 0.35e-3, -0.2e-3, 0.0, -0.1e-3, 0.25e-3;
  NodeAccess access({0, 3}, l, 1e3);
  access.add(Vector3d(1.3e-3, 0.05e-3, 0.02e-3), 1);
  Vector3d gi, gj;
  access.gradient(0, x, gi, gj);
  const double h     = 1e-9; // m: truncation ~(h/|p − b|)² ≈ 1e-11, round-off ~1e-16 |x|/h ≈ 1e-10
  double       error = 0;
  for (unsigned node = 1; node <= 2; ++node)
    for (unsigned d = 0; d < 3; ++d)
      {
        Matrix3Xd y = x;
        y(d, node) += h;
        const double cp = access.violation(0, y);
        y(d, node) -= 2 * h;
        const double cm = access.violation(0, y);
        error           = std::max(error, std::abs((cp - cm) / (2 * h) - (node == 1 ? gi : gj)[d]));
      }
  EXPECT_LT(error, 1e-7); // of unit vectors
  // node 0 is not on the access segment
  Matrix3Xd y = x;
  y(0, 0) += 1e-4;
  EXPECT_EQ(access.violation(0, y), access.violation(0, x));
}

TEST(NodeAccess, XpbdForcesMatchThePenaltyForcesOnceConverged)
{
  // (the penalty forces against the energy: RealtimeInteractions.NodeAccessForcesAreMinusTheEnergyGradient)
  const double l = 1e-3, k = 50;
  Matrix3Xd    x(3, 3);
  x << 0.0, 1.1e-3, 1.9e-3, 0.0, 0.3e-3, 0.1e-3, 0.0, 0.0, -0.2e-3;
  NodeAccess access({0, 3}, l, k);
  access.add(Vector3d(1.4e-3, -0.1e-3, 0.1e-3), 1);

  // XPBD: sweeps at dt converge to C + α̃λ = 0, where λ∇C/dt² = −k C ∇C (Macklin et al.
  // 2016, §4), the penalty force at the converged state.
  const double dt = 1e-3;
  VectorXd     w(3);
  w << 0, 2e3, 1e3;
  access.reset_multipliers();
  for (int sweep = 0; sweep < 200; ++sweep)
    access.project(x, w, dt);
  Matrix3Xd penalty = Matrix3Xd::Zero(3, 3), constraint = Matrix3Xd::Zero(3, 3);
  access.add_forces(x, penalty);
  access.add_constraint_forces(x, constraint, dt);
  EXPECT_GT(penalty.norm(), 0);
  EXPECT_LT((constraint - penalty).norm(), 1e-10 * penalty.norm());
}

TEST(NodeAccess, RigidAccessIsMetAndTheHeldNodeStays)
{
  const double l = 1e-3;
  Matrix3Xd    x(3, 2);
  x << 0.0, 1.2e-3, 0.0, 0.4e-3, 0.0, 0.0;
  NodeAccess access({0, 2}, l, std::numeric_limits<double>::infinity());
  access.add(Vector3d(0.5e-3, -0.2e-3, 0.0), 0);
  VectorXd w(2);
  w << 0, 1;
  const Vector3d held = x.col(0);
  for (int sweep = 0; sweep < 50; ++sweep)
    access.project(x, w, 1e-3);
  EXPECT_LT(std::abs(access.violation(0, x)), 1e-15);
  EXPECT_EQ(Vector3d(x.col(0)), held);
  // with node 0 held, node 1 lies on the sphere of radius l − |b − p₀| about b, on the
  // ray from b through its start (each projection moves it along that ray)
  const Vector3d b = access.list()[0].b;
  EXPECT_NEAR((x.col(1) - b).norm(), l - (held - b).norm(), 1e-15);
  EXPECT_NEAR((x.col(1) - b).normalized().dot((Vector3d(1.2e-3, 0.4e-3, 0) - b).normalized()), 1.0, 1e-14);
}

TEST(NodeAccess, AccessFollowsTheSegmentThatHoldsItAsAStraightSutureSlides)
{
  const double   l = 1e-3;
  const unsigned n = 8;
  NodeAccess     access({0, n + 1}, l, 1e3);
  access.add(Vector3d(2.3e-3, 0, 0), 0);
  // closed form: the segment floor((b − x₀)/l), clamped to the suture
  for (const double shift : {0.0, -1.5e-3, -4.1e-3, 2.0e-3, -0.2e-3, -9e-3, 5e-3})
    {
      access.detect(straight(n, l, shift));
      const double        arc      = (2.3e-3 - shift) / l;
      const std::uint32_t expected = static_cast<std::uint32_t>(std::clamp(std::floor(arc), 0.0, n - 1.0));
      EXPECT_EQ(access.list()[0].segment, expected) << "shift " << shift;
      if (arc > 0 && arc < n) // while b is on the suture, the constraint is met
        {
          EXPECT_NEAR(access.violation(0, straight(n, l, shift)), 0, 1e-18);
        }
    }
  EXPECT_THROW(access.add(Vector3d::Zero(), n), std::invalid_argument);
}

// A suture of n links of rest length l (springs k) held at its first node, pulled at its
// last by F at 60° to its line, through an access point b on its line between nodes 3
// and 4 (access stiffness k). Closed form (a thread over a frictionless peg): the tension
// is |F| everywhere, every link is l' = l + |F|/k long along the path, and the node at
// arc length s = j l' lies on the ray from p₀ to b while s < |b − p₀|, else on the ray
// from b along F.
TEST(NodeAccess, SuturePulledOverTheAccessPointMatchesTheFrictionlessPeg)
{
  const unsigned n = 10;
  const double   l = 1e-3, k = 1e3, F = 0.1, angle = M_PI / 3;
  const Vector3d b(3.5e-3, 0, 0), direction(std::cos(angle), std::sin(angle), 0);
  Matrix3Xd      x = straight(n, l);

  SpringSet springs("suture");
  for (unsigned j = 0; j < n; ++j)
    if (j != 3) // the access constraint stands in for the link that holds b
      springs.add(j, j + 1, l, k);
  NodeAccess access({0, n + 1}, l, k);
  access.add(b, 0);

  // quasi-static descent x ← x + η f of the free nodes (η below 2/λ_max ≈ 1/(2k))
  const double eta      = 2e-4;
  double       residual = std::numeric_limits<double>::infinity();
  unsigned     steps    = 0;
  for (; steps < 2000000 && residual > 1e-13; ++steps)
    {
      access.detect(x);
      Matrix3Xd f = Matrix3Xd::Zero(3, n + 1);
      springs.add_forces(x, f);
      access.add_forces(x, f);
      f.col(n) += F * direction;
      f.col(0).setZero(); // held
      residual = f.cwiseAbs().maxCoeff();
      x += eta * f;
    }
  ASSERT_LE(residual, 1e-13) << "no equilibrium after " << steps << " steps";
  EXPECT_EQ(access.list()[0].segment, 3u);

  const double   stretched = l + F / k, to_b = b.norm();
  const Vector3d towards_b = b / to_b;
  double         error     = 0;
  for (unsigned j = 0; j <= n; ++j)
    {
      const double   s        = j * stretched;
      const Vector3d expected = s < to_b ? Vector3d(s * towards_b) : Vector3d(b + (s - to_b) * direction);
      error                   = std::max(error, (x.col(j) - expected).norm());
    }
  // m, 1e-9 of a link; the residual 1e-13 N over the softest mode's stiffness (the swing
  // about b, |F| over the 7 mm beyond it, 14 N/m) bounds the error at 1e-14 m
  EXPECT_LT(error, 1e-12) << steps << " steps";
  EXPECT_NEAR(access.violation(0, x) * k, F, 1e-9); // the tension through b is |F|
}

namespace
{
  /// The suture's link springs of @p world (their stiffness tells a link left out: 0).
  const SpringSet &
  suture_springs(const World &world)
  {
    for (const auto &i : world.system().interactions)
      if (const auto *s = dynamic_cast<const SpringSet *>(i.get()); s != nullptr && s->name() == "suture springs")
        return *s;
    throw std::logic_error("no suture springs");
  }

  /// The links of @p world's suture whose spring is left out (local indices).
  std::vector<std::uint32_t>
  links_left_out(const World &world)
  {
    const auto               &springs = suture_springs(world);
    const auto                begin   = world.system().suture.begin;
    std::vector<std::uint32_t> out;
    for (std::size_t e = 0; e < springs.size(); ++e)
      if (springs.stiffnesses()[e] == 0)
        out.push_back(springs.first_ends()[e] - begin);
    std::sort(out.begin(), out.end());
    return out;
  }

  /// A straight mass-spring suture of @p n links of 1 mm along x from the origin, links
  /// of 1000 N/m, under the quasi-static integrator at dt = 25 µs (under its limit
  /// 2B/λ_max = 2·0.1/(4k) = 50 µs).
  WorldSetup
  quasi_static_suture(const unsigned n)
  {
    WorldSetup w;
    w.suture = test_support::make_model<SutureModel::Registry>("mass-spring", {{"Stretch stiffness", "1000"}});
    w.suture_geometry = test_support::straight_suture(n, n * 1e-3, Vector3d::Zero(), Vector3d::UnitX());
    w.integrator      = test_support::make_model<Integrator::Registry>("quasi-static", {{"Suture damping", "0.1"}});
    w.substeps        = 40;
    return w;
  }
} // namespace

TEST(NodeAccess, WorldLeavesOutTheLinkItHoldsAndSettlesOnThePeg)
{
  // The peg's closed form (above) reached through a scene's world: a mass-spring suture
  // (links k) held by a tool at node 0, |F| at 60° on its last node under the quasi-
  // static integrator, the access put on the link nearest b by World::add_access, which
  // leaves that link's spring out of the suture for as long as the access holds it.
  const unsigned n = 10;
  const double   l = 1e-3, k = 1e3, F = 0.1, angle = M_PI / 3;
  const Vector3d b(3.5e-3, 0, 0), direction(std::cos(angle), std::sin(angle), 0);
  World          world(quasi_static_suture(n));
  const auto s = world.system().suture;
  world.add_tool("holder", {s.begin}, {});
  world.add_access({b}, k);
  EXPECT_EQ(links_left_out(world), std::vector<std::uint32_t>{3});
  world.set_loads([&](double, Matrix3Xd &f) { f.col(s.end - 1) = F * direction; });
  world.initialize();
  for (int step = 0; step < 3000; ++step)
    world.step({ToolPose()});

  const double   stretched = l + F / k, to_b = b.norm();
  const Vector3d towards_b = b / to_b;
  double         error     = 0;
  for (unsigned j = 0; j <= n; ++j)
    {
      const double   along    = j * stretched;
      const Vector3d expected = along < to_b ? Vector3d(along * towards_b) : Vector3d(b + (along - to_b) * direction);
      error                   = std::max(error, (world.system().nodes.x.col(s.begin + j) - expected).norm());
    }
  std::printf("[ peg through the world ] largest node error %.3e m\n", error);
  // m, 1e-9 of a link: 3 s of the damped flow B ẋ = f is 400 time constants B/k_swing
  // (7 ms) of its slowest mode
  EXPECT_LT(error, 1e-12);
  EXPECT_EQ(world.access()->list()[0].segment, 3u);
  EXPECT_EQ(links_left_out(world), std::vector<std::uint32_t>{3});
  EXPECT_NEAR(world.access()->violation(0, world.system().nodes.x) * k, F, 1e-9);
  // the holder feels the tension |F| along the first part, towards b
  EXPECT_LT((world.tool_forces()[0].force - F * towards_b).norm(), 1e-9);
}

TEST(NodeAccess, WorldGivesTheLinksBackAsTheThreadSlidesOn)
{
  // A suture of 20 links pulled over b by its far end (a tool moving 6 mm at 30°) against
  // a counterweight W on its first node, under the quasi-static integrator. Links pass
  // through b; at every step the one link left out is the one that holds b, and once
  // the tool stops the peg is frictionless: the links on both sides of b carry W.
  const unsigned n = 20;
  const double   l = 1e-3, k = 1e3, W = 0.05, angle = M_PI / 6;
  const Vector3d b(9.5e-3, 0, 0), direction(std::cos(angle), std::sin(angle), 0);
  World          world(quasi_static_suture(n));
  const auto s = world.system().suture;
  world.add_tool("grasper", {s.end - 1}, {});
  world.add_access({b}, k);
  world.set_loads([&](double, Matrix3Xd &f) { f.col(s.begin) = -W * Vector3d::UnitX(); });
  world.initialize();
  unsigned moves = 0, last = world.access()->list()[0].segment;
  for (int step = 0; step < 4000; ++step)
    {
      ToolPose pose;
      pose.position = 6e-3 * std::min(world.time(), 1.0) * direction; // 6 mm/s for 1 s
      const Matrix3Xd before = world.system().nodes.x;
      world.step({pose});
      const auto    &x = world.system().nodes.x;
      // detection comes first in a substep, so after a step b may lie beyond the link's
      // ends by what the nodes moved in its last substep; bounded by the whole step's
      // largest move (the counterweight's first pull moves node 0 at up to W/B = 0.5 m/s)
      const double lag = 2 * (x - before).colwise().norm().maxCoeff() / l;
      const unsigned i = world.access()->list()[0].segment;
      const Vector3d p = x.col(s.begin + i), d = x.col(s.begin + i + 1) - p;
      const double   t = (b - p).dot(d) / d.squaredNorm();
      ASSERT_GE(t, -lag) << "step " << step;
      ASSERT_LE(t, 1 + lag) << "step " << step;
      ASSERT_EQ(links_left_out(world), std::vector<std::uint32_t>{i}) << "step " << step;
      moves += i != last;
      last = i;
    }
  // the end comes 5.5 mm further from b (|(14.5 + 5.2, 3.0)| − 10.5 mm): b moves from
  // 9.5 mm to about 4 mm along the thread from node 0, from link 9 to link 4
  std::printf("[ sliding ] access on link %u after %u moves\n", last, moves);
  EXPECT_EQ(last, 4u);
  EXPECT_EQ(moves, 5u);
  std::vector<double> tension;
  world.suture()->segment_tension(world.system(), tension);
  std::printf("[ sliding ] tension before b %.9f N, after b %.9f N, W %.3f N\n", tension[last - 1],
              tension[last + 1], W);
  EXPECT_NEAR(tension[last - 1], W, 1e-6 * W);
  EXPECT_NEAR(tension[last + 1], W, 1e-6 * W);
  EXPECT_NEAR(world.access()->violation(0, world.system().nodes.x) * k, W, 1e-6 * W);
}

TEST(NodeAccess, WorldRefusesARigidAccessUnderForces)
{
  WorldSetup w;
  w.suture          = test_support::make_model<SutureModel::Registry>("mass-spring");
  w.suture_geometry = test_support::straight_suture(4, 4e-3, Vector3d::Zero(), Vector3d::UnitX());
  w.integrator      = test_support::make_model<Integrator::Registry>("quasi-static");
  World world(std::move(w));
  EXPECT_THROW(world.add_access({Vector3d(1.5e-3, 0, 0)}, std::numeric_limits<double>::infinity()),
               std::invalid_argument);
}
