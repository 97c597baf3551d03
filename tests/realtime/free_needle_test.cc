// The needle let go (seed 001 §5–6): its law against closed forms (mass, centroid, the
// drift under its weight, the equilibrium hanging from a spring), and in the world a
// needle released mid-pass that stays in the tissue and, taken again, completes the pass.
#include <suturesim/realtime/free_needle.h>
#include <suturesim/realtime/world.h>
#include <suturesim/tools/surgical_pass.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "realtime/test_meshes.h"
#include "realtime/test_worlds.h"

using namespace suturesim;
using namespace suturesim::realtime;

namespace
{
  const Vector3d gravity(0, 0, -9.81);
} // namespace

TEST(FreeNeedle, MassAndCentroidAreTheArcsClosedForms)
{
  // a 1/2 needle of R = 8 mm, d = 0.4 mm: m = ρ π d²/4 · π R, the centroid of a
  // semicircle 2R/π from its centre on its axis of symmetry
  const double              R = 0.008, d = 4e-4, rho = 7800;
  const tools::CurvedNeedle needle(R, M_PI, d);
  FreeNeedle                body(needle, rho, 0.1);
  body.release(tools::Pose());
  EXPECT_NEAR(body.mass(), rho * M_PI * d * d / 4 * M_PI * R, 1e-15);
  EXPECT_LT((body.centroid() - Vector3d(0, 2 * R / M_PI, 0)).norm(), 1e-15);
  EXPECT_THROW(FreeNeedle(needle, 0, 0.1), std::invalid_argument);
  EXPECT_THROW(FreeNeedle(needle, rho, 0), std::invalid_argument);
}

TEST(FreeNeedle, WeightAloneMovesItsCentroidAtMgOverBWithoutTurning)
{
  // V = F/B with F = m g at the centroid: no moment about it, so no turn
  const tools::CurvedNeedle needle(0.008, 3 * M_PI / 4, 4e-4);
  const double              B = 0.1, dt = 1e-3;
  FreeNeedle                body(needle, 7800, B);
  tools::Pose               start;
  start.position    = Vector3d(0.01, -0.02, 0.03);
  start.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()));
  body.release(start);
  const Vector3d c0 = body.centroid();
  for (int k = 0; k < 10; ++k)
    body.step(Vector3d::Zero(), Vector3d::Zero(), gravity, Matrix6d::Zero(), dt);
  const Vector3d expected = c0 + 10 * dt * body.mass() * gravity / B;
  EXPECT_LT((body.centroid() - expected).norm(), 1e-15);
  EXPECT_LT(body.pose().orientation.angularDistance(start.orientation), 1e-12);
}

TEST(FreeNeedle, HangsFromASpringWithItsCentroidBelowItAndTheSpringStretchedByItsWeight)
{
  // A spring k from fixed point P to the arc's point a at ζ = L/4. At rest the body
  // is in equilibrium: the spring carries the weight, k |a − P| = m g, and the weight's
  // line passes through a (no moment about it): the centroid lies straight below a.
  const tools::CurvedNeedle needle(0.008, 3 * M_PI / 4, 4e-4);
  const double              k = 50, dt = 1e-3, zeta = needle.length() / 4;
  FreeNeedle                body(needle, 7800, 1e-3);
  tools::Pose               start;
  start.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vector3d::UnitX()));
  body.release(start);
  const Vector3d P = needle.point(start, zeta);
  for (int step = 0; step < 20000; ++step)
    {
      const Vector3d a = needle.point(body.pose(), zeta);
      const Vector3d f = -k * (a - P);
      const Vector3d c = body.centroid();
      Matrix6d       K = Matrix6d::Zero();
      add_point_stiffness(K, a - c, k);
      body.step(f, (a - body.pose().position).cross(f), gravity, K, dt);
    }
  const Vector3d a = needle.point(body.pose(), zeta), c = body.centroid();
  const double   weight = body.mass() * gravity.norm();
  std::printf("[ free needle ] stretch %.6e m (m g/k %.6e m); centroid off the vertical through a %.3e m; "
              "resultant %.3e N\n",
              (a - P).norm(), weight / k, std::hypot(c[0] - a[0], c[1] - a[1]), body.resultant_force().norm());
  EXPECT_NEAR((a - P).norm(), weight / k, 1e-9 * weight / k);
  EXPECT_NEAR(a[2] - P[2], -weight / k, 1e-9 * weight / k);
  EXPECT_LT(std::hypot(c[0] - a[0], c[1] - a[1]), 1e-9 * needle.radius());
  EXPECT_GT(a[2], c[2]); // below, not balanced above
  EXPECT_LT(body.resultant_force().norm(), 1e-9 * weight);
}

namespace
{
  /// A 1/2 needle's pass 3 mm deep through the top of the 40 × 40 × 10 mm block of the
  /// needle tests (needle_test.cc), with an ftl suture under gravity. The driver's jaws
  /// open at @p open and close again at @p close (s); meanwhile the driver waits, and
  /// then goes on along its path. Records the needle's centroid while it is free, and
  /// the events.
  struct ReleaseRun
  {
    std::vector<double>                  time;     ///< while free, s
    std::vector<Vector3d>                centroid; ///< while free, m
    std::vector<std::vector<double>>     anchors;  ///< of the pierce points while free, m
    std::vector<bool>                    slipping; ///< any pierce point, while free
    bool                                 points_held = true; ///< both holes hold on while open
    double                               weight = 0;
    std::vector<coupling::PunctureEvent> events, thread_events;
  };

  const tools::CurvedNeedle half_needle(0.008, M_PI, 4e-4);

  ReleaseRun
  run_release(const double open, const double close)
  {
    const auto                mesh = test_support::box_mesh(0.04, 0.04, 0.01, 10, 10, 3);
    const auto                pass = test_support::block_pass(half_needle, 0.003);
    const tools::Pose         start = pass.trajectory.pose(0);
    WorldSetup                w     = test_support::needle_block(mesh, half_needle, start);
    w.gravity                       = gravity;
    World world(std::move(w));
    world.fix_vertices(mesh::vertices_with_tag(mesh::extract_boundary(mesh), 1));
    const NeedleCouplingParameters p = test_support::needle_block_coupling(0.2);
    world.add_needle(half_needle, p, start, true);
    world.initialize();

    ReleaseRun run;
    // the driver's time along its path: it waits while the jaws are open
    const auto driver = [&](const double t) { return t < open ? t : t < close ? open : t - (close - open); };
    std::vector<tools::Pose> poses(1);
    const int                steps = static_cast<int>(std::round((pass.t_end + close - open) * 1000));
    for (int k = 1; k <= steps; ++k)
      {
        const double t = k * 1e-3;
        if (std::abs(t - open) < 0.5e-3)
          {
            world.release_needle(7800, 1e-3);
            run.weight = world.free_needle()->mass() * gravity.norm();
          }
        if (std::abs(t - close) < 0.5e-3)
          world.grasp_needle(pass.trajectory.pose(driver(t)));
        poses[0] = pass.trajectory.pose(driver(t));
        world.step(poses);
        if (const auto *free = world.free_needle())
          {
            run.time.push_back(world.time());
            run.centroid.push_back(free->centroid());
            const auto &points = world.needle()->pierce_points();
            run.points_held    = run.points_held && points.size() == 2;
            run.anchors.emplace_back();
            bool slips = false;
            for (const auto &q : points)
              {
                run.anchors.back().push_back(q.anchor);
                slips = slips || q.slipping;
              }
            run.slipping.push_back(slips);
          }
      }
    run.events        = world.needle()->puncture_state().events();
    run.thread_events = world.needle()->thread_events();
    return run;
  }
} // namespace

TEST(FreeNeedle, ReleasedMidPassStaysInTheTissueAndTakenAgainCompletesThePass)
{
  // The jaws open once the tip is out of the exit (both holes on the needle's arc,
  // the suture still outside) and close 1 s later. The needle lies in the tissue: its
  // two pierce points hold it against its weight and the suture's pull; it gives a
  // little as the tissue it pre-loaded relaxes, then rests. Taken again, it is drawn
  // through: the suture passes both holes.
  const auto       pass = test_support::block_pass(half_needle, 0.003);
  const double     open = pass.t_tip_exit + 0.06, close = open + 1;
  const ReleaseRun run  = run_release(open, close);
  std::vector<std::string> kinds;
  double                   exit_time = 0;
  for (const auto &e : run.events)
    {
      kinds.push_back(e.kind);
      if (e.kind == "puncture_exit")
        exit_time = e.time;
    }
  ASSERT_EQ(kinds, (std::vector<std::string>{"touch_entry", "puncture_entry", "touch_exit", "puncture_exit"}));
  ASSERT_LT(exit_time, open) << "release after both punctures";
  ASSERT_FALSE(run.centroid.empty());
  double largest = 0, late = 0, slid = 0; // m: from where it was let go; in the last quarter second
  bool   slipped = false;
  for (std::size_t i = 0; i < run.centroid.size(); ++i)
    {
      largest = std::max(largest, (run.centroid[i] - run.centroid.front()).norm());
      if (run.time[i] > close - 0.25)
        {
          late    = std::max(late, (run.centroid[i] - run.centroid.back()).norm());
          slipped = slipped || run.slipping[i];
          for (std::size_t k = 0; k < run.anchors[i].size(); ++k)
            slid = std::max(slid, std::abs(run.anchors[i][k] - run.anchors.back()[k]));
        }
    }
  std::printf("[ free needle ] open %.3f-%.3f s: the centroid gave %.3e m, moved %.3e m in the last 0.25 s, "
              "the holes slid %.3e m along it (weight %.3e N)\n",
              open, close, largest, late, slid, run.weight);
  EXPECT_TRUE(run.points_held); // by both holes throughout
  // it stays where it was let go, to a quarter of its wire's diameter (0.1 mm) ...
  EXPECT_LT(largest, half_needle.wire_diameter() / 4);
  // ... and comes to rest in the holes: in the last quarter second both stick (their
  // material points on the needle do not move); what moves it then is the tissue's own
  // relaxation
  EXPECT_FALSE(slipped);
  EXPECT_EQ(slid, 0.0);
  std::size_t onto = 0;
  for (const auto &e : run.thread_events)
    onto += e.kind == "onto_suture";
  EXPECT_EQ(onto, 2u) << "the suture drawn through both holes";
}

// A handover (World::hand_needle_over): another grasper takes the needle where it is,
// and from then on the needle follows that grasper rigidly; handed back, it follows
// the first. Never free, so a free needle cannot be handed over.
TEST(FreeNeedle, HandedOverItStaysWhereItIsAndFollowsItsNewHolder)
{
  const auto        mesh  = test_support::box_mesh(0.04, 0.04, 0.01, 10, 10, 3);
  const auto        pass  = test_support::block_pass(half_needle, 0.003);
  const tools::Pose start = pass.trajectory.pose(0); // the tip before the entry, in the air
  World             world(test_support::needle_block(mesh, half_needle, start));
  world.fix_vertices(mesh::vertices_with_tag(mesh::extract_boundary(mesh), 1));
  world.add_needle(half_needle, test_support::needle_block_coupling(0.2), start, true);
  world.initialize();
  const auto distance = [](const tools::Pose &a, const tools::Pose &b) {
    return (a.position - b.position).norm() + a.orientation.angularDistance(b.orientation) * half_needle.radius();
  };
  std::vector<tools::Pose> poses{start};
  world.step(poses);
  // the other hand, 20 mm off and turned 0.7 rad about a skew axis
  const tools::Pose other{start.position + Vector3d(0.02, -0.01, 0.005),
                          Eigen::Quaterniond(Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized())) * start.orientation};
  world.hand_needle_over(other);
  poses[0] = other;
  world.step(poses);
  EXPECT_LT(distance(world.needle()->pose(), start), 1e-15); // it stays
  // the other hand moves 5 mm and turns 0.3 rad about z: the needle with it, rigidly
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.3, Vector3d::UnitZ()));
  const Vector3d    shift(0, 0, 0.005);
  poses[0] = {turn * (other.position - start.position) + start.position + shift, turn * other.orientation};
  world.step(poses);
  const tools::Pose expected{start.position + shift, turn * start.orientation};
  EXPECT_LT(distance(world.needle()->pose(), expected), 1e-15);
  // handed back to the driver, still at start: the needle stays where the other hand left it
  world.hand_needle_over(start);
  poses[0] = start;
  world.step(poses);
  EXPECT_LT(distance(world.needle()->pose(), expected), 1e-15);
  world.release_needle(7800, 1e-3);
  EXPECT_THROW(world.hand_needle_over(start), std::invalid_argument);
}
