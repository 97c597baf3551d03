// The triangle bounding-sphere hierarchy (seed 000 Algorithm 1, bottom-up refit) after
// large deformations, and suture–tissue-surface contact.
#include <suturesim/collision/triangle_sphere_tree.h>
#include <suturesim/collision/volume_penetration.h>
#include <suturesim/mesh/simplex_mesh.h>

#include <gtest/gtest.h>

#include "realtime/test_meshes.h"
#include "realtime/test_worlds.h"

#include <random>
#include <set>

using namespace suturesim;
using namespace suturesim::realtime;

namespace
{
  /// Every leaf bounds its triangle (grown by the thickness), every parent its children.
  void
  expect_bounding(const collision::TriangleSphereTree &tree, const Matrix3Xd &x,
                  const std::vector<mesh::Triangle> &triangles)
  {
    const auto &s   = tree.spheres();
    const double eps = 1e-12;
    for (std::size_t leaf = 0; leaf < tree.n_leaves(); ++leaf)
      for (const auto v : triangles[tree.triangle(leaf)])
        EXPECT_LE((x.col(v) - s[leaf].centre).norm() + tree.thickness(), s[leaf].radius + eps)
          << "leaf " << leaf;
    std::size_t children = 0;
    for (std::size_t n = tree.n_leaves(); n < s.size(); ++n)
      for (const int c : {tree.left_child(n), tree.right_child(n)})
        if (c >= 0)
          {
            EXPECT_LE((s[c].centre - s[n].centre).norm() + s[c].radius, s[n].radius + eps)
              << "node " << n << " child " << c;
            ++children;
          }
    EXPECT_EQ(children, s.size() - 1); // every node but the root is some node's child
  }
} // namespace

TEST(TriangleSphereTree, RefitBoundsEveryTriangleAfterLargeDeformations)
{
  const auto mesh    = test_support::box_mesh(0.04, 0.04, 0.01, 8, 8, 2);
  const auto surface = mesh::extract_boundary(mesh);
  Matrix3Xd  x       = mesh.vertices;
  collision::TriangleSphereTree tree;
  tree.build(x, surface.triangles, 1e-4);
  expect_bounding(tree, x, surface.triangles);

  std::mt19937                           rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int round = 0; round < 4; ++round)
    {
      // twist about z, bend in z, stretch in x, and noise of a fifth of the block's size
      for (Eigen::Index v = 0; v < x.cols(); ++v)
        {
          const Vector3d p = x.col(v);
          x.col(v)         = Eigen::AngleAxisd(10 * p[2], Vector3d::UnitZ()) * p +
                     Vector3d(0.5 * p[0], 0, 20 * p[0] * p[0]) +
                     0.008 * Vector3d(u(rng), u(rng), u(rng));
        }
      tree.refit(x);
      expect_bounding(tree, x, surface.triangles);

      // candidate pairs against probe triangles on mesh vertices: every triangle sharing a
      // point with a probe must be found (both leaf spheres hold that point)
      collision::TriangleSphereTree other;
      std::vector<mesh::Triangle>   probe_triangles;
      Matrix3Xd                     probe = Matrix3Xd::Zero(3, 30);
      for (int k = 0; k < 10; ++k)
        {
          for (int j = 0; j < 3; ++j)
            probe.col(3 * k + j) = x.col((37 * k + 11 * j) % x.cols());
          probe_triangles.push_back({std::uint32_t(3 * k), std::uint32_t(3 * k + 1), std::uint32_t(3 * k + 2)});
        }
      other.build(probe, probe_triangles, 0);
      collision::LeafPairs pairs;
      tree.overlaps(other, 0, pairs);
      std::set<std::pair<std::uint32_t, std::uint32_t>> found;
      for (const auto &[a, b] : pairs)
        found.insert({tree.triangle(a), other.triangle(b)});
      std::size_t expected = 0;
      for (std::uint32_t t = 0; t < surface.triangles.size(); ++t)
        for (std::uint32_t p = 0; p < probe_triangles.size(); ++p)
          {
            bool close = false;
            for (const auto a : surface.triangles[t])
              for (const auto b : probe_triangles[p])
                close = close || (x.col(a) - probe.col(b)).norm() == 0;
            if (close)
              {
                ++expected;
                EXPECT_TRUE(found.count({t, p})) << "triangle " << t << " probe " << p;
              }
          }
      EXPECT_GT(expected, 0u);
    }

  // a partial refit of the moved vertices equals a full refit
  collision::TriangleSphereTree full = tree;
  std::vector<std::uint32_t>    moved{5, 77, 160};
  for (const auto v : moved)
    x.col(v) += Vector3d(0.01, -0.02, 0.03);
  const std::size_t recomputed = tree.refit(x, moved);
  full.refit(x);
  for (std::size_t n = 0; n < full.spheres().size(); ++n)
    {
      EXPECT_LT((tree.spheres()[n].centre - full.spheres()[n].centre).norm(), 1e-14);
      EXPECT_NEAR(tree.spheres()[n].radius, full.spheres()[n].radius, 1e-14);
    }
  EXPECT_LT(recomputed, tree.spheres().size() / 4);
  expect_bounding(tree, x, surface.triangles);
}

TEST(SurfaceContact, SutureLyingAcrossABlockStaysOnItsTopAndIsNotPushedOverTheEdge)
{
  // A suture lies two radii above the top of a block and overhangs it on both sides.
  // Nodes next to the top edges must touch the top, not be taken to be behind the side
  // faces (regression: they were pushed out over the edge and the run diverged); under
  // gravity the suture rests on the top with no node inside it.
  const double H = 0.01, r = 1.1e-4;
  const auto   mesh = test_support::box_mesh(0.04, 0.04, H, 8, 8, 2);
  WorldSetup   w;
  w.mesh              = &mesh;
  w.material          = {6e3, 0.45, 1060, {}};
  w.tissue            = test_support::make_model<TissueModel::Registry>("volume");
  w.suture            = test_support::make_model<SutureModel::Registry>("xpbd-rod");
  w.suture_geometry   = test_support::straight_suture(99, 0.06, Vector3d(-0.01, 0.02, H + 2 * r),
                                                      Vector3d::UnitX(), 118, 3.7e-7, r, 1140);
  w.contact           = true;
  w.contact_stiffness = 100;
  w.contact_depth     = 1e-3;
  w.integrator        = test_support::make_model<Integrator::Registry>("xpbd", {{"Iterations", "4"}});
  w.gravity           = Vector3d(0, 0, -9.81);
  World world(std::move(w));
  world.fix_vertices(mesh::vertices_with_tag(mesh::extract_boundary(mesh), 1));
  world.initialize();
  world.step({});
  // after one step no node over the top is in contact with a side face: the nodes next
  // to the edges are nearer the top (2 r, no contact yet) than the side faces they are
  // 0.3 mm "behind" (the regression put such contacts in the list); once the suture
  // rests on the top (below), every contact over it has the top's normal
  const auto &contact  = *world.surface_contact();
  const auto  over_top = [&](const auto &c) {
    const double X = world.system().nodes.reference(0, c.node);
    return X > 0 && X < 0.04;
  };
  unsigned on_side = 0;
  for (const auto &c : contact.list())
    on_side += over_top(c) && !(c.normal[2] > 0.999);
  EXPECT_EQ(on_side, 0u) << "a node over the top in contact with a side face after one step";
  for (int k = 0; k < 500; ++k)
    world.step({});
  const auto &n = world.system().nodes;
  const auto  s = world.system().suture;
  double deepest = 0, sideways = 0;
  for (auto i = s.begin; i < s.end; ++i)
    sideways = std::max(sideways, std::abs(n.x(1, i) - n.reference(1, i)));
  unsigned resting = 0;
  for (const auto &c : contact.list())
    {
      deepest = std::min(deepest, contact.gap(c, n.x));
      // over the top where they are now (the overhangs' first nodes have slid past
      // the edges and touch the side faces, rightly)
      if (n.x(0, c.node) > 0 && n.x(0, c.node) < 0.04)
        {
          EXPECT_GT(c.normal[2], 0.999) << "node " << c.node << " at x = " << n.x(0, c.node) << " normal "
                                        << c.normal.transpose();
          ++resting;
        }
    }
  EXPECT_GT(resting, 40u); // the part on the top touches it (66 nodes lie over it)
  std::printf("[ contact ] %zu contacts, deepest gap %.2e m (radius %.1e m), largest sideways "
              "motion %.2e m\n",
              contact.active(), deepest, r, sideways);
  EXPECT_GT(contact.active(), 40u); // the part on the top touches (66 nodes lie over it)
  EXPECT_GT(deepest, -0.05 * r);    // no node more than 5 % of a radius into the surface
  EXPECT_LT(sideways, 0.5 * r);     // nothing pushes the suture off its line
  EXPECT_LT(n.x(2, s.end - 1), H - 0.001); // the overhangs hang down past the edges
}

TEST(TriangleSphereTree, LazyUpdateBoundsEveryTriangleAndRefitsOnlyEscapedVertices)
{
  // the fat-bounds refit (TriangleSphereTree::update): leaves grown by a slack s are
  // refitted only where a vertex moved farther than s since its last fit
  const auto mesh    = test_support::box_mesh(0.04, 0.04, 0.01, 8, 8, 2);
  const auto surface = mesh::extract_boundary(mesh);
  Matrix3Xd  x       = mesh.vertices;
  const double slack = 2e-4;
  collision::TriangleSphereTree tree;
  tree.build(x, surface.triangles, 1e-4);
  tree.update(x, slack);
  expect_bounding(tree, x, surface.triangles);

  // 200 small motions (micrometres, as tissue moves per haptic step) adding up far
  // beyond the slack: the bounds hold after every one, and the work is a fraction of
  // refitting every node each time
  std::mt19937                           rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  std::size_t                            recomputed = 0, updates = 0;
  for (int step = 0; step < 200; ++step)
    {
      for (Eigen::Index v = 0; v < x.cols(); ++v)
        x.col(v) += 5e-6 * Vector3d(1 + u(rng), u(rng), 0.5 * u(rng));
      recomputed += tree.update(x, slack);
      ++updates;
      expect_bounding(tree, x, surface.triangles);
    }
  EXPECT_LT(recomputed, updates * tree.spheres().size() / 4)
    << "the slack should absorb most small motions";

  // a large deformation escapes everywhere and is bounded at once
  for (Eigen::Index v = 0; v < x.cols(); ++v)
    x.col(v) = Eigen::AngleAxisd(8 * x(2, v), Vector3d::UnitZ()) * x.col(v) + Vector3d(0, 0, 10 * x(0, v) * x(0, v));
  EXPECT_GT(tree.update(x, slack), tree.n_leaves() / 2);
  expect_bounding(tree, x, surface.triangles);
}

TEST(VolumePenetration, FindsThePointsDeeperThanTheToleranceWithTheirDepthFromCellsOrSurface)
{
  // a 2 × 1 × 1 cm box of 4 × 2 × 2 Kuhn cubes; its boundary from the cells
  const auto mesh    = test_support::box_mesh(0.02, 0.01, 0.01, 4, 2, 2);
  const auto surface = mesh::extract_boundary(mesh);
  Matrix3Xd  points(3, 5);
  points.col(0) << 0.010, 0.005, 0.007;  // inside, 3 mm below the top
  points.col(1) << 0.0031, 0.0047, 0.0098; // inside, 0.2 mm below the top: within tolerance
  points.col(2) << 0.010, 0.005, 0.0105; // above the top
  points.col(3) << 0.0195, 0.004, 0.005;  // inside, 0.5 mm from the end face x = 0.02
  points.col(4) << 0.012, 0.005, 0.004;  // inside, 4 mm deep
  const auto r = collision::volume_penetration(mesh.vertices, mesh.tetrahedra, surface.triangles, points, 3e-4);
  ASSERT_EQ(r.points, (std::vector<std::size_t>{0, 3, 4}));
  EXPECT_NEAR(r.depths[0], 3e-3, 1e-12);
  EXPECT_NEAR(r.depths[1], 5e-4, 1e-12);
  EXPECT_NEAR(r.depths[2], 4e-3, 1e-12);
  // a point on a face shared by two cells, and one at a vertex, count as inside
  EXPECT_TRUE(collision::inside_tetrahedron(Vector3d(0.25, 0.25, 0), Vector3d(0, 0, 0), Vector3d(1, 0, 0),
                                            Vector3d(0, 1, 0), Vector3d(0, 0, 1)));
  EXPECT_FALSE(collision::inside_tetrahedron(Vector3d(0.5, 0.5, 0.1), Vector3d(0, 0, 0), Vector3d(1, 0, 0),
                                             Vector3d(0, 1, 0), Vector3d(0, 0, 1)));
  // deformed: the box's top pushed down by 4 mm near x = 1 cm leaves point 0 above it
  Matrix3Xd x = mesh.vertices;
  for (Eigen::Index v = 0; v < x.cols(); ++v)
    if (x(2, v) > 0.009 && std::abs(x(0, v) - 0.01) < 1e-9)
      x(2, v) -= 0.004;
  const auto dented = collision::volume_penetration(x, mesh.tetrahedra, surface.triangles, points, 3e-4);
  EXPECT_EQ(dented.points, (std::vector<std::size_t>{3, 4}));

  // the same from the boundary alone (the accurate path knows its tissue by its surface):
  // winding number 1 inside, 0 outside (also a nanometre either side of the top face),
  // and the same points and depths
  EXPECT_NEAR(collision::winding_number(points.col(0), mesh.vertices, surface.triangles), 1, 1e-12);
  EXPECT_NEAR(collision::winding_number(points.col(2), mesh.vertices, surface.triangles), 0, 1e-12);
  EXPECT_NEAR(collision::winding_number(Vector3d(0.0101, 0.0043, 0.01 - 1e-9), mesh.vertices, surface.triangles), 1, 1e-6);
  EXPECT_NEAR(collision::winding_number(Vector3d(0.0101, 0.0043, 0.01 + 1e-9), mesh.vertices, surface.triangles), 0, 1e-6);
  const auto from_surface = collision::surface_penetration(mesh.vertices, surface.triangles, points, 3e-4);
  EXPECT_EQ(from_surface.points, r.points);
  for (std::size_t k = 0; k < r.depths.size(); ++k)
    EXPECT_DOUBLE_EQ(from_surface.depths[k], r.depths[k]);
  EXPECT_EQ(collision::surface_penetration(x, surface.triangles, points, 3e-4).points, dented.points);
}

#include <suturesim/collision/proximity.h>

TEST(Proximity, SegmentCrossesATriangleWhereTheLineMeetsItsPlaneInside)
{
  using suturesim::collision::segment_crosses_triangle;
  const Eigen::Vector3d a(0, 0, 0), b(2, 0, 0), c(0, 2, 0);
  double                s = -1;
  Eigen::Vector3d       bary;
  // through (0.5, 0.25, 0) a quarter of the way along, from either side
  ASSERT_TRUE(segment_crosses_triangle({0.5, 0.25, -1}, {0.5, 0.25, 3}, a, b, c, s, bary));
  EXPECT_NEAR(s, 0.25, 1e-15);
  EXPECT_NEAR((bary[0] * a + bary[1] * b + bary[2] * c - Eigen::Vector3d(0.5, 0.25, 0)).norm(), 0, 1e-15);
  EXPECT_NEAR(bary.sum(), 1, 1e-15);
  ASSERT_TRUE(segment_crosses_triangle({0.5, 0.25, 3}, {0.5, 0.25, -1}, a, b, c, s, bary));
  EXPECT_NEAR(s, 0.75, 1e-15);
  // a slanted one: from (1.5, 1.5, 1) to (-0.5, -0.5, -1) meets the plane at (0.5, 0.5)
  ASSERT_TRUE(segment_crosses_triangle({1.5, 1.5, 1}, {-0.5, -0.5, -1}, a, b, c, s, bary));
  EXPECT_NEAR(s, 0.5, 1e-15);
  EXPECT_NEAR(bary[1], 0.25, 1e-15);
  EXPECT_NEAR(bary[2], 0.25, 1e-15);
  // misses: outside the triangle, short of the plane, and in the plane
  EXPECT_FALSE(segment_crosses_triangle({1.5, 1.5, -1}, {1.5, 1.5, 1}, a, b, c, s, bary));
  EXPECT_FALSE(segment_crosses_triangle({0.5, 0.25, 1}, {0.5, 0.25, 0.1}, a, b, c, s, bary));
  EXPECT_FALSE(segment_crosses_triangle({0.1, 0.1, 0}, {0.5, 0.5, 0}, a, b, c, s, bary));
}

namespace
{
  /// A block with an ftl thread of 20 links of 1 mm (k_q = 1e4 N/m) held at both ends by
  /// tools, the thread's contact with the block, and Realtime/Contact load as @p load.
  std::unique_ptr<World>
  thread_on_a_block(const mesh::SimplexMesh &mesh, const bool load)
  {
    WorldSetup w;
    w.mesh              = &mesh;
    w.material          = {6e3, 0.45, 1060, {}};
    w.tissue            = test_support::make_model<TissueModel::Registry>("volume");
    w.suture            = test_support::make_model<SutureModel::Registry>(
      "ftl", {{"Gravity speed", "0"}, {"Quasi-spring constant", "1e4"}, {"Tension law", "per link"}});
    w.suture_geometry   = test_support::straight_suture(20, 0.02, Vector3d(0, 0.0112, 0.0102), Vector3d::UnitX());
    w.contact_stiffness = 100;
    w.contact_depth     = 1e-3;
    w.contact_load      = load;
    w.integrator        = test_support::make_model<Integrator::Registry>("quasi-static");
    auto        world   = std::make_unique<World>(std::move(w));
    const auto &s       = world->system();
    world->add_tool("left", {s.suture.begin}, ToolPose());
    ToolPose right;
    right.position = s.nodes.x.col(s.suture.end - 1);
    world->add_tool("right", {s.suture.end - 1}, right);
    world->initialize();
    return world;
  }
} // namespace

TEST(SurfaceContact, AnFtlThreadBentOverTheSurfaceLoadsItWithTheWholeTurnsPull)
{
  // The thread rises at α to a crest on the block's top and falls at α beyond it, the
  // turn 2α shared by the seven nodes of the crest (each within the contact's skin) and
  // its links stretched by 1 % (one section between the tools, tension T). With
  // Realtime/Contact load the surface carries the pull of the whole turn,
  // Σ T (â + b̂)·n = −2T sin α (the legs' nodes are straight: nothing), into the top
  // along its normal and on the triangles' corners; without it, only the penalty.
  const double H = 0.01, r = 1e-4, alpha = 0.2, l = 1e-3 * 1.01;
  const auto   block = test_support::box_mesh(0.03, 0.02, H, 6, 4, 2);
  const auto lay = [&](World &world, const double crest, const double sign) {
    auto      &x = world.system().nodes.x;
    const auto s = world.system().suture;
    // link k (node k to k + 1) at angle a_k: +α up to node 7, turning by 2α/7 at each
    // of nodes 7–13, −α beyond; then the whole lifted so that its top is at @p crest
    Matrix3Xd p(3, s.size());
    p.col(0) = Vector3d(0.0062, 0.0112, 0);
    for (std::uint32_t k = 0; k + 1 < s.size(); ++k)
      {
        const double a = sign * std::clamp(alpha - (double(k) - 6.5) * 2 * alpha / 7, -alpha, alpha);
        p.col(k + 1)   = p.col(k) + l * Vector3d(std::cos(a), 0, std::sin(a));
      }
    p.row(2).array() += crest - (sign > 0 ? p.row(2).maxCoeff() : p.row(2).minCoeff());
    for (std::uint32_t k = 0; k < s.size(); ++k)
      x.col(s.begin + k) = p.col(k);
  };
  struct Load
  {
    Vector3d    total = Vector3d::Zero();
    double      T     = 0;
    std::size_t touching = 0;
  };
  const auto load_of = [&](World &world, const bool carried) {
    auto       &contact = dynamic_cast<SurfaceContact &>(*world.system().contacts.front());
    const auto &x       = world.system().nodes.x;
    contact.detect(x);
    Matrix3Xd with = Matrix3Xd::Zero(3, x.cols()), penalty = with;
    contact.add_forces(x, with);
    contact.NodeTriangleContacts::add_forces(x, penalty);
    Load result;
    const auto t = world.system().tissue;
    for (auto i = t.begin; i < t.end; ++i)
      result.total += with.col(i) - penalty.col(i);
    if (!carried)
      {
        EXPECT_EQ((with - penalty).norm(), 0) << "a load without Contact load";
      }
    std::vector<double> T;
    world.suture()->segment_tension(world.system(), T);
    result.T = T.front();
    for (const double Tk : T)
      EXPECT_NEAR(Tk, result.T, 1e-12 * result.T) << "one section: one tension";
    for (const auto &c : contact.list())
      result.touching += contact.gap(c, x) <= 0.25 * r;
    return result;
  };
  for (const bool carried : {true, false})
    {
      auto world = thread_on_a_block(block, carried);
      lay(*world, H + 1.2 * r, +1); // the crest's top node 0.2 r above the top: resting
      const Load over = load_of(*world, carried);
      const double expected = carried ? -2 * over.T * std::sin(alpha) : 0;
      std::printf("[ contact load ] %s: T = %.4e N, %zu nodes within the skin, load on the tissue "
                  "(%.3e, %.3e, %.3e) N, expected z %.6e N\n",
                  carried ? "carried" : "not carried", over.T, over.touching, over.total[0], over.total[1],
                  over.total[2], expected);
      EXPECT_NEAR(over.T, 1e4 * 1e-3 * 0.01, 1e-9); // k_q l (L − m)/m, the links 1 % long
      EXPECT_GE(over.touching, 9u); // the crest's seven nodes and leg nodes below them
      EXPECT_NEAR(over.total[2], expected, 1e-9 * over.T);
      EXPECT_NEAR(over.total[0], 0, 1e-9 * over.T);
      EXPECT_NEAR(over.total[1], 0, 1e-9 * over.T);
    }
  {
    // the same thread sagging onto the surface (its lowest node resting on it) pulls away
    // from it: a surface does not hold a thread up from below, and nothing is carried
    auto world = thread_on_a_block(block, true);
    lay(*world, H + 1.2 * r, -1);
    const Load sag = load_of(*world, true);
    EXPECT_GE(sag.touching, 1u);
    EXPECT_EQ(sag.total.norm(), 0);
  }
  {
    // only for a thread moved geometrically, under a force-based integrator
    WorldSetup w;
    const auto h      = test_support::box_mesh(0.02, 0.02, H, 2, 2, 1);
    w.mesh            = &h;
    w.material        = {6e3, 0.45, 1060, {}};
    w.tissue          = test_support::make_model<TissueModel::Registry>("volume");
    w.suture          = test_support::make_model<SutureModel::Registry>("xpbd-rod");
    w.suture_geometry = test_support::straight_suture(10, 0.01, Vector3d(0, 0.01, 0.0102), Vector3d::UnitX());
    w.contact_load    = true;
    w.integrator      = test_support::make_model<Integrator::Registry>("xpbd");
    EXPECT_THROW(World world(std::move(w)), ParameterError);
  }
}
