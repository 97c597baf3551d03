
// The needle in the realtime world: a planned surgical pass through the top of a block
// (entry and exit on the same face), puncture at the threshold, two pierce points that
// keep their order, and the suture drawn after the needle.
#include <suturesim/realtime/world.h>
#include <suturesim/tools/surgical_pass.h>

#include <gtest/gtest.h>

#include "realtime/test_meshes.h"
#include "realtime/test_worlds.h"

using namespace suturesim;
using namespace suturesim::realtime;

namespace
{
  struct PassRun
  {
    std::vector<double>             time, force; ///< |needle force|
    std::vector<coupling::PunctureEvent> events;
    std::vector<PiercePointState>   final_points;
    std::vector<coupling::PunctureEvent> thread_events;
    std::size_t                     max_points = 0;
    bool                            order_kept = true;
    bool                            on_node_grid = true; ///< every anchor at swage + i·link
    std::size_t                     slips        = 0;    ///< point-steps with the anchor moving
    bool                            friction_dissipates = true; ///< test_support::friction_dissipates()
  };


  PassRun
  run_pass(const std::string &integrator, const double mu, const bool with_suture,
           const std::string &shape = "3/8", const std::string &suture_model = "ftl",
           const std::string &pierce_model = "automatic", const double load_radius = 0)
  {
    const auto mesh = test_support::box_mesh(0.04, 0.04, 0.01, 10, 10, 3);
    const tools::CurvedNeedle needle(0.008, tools::CurvedNeedle::arc_angle_of(shape), 4e-4);
    const auto                pass = test_support::block_pass(needle, 0.004);

    WorldSetup w;
    w.mesh     = &mesh;
    w.material = {1e5, 0.3, 1100, {}};
    w.tissue   = test_support::make_model<TissueModel::Registry>("volume");
    const tools::Pose start = pass.trajectory.pose(0);
    if (with_suture)
      {
        // the suture leaves the swage backwards along the needle
        const Vector3d swage = needle.swage(start), away = -needle.tangent(start, needle.length());
        w.suture          = test_support::make_model<SutureModel::Registry>(suture_model);
        w.suture_geometry = test_support::straight_suture(100, 0.1, swage, away, 119, 3e-9, 1.1e-4, 1100);
        w.contact_stiffness = 100;
        w.contact_depth     = 1e-3;
      }
    w.integrator = test_support::make_model<Integrator::Registry>(
      integrator, integrator == "xpbd" ? std::map<std::string, std::string>{{"Iterations", "4"}, {"Suture iterations", "8"}, {"Damping rate", "20"}}
                                       : std::map<std::string, std::string>{{"Tissue damping", "0.5"}});
    w.substeps = integrator == "xpbd" ? 1 : 4;
    World world(std::move(w));
    world.fix_vertices(mesh::vertices_with_tag(mesh::extract_boundary(mesh), 1));
    NeedleCouplingParameters p;
    p.puncture           = {0.5, 2000, 1e-3};
    p.friction           = {mu, 500, 0.05};
    p.transverse_stiffness = 500;
    p.pierce_model       = pierce_model;
    p.load_radius        = load_radius;
    const auto tool      = world.add_needle(needle, p, start, with_suture);
    world.initialize();

    PassRun            run;
    std::vector<tools::Pose> poses(1);
    const int          steps = static_cast<int>(pass.t_end * 1000);
    for (int k = 1; k <= steps; ++k)
      {
        poses[0] = pass.trajectory.pose(k * 1e-3);
        const auto &forces = world.step(poses);
        run.time.push_back(world.time());
        run.force.push_back(forces[tool].force.norm());
        const auto &points = world.needle()->pierce_points();
        run.max_points     = std::max(run.max_points, points.size());
        // node-slip points may share a node (in list order); the others keep a gap
        for (std::size_t i = 0; i + 1 < points.size(); ++i)
          run.order_kept = run.order_kept && (pierce_model == "node-slip"
                                                ? points[i].anchor <= points[i + 1].anchor
                                                : points[i].anchor < points[i + 1].anchor);
        const double link = with_suture ? 0.1 / 100 : needle.length(); // 100 links
        for (const auto &q : points)
          {
            run.friction_dissipates = test_support::friction_dissipates(q, run.slips) && run.friction_dissipates;
            const double i = (q.anchor - needle.length()) / link;
            run.on_node_grid = run.on_node_grid && std::abs(i - std::round(i)) < 1e-9;
          }
      }
    run.events        = world.needle()->puncture_state().events();
    run.thread_events = world.needle()->thread_events();
    run.final_points = world.needle()->pierce_points();
    return run;
  }

  /// The pass punctured the entry, then the exit, each at the contact force of the
  /// threshold within 5 % (issue 5).
  void
  expect_punctures_at_the_threshold(const PassRun &run, const std::string &integrator)
  {
    std::vector<std::string> kinds;
    for (const auto &e : run.events)
      if (e.kind.rfind("puncture", 0) == 0)
        {
          kinds.push_back(e.kind);
          EXPECT_GE(e.force, 0.5) << integrator << " " << e.kind;
          EXPECT_LE(e.force, 0.525) << integrator << " " << e.kind;
        }
    EXPECT_EQ(kinds, (std::vector<std::string>{"puncture_entry", "puncture_exit"})) << integrator;
  }
} // namespace

TEST(RealtimeNeedle, PassPuncturesAtTheThresholdAndLeavesTwoOrderedPiercePoints)
{
  // a half-circle needle without suture: its swage reaches the entry hole only after the
  // tip is out, so both pierce points live together on the needle, then slip off the
  // swage (released) as the needle leaves
  for (const std::string integrator : {"xpbd", "quasi-static"})
    {
      const PassRun run = run_pass(integrator, 0.2, false, "1/2");
      expect_punctures_at_the_threshold(run, integrator);
      EXPECT_EQ(run.max_points, 2u) << integrator;
      EXPECT_TRUE(run.order_kept) << integrator;
      EXPECT_TRUE(run.final_points.empty()) << integrator;
      EXPECT_EQ(run.thread_events.size(), 2u) << integrator;
      // the needle's force peaks at the two punctures and drops after each (the dimple
      // and the tent relax as the tissue slides on the needle)
      const auto at = [&](const double t) {
        return run.force[static_cast<std::size_t>(std::lround(t * 1000)) - 1];
      };
      unsigned dropped = 0;
      for (const auto &e : run.events)
        if (e.kind.rfind("puncture", 0) == 0)
          {
            EXPECT_LT(at(e.time + 0.05), 0.5 * e.force) << integrator << " after " << e.kind;
            ++dropped;
          }
      EXPECT_EQ(dropped, 2u) << integrator;
    }
}

TEST(RealtimeNeedle, PiercePointsPassFromTheNeedleOntoTheSutureInOrder)
{
  // the 3/8 needle's swage reaches the entry hole before the tip is out: the entry point
  // moves onto the suture, then the exit point; both stay, in order, while the needle
  // draws the suture through
  const PassRun run = run_pass("xpbd", 0.2, true);
  std::vector<std::string> kinds;
  for (const auto &e : run.thread_events)
    kinds.push_back(e.kind);
  EXPECT_EQ(kinds, (std::vector<std::string>{"onto_suture", "onto_suture"}));
  ASSERT_EQ(run.final_points.size(), 2u);
  EXPECT_TRUE(run.final_points[0].on_suture && run.final_points[1].on_suture);
  EXPECT_TRUE(run.final_points[0].exit);
  EXPECT_FALSE(run.final_points[1].exit);
  EXPECT_TRUE(run.order_kept);
  EXPECT_GT(run.slips, 0u);
  EXPECT_TRUE(run.friction_dissipates);
}

TEST(RealtimeNeedle, SpreadPiercePointsPunctureAtTheThresholdAndPassOntoTheSutureInOrder)
{
  // Pierce loads spread over 6 mm (Pierce points/Load radius; the block's longest surface
  // edge is the 4 mm cells' diagonal, 5.66 mm). XPBD with the suture corrects the points
  // through their generalised inverse mass Σ W_I² w_I; quasi-static integration without
  // it (a 1/2 needle, as in the test above: this block's quasi-static pass with the
  // suture diverges with point loads as well) spreads the tie's penalty forces. The
  // passes behave as with point loads: punctures at the threshold, the points in order,
  // onto the suture or released as the needle leaves.
  const PassRun xpbd = run_pass("xpbd", 0.2, true, "3/8", "ftl", "automatic", 0.006);
  expect_punctures_at_the_threshold(xpbd, "xpbd");
  std::vector<std::string> onto;
  for (const auto &e : xpbd.thread_events)
    onto.push_back(e.kind);
  EXPECT_EQ(onto, (std::vector<std::string>{"onto_suture", "onto_suture"}));
  ASSERT_EQ(xpbd.final_points.size(), 2u);
  EXPECT_TRUE(xpbd.final_points[0].exit);
  EXPECT_TRUE(xpbd.order_kept);

  const PassRun quasi_static = run_pass("quasi-static", 0.2, false, "1/2", "ftl", "automatic", 0.006);
  expect_punctures_at_the_threshold(quasi_static, "quasi-static");
  EXPECT_EQ(quasi_static.max_points, 2u);
  EXPECT_TRUE(quasi_static.order_kept);
  EXPECT_TRUE(quasi_static.final_points.empty());
  // sampled at the nodes, a radius must exceed the surface's longest edge: checked where
  // the needle is added
  EXPECT_THROW(run_pass("xpbd", 0.2, true, "3/8", "ftl", "automatic", 0.005), std::invalid_argument);
}

TEST(RealtimeNeedle, NodeSlipPointsJumpFromNodeToNodeOntoTheSuture)
{
  // seed 001's hole under both kinds of integrator: each point is joined to a node of
  // the thread (the suture's, continued along the needle at the same spacing) and can
  // reach the suture only by slipping node by node, about 19 nodes along the needle;
  // with the slip rule broken (never moving) neither point would pass the swage
  for (const std::string integrator : {"xpbd", "quasi-static"})
    {
      const PassRun run = run_pass(integrator, 0.2, true, "3/8", "ftl", "node-slip");
      std::vector<std::string> kinds;
      for (const auto &e : run.thread_events)
        kinds.push_back(e.kind);
      EXPECT_EQ(kinds, (std::vector<std::string>{"onto_suture", "onto_suture"})) << integrator;
      ASSERT_EQ(run.final_points.size(), 2u) << integrator;
      EXPECT_TRUE(run.final_points[0].exit) << integrator;
      EXPECT_TRUE(run.order_kept) << integrator;
      EXPECT_TRUE(run.on_node_grid) << integrator;
      EXPECT_GT(run.slips, 0u) << integrator;
      EXPECT_TRUE(run.friction_dissipates) << integrator;
    }
  // the model's name is checked where the needle is added
  EXPECT_THROW(run_pass("xpbd", 0.2, true, "3/8", "ftl", "no-such-model"), std::invalid_argument);
  // seed 002's soft constraints need the FTL suture under a force-based integrator
  EXPECT_THROW(run_pass("xpbd", 0.2, true, "3/8", "ftl", "soft-constraint"), std::invalid_argument);
}
