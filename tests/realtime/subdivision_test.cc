// Seed 002 §4.A: the surface model subdivided where the needle touches it
// (realtime/surface_subdivision.h), first on its own, then in a pass of the needle.
#include <suturesim/realtime/home_springs.h>
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/world.h>
#include <suturesim/tools/surgical_pass.h>

#include <gtest/gtest.h>

#include "realtime/test_meshes.h"
#include "realtime/test_worlds.h"

#include <algorithm>
#include <map>
#include <set>

using namespace suturesim;
using namespace suturesim::realtime;

namespace
{
  struct Pad
  {
    mesh::SimplexMesh      mesh     = test_support::box_mesh(0.02, 0.02, 0.01, 4, 4, 2);
    mesh::BoundarySurface  boundary = mesh::extract_boundary(mesh);
    System                 s;
    std::unique_ptr<TissueModel> model;

    explicit Pad(const std::map<std::string, std::string> &values)
    {
      model = test_support::make_model<TissueModel::Registry>("surface", values);
      model->build(s, mesh, boundary, TissueMaterial{1e5, 0.3, 1100, {}}, false);
      s.finalize();
    }
    SpringSet &
    springs()
    {
      return dynamic_cast<SpringSet &>(*s.interactions[0]);
    }
    HomeSprings &
    home()
    {
      return dynamic_cast<HomeSprings &>(*s.interactions[1]);
    }
    /// A triangle of the top face (z = 10 mm).
    std::uint32_t
    top_triangle() const
    {
      for (std::uint32_t t = 0; t < model->surface().size(); ++t)
        {
          bool top = true;
          for (const auto i : model->surface()[t])
            top = top && std::abs(s.nodes.reference(2, i) - 0.01) < 1e-12;
          if (top)
            return t;
        }
      return 0;
    }
    /// Sum of a per-node quantity over the nodes in use (not dormant).
    template <typename Of>
    double
    sum_awake(const Of &of) const
    {
      double total = 0;
      for (std::uint32_t i = 0; i < s.nodes.size(); ++i)
        if (!(s.nodes.held[i] & Nodes::dormant))
          total += of(i);
      return total;
    }
  };

  /// Every directed edge of a closed, consistently oriented surface appears once, and its
  /// reverse once.
  bool
  closed_and_oriented(const std::vector<mesh::Triangle> &triangles)
  {
    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directed;
    for (const auto &t : triangles)
      for (unsigned k = 0; k < 3; ++k)
        ++directed[{t[k], t[(k + 1) % 3]}];
    for (const auto &[edge, count] : directed)
      {
        const auto reverse = directed.find({edge.second, edge.first});
        if (count != 1 || reverse == directed.end() || reverse->second != 1)
          return false;
      }
    return true;
  }
} // namespace

TEST(SurfaceSubdivision, TheTouchedPointBecomesAVertexByLoopsEdgeMaskAndThePatchFollowsSeed002sRule)
{
  // rest length factor 1: the patch is stress-free at creation, so the whole surface
  // stays in equilibrium at rest (a wrong rest length, home or mask would not)
  Pad                pad({{"Subdivision rest length factor", "1"}, {"Subdivision capacity", "2"}});
  auto              &n          = pad.s.nodes;
  const std::uint32_t first_spare = pad.boundary.vertices.size();
  ASSERT_EQ(n.size(), first_spare + 8); // two subdivisions of four nodes set aside
  for (std::uint32_t i = first_spare; i < n.size(); ++i)
    EXPECT_EQ(n.inverse_mass[i], 0) << "spare node " << i << " is dormant";
  const std::uint32_t  t      = pad.top_triangle();
  const mesh::Triangle before = pad.model->surface()[t];
  const std::size_t    triangles_before = pad.model->surface().size(), springs_before = pad.springs().size();
  double               k_mesh = 0, l_max = 0;
  for (unsigned e = 0; e < 3; ++e)
    k_mesh += pad.springs().stiffnesses()[pad.springs().find(before[e], before[(e + 1) % 3])] / 3;
  for (const auto &tri : pad.model->surface())
    for (unsigned e = 0; e < 3; ++e)
      l_max = std::max(l_max, (n.reference.col(tri[e]) - n.reference.col(tri[(e + 1) % 3])).norm());
  const double mass_before = pad.sum_awake([&](auto i) { return n.mass[i]; });
  const auto   home_of     = [&](const std::uint32_t i) {
    const std::size_t h = pad.home().find(i);
    return h < pad.home().size() ? pad.home().stiffness_of(h) : 0.0;
  };
  const double home_before = pad.sum_awake(home_of);

  const Eigen::Vector3d w(0.2, 0.3, 0.5);
  const std::int64_t    P = pad.model->subdivide(pad.s, t, w);
  ASSERT_EQ(P, first_spare);
  const auto &surface = pad.model->surface();
  // the touched point is the new vertex, first in the triangle that keeps the index
  EXPECT_EQ(surface[t][0], P);
  Eigen::Vector3d X = Eigen::Vector3d::Zero();
  for (unsigned k = 0; k < 3; ++k)
    X += w[k] * n.reference.col(before[k]);
  EXPECT_LT((n.reference.col(P) - X).norm(), 1e-15);
  EXPECT_LT((n.x.col(P) - X).norm(), 1e-15);
  // four nodes awake, eight more triangles, twelve more springs, still a closed surface
  for (std::uint32_t i = first_spare; i < first_spare + 8; ++i)
    EXPECT_EQ(n.inverse_mass[i] > 0, i < first_spare + 4) << "node " << i;
  EXPECT_EQ(surface.size(), triangles_before + 8);
  EXPECT_EQ(pad.model->surface_tags().size(), surface.size());
  EXPECT_EQ(pad.springs().size(), springs_before + 12);
  EXPECT_TRUE(closed_and_oriented(surface));
  // Loop's edge mask: E_ab = 3/8 (a + b) + 1/8 (P + d), d opposite ab beyond it; the
  // original edges are gone, split at E
  for (unsigned e = 0; e < 3; ++e)
    {
      const std::uint32_t a = before[e], b = before[(e + 1) % 3], E = P + 1 + e;
      EXPECT_EQ(pad.springs().find(a, b), pad.springs().size()) << "edge " << e;
      std::uint32_t d = 0;
      for (const auto &tri : surface)
        for (unsigned k = 0; k < 3; ++k)
          if (tri[k] == b && tri[(k + 1) % 3] == E)
            d = tri[(k + 2) % 3];
      const Eigen::Vector3d mask = 3. / 8 * (n.reference.col(a) + n.reference.col(b)) +
                                   1. / 8 * (n.reference.col(P) + n.reference.col(d));
      EXPECT_LT((n.reference.col(E) - mask).norm(), 1e-15) << "edge " << e;
    }
  // seed 002's eq. (1) on every spring at a new node: rest length factor x length,
  // k = (l_max/l) k_mesh within [k_mesh, 4 k_mesh]
  unsigned checked = 0;
  for (std::size_t sp = 0; sp < pad.springs().size(); ++sp)
    {
      const auto i = pad.springs().first_ends()[sp], j = pad.springs().second_ends()[sp];
      if (std::max(i, j) < first_spare)
        continue;
      const double l = (n.x.col(i) - n.x.col(j)).norm(), k = pad.springs().stiffnesses()[sp];
      EXPECT_NEAR(pad.springs().rest_lengths()[sp], l, 1e-15);
      EXPECT_NEAR(k, std::clamp(l_max / l * k_mesh, k_mesh, 4 * k_mesh), 1e-9 * k_mesh);
      ++checked;
    }
  EXPECT_EQ(checked, 15u); // 6 spokes, 6 halves, 3 across the neighbours
  // the patch keeps its mass and its home-spring stiffness
  EXPECT_NEAR(pad.sum_awake([&](auto i) { return n.mass[i]; }), mass_before, 1e-12 * mass_before);
  EXPECT_NEAR(pad.sum_awake(home_of), home_before, 1e-9 * home_before);
  // stress-free at rest: no force anywhere
  Matrix3Xd f(3, n.size());
  pad.s.internal_forces(n.x, f);
  EXPECT_LT(f.cwiseAbs().maxCoeff(), 1e-12 * k_mesh * l_max);
  // the capacity: one more, then none
  EXPECT_EQ(pad.model->subdivide(pad.s, pad.top_triangle(), w), first_spare + 4);
  const std::size_t full = surface.size();
  EXPECT_EQ(pad.model->subdivide(pad.s, pad.top_triangle(), w), -1);
  EXPECT_EQ(surface.size(), full);
}

TEST(SurfaceSubdivision, SeedsRestLengthFactorPutsThePatchUnderTensionAndOffTurnsItOff)
{
  Pad          seed({});
  const auto   t = seed.top_triangle();
  const auto   P = seed.model->subdivide(seed.s, t, Eigen::Vector3d(1. / 3, 1. / 3, 1. / 3));
  ASSERT_GE(P, 0);
  // seed 002: 0.9 of the length at creation; the patch pulls its rim inwards
  unsigned shortened = 0;
  for (std::size_t sp = 0; sp < seed.springs().size(); ++sp)
    {
      const auto   i = seed.springs().first_ends()[sp], j = seed.springs().second_ends()[sp];
      const double l = (seed.s.nodes.x.col(i) - seed.s.nodes.x.col(j)).norm();
      if (std::max(i, j) >= static_cast<std::uint32_t>(P))
        {
          EXPECT_NEAR(seed.springs().rest_lengths()[sp], 0.9 * l, 1e-15);
          ++shortened;
        }
    }
  EXPECT_EQ(shortened, 15u);
  EXPECT_GT(seed.s.elastic_energy(seed.s.nodes.x), 0);

  Pad off(std::map<std::string, std::string>{{"Subdivision", "false"}});
  EXPECT_EQ(off.s.nodes.size(), off.boundary.vertices.size()); // no spare nodes
  EXPECT_EQ(off.model->subdivide(off.s, off.top_triangle(), Eigen::Vector3d(1. / 3, 1. / 3, 1. / 3)), -1);
  // the volume model does not subdivide
  System                       s;
  const auto                   mesh  = test_support::box_mesh(0.02, 0.02, 0.01, 2, 2, 1);
  std::unique_ptr<TissueModel> volume = test_support::make_model<TissueModel::Registry>("volume");
  volume->build(s, mesh, mesh::extract_boundary(mesh), TissueMaterial{1e5, 0.3, 1100, {}}, false);
  EXPECT_EQ(volume->subdivide(s, 0, Eigen::Vector3d(1. / 3, 1. / 3, 1. / 3)), -1);
}

TEST(SurfaceSubdivision, ANeedlePassSubdividesAtEachTouchAndItsPiercePointsAreTheNewVertices)
{
  // seed 002 whole: the surface model, the FTL suture, soft constraints (the automatic
  // choice under quasi-static integration), a 3/8 needle in and out through the top.
  // The pierced vertex carries the whole soft-constraint load (a barycentric point
  // shares it with three nodes): with k_q = EA/l = 1.2e5 N/m the quasi-static step
  // needs B > k dt/2 there, so the thread's quasi-spring is softened to 2000 N/m.
  const auto                mesh = test_support::box_mesh(0.04, 0.04, 0.01, 10, 10, 3);
  const auto                boundary = mesh::extract_boundary(mesh);
  const tools::CurvedNeedle needle(0.008, tools::CurvedNeedle::arc_angle_of("3/8"), 4e-4);
  const auto                pass = test_support::block_pass(needle, 0.003);

  WorldSetup w;
  w.mesh     = &mesh;
  w.material = {1e5, 0.3, 1100, {}};
  w.tissue   = test_support::make_model<TissueModel::Registry>("surface");
  const tools::Pose start = pass.trajectory.pose(0);
  w.suture          = test_support::make_model<SutureModel::Registry>("ftl", {{"Quasi-spring constant", "2000"}});
  w.suture_geometry = test_support::straight_suture(100, 0.1, needle.swage(start),
                                                    -needle.tangent(start, needle.length()), 119, 3e-9, 1.1e-4, 1100);
  w.contact_stiffness = 100;
  w.contact_depth     = 1e-3;
  w.integrator = test_support::make_model<Integrator::Registry>("quasi-static", {{"Tissue damping", "0.5"}});
  w.substeps   = 10;
  World world(std::move(w));
  world.fix_vertices(mesh::vertices_with_tag(boundary, 1));
  NeedleCouplingParameters p;
  p.puncture             = {0.5, 2000, 1e-3};
  p.friction             = {0.2, 500, 0.05};
  p.transverse_stiffness = 500;
  p.pierce_model         = "automatic";
  world.add_needle(needle, p, start, true);
  world.initialize();
  EXPECT_EQ(world.needle()->pierce_model(), "soft-constraint");
  const double limit_before = world.stability_limit();

  const std::uint32_t      first_spare = boundary.vertices.size();
  std::vector<tools::Pose> poses(1);
  bool                     order_kept = true, on_vertices = true, dissipates = true;
  std::size_t              most = 0, slips = 0;
  const auto              &x          = world.system().nodes.x;
  for (int k = 1; k <= static_cast<int>(pass.t_end * 1000); ++k)
    {
      poses[0] = pass.trajectory.pose(k * 1e-3);
      world.step(poses);
      const auto &points = world.needle()->pierce_points();
      most               = std::max(most, points.size());
      for (std::size_t i = 0; i + 1 < points.size(); ++i)
        order_kept = order_kept && points[i].anchor < points[i + 1].anchor;
      // each pierce point is a subdivision's first new node, exactly
      for (const auto &q : points)
        {
          dissipates     = test_support::friction_dissipates(q, slips) && dissipates;
          double nearest = 1;
          for (std::uint32_t P = first_spare; P < first_spare + 8; P += 4)
            nearest = std::min(nearest, (x.col(P) - q.position).norm());
          on_vertices = on_vertices && nearest == 0;
        }
    }
  std::vector<std::string> kinds;
  for (const auto &e : world.needle()->thread_events())
    kinds.push_back(e.kind);
  unsigned punctures = 0;
  for (const auto &e : world.needle()->puncture_state().events())
    if (e.kind.rfind("puncture", 0) == 0)
      {
        EXPECT_GE(e.force, 0.5) << e.kind;
        EXPECT_LE(e.force, 0.525) << e.kind; // the threshold within 5 % (issue 5)
        ++punctures;
      }
  EXPECT_EQ(punctures, 2u); // entry and exit
  // one subdivision at each touch (entry and exit), then both points onto the suture
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "subdivision"), 2);
  EXPECT_EQ(std::count(kinds.begin(), kinds.end(), "onto_suture"), 2);
  EXPECT_EQ(most, 2u);
  EXPECT_TRUE(order_kept);
  EXPECT_TRUE(on_vertices);
  // the soft constraints' slip (seed 002 eq. 3) records its friction as the other
  // models do (it had the sign of the tension difference T₋ − T₊ instead, the opposite)
  EXPECT_GT(slips, 0u);
  EXPECT_TRUE(dissipates);
  EXPECT_TRUE(closed_and_oriented(world.tissue()->surface()));
  // the patches' stiffer springs on lighter nodes lower the step's limit, which the world
  // estimates again after each subdivision (with 4 substeps, 0.25 ms, the vertex ran
  // away at the first touch; with 8 the first patch put dt_crit at 0.123 ms, just below
  // the step: measured)
  std::printf("[ subdivision ] dt_crit %.4g s at set-up, %.4g s after the subdivisions, dt %.4g s\n", limit_before,
              world.stability_limit(), world.dt());
  EXPECT_LT(world.stability_limit(), limit_before);
  EXPECT_LT(world.dt(), world.stability_limit());
  EXPECT_TRUE(world.warning().empty()) << world.warning();
}
