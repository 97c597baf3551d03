// The seeds' models against what they promise: home springs restore the rest shape
// (seed 001 Fig. 1); follow-the-leader keeps its links and its quasi-spring tension
// (seed 002 §3); quasi-static and XPBD chains settle on the static catenary of the same
// discrete chain; XPBD's stretch error falls with iterations.
#include <suturesim/realtime/spring_set.h>

#include <gtest/gtest.h>

#include "realtime/test_meshes.h"
#include "realtime/test_worlds.h"

using namespace suturesim;
using namespace suturesim::realtime;

TEST(RealtimeModels, HomeSpringsRestoreTheRestShapeAfterTheLoadIsRemoved)
{
  // seed 001, Fig. 1: a surface model pressed in and let go returns to its shape
  const auto mesh = test_support::box_mesh(0.02, 0.02, 0.01, 4, 4, 2);
  WorldSetup w;
  w.mesh       = &mesh;
  w.material   = {1e4, 0.3, 1000, {}};
  w.tissue     = test_support::make_model<TissueModel::Registry>("surface");
  w.integrator = test_support::make_model<Integrator::Registry>("quasi-static", {{"Tissue damping", "2"}});
  w.rate       = 1000;
  World world(std::move(w));
  // the load: 0.05 N down on the top centre node, for the first 0.2 s
  std::uint32_t centre = 0;
  for (Eigen::Index v = 0; v < mesh.vertices.cols(); ++v)
    if ((mesh.vertices.col(v) - Vector3d(0.01, 0.01, 0.01)).norm() < 1e-9)
      centre = world.tissue()->node(v);
  world.set_loads([&](const double t, Matrix3Xd &f) {
    if (t <= 0.2)
      f(2, centre) = -0.05;
  });
  world.initialize();
  ASSERT_TRUE(world.warning().empty()) << world.warning();
  const auto displacement = [&] {
    return (world.system().nodes.x - world.system().nodes.reference).colwise().norm().maxCoeff();
  };
  while (world.time() < 0.2 - 1e-12)
    world.step({});
  const double loaded = displacement();
  while (world.time() < 1.4 - 1e-12)
    world.step({});
  const double released = displacement();
  std::printf("[ home springs ] max displacement loaded %.3e m, 1.2 s after release %.3e m\n", loaded,
              released);
  EXPECT_GT(loaded, 1e-4);
  EXPECT_LT(released, 1e-6 * loaded);
}

TEST(RealtimeModels, FollowTheLeaderKeepsEveryLinkAtItsLength)
{
  WorldSetup w;
  w.suture          = test_support::make_model<SutureModel::Registry>("ftl", {{"Gravity speed", "0"}});
  w.suture_geometry = test_support::straight_suture(30, 0.03, Vector3d::Zero(), Vector3d::UnitX());
  w.integrator      = test_support::make_model<Integrator::Registry>("xpbd");
  World world(std::move(w));
  world.add_tool("grasp", {world.system().suture.begin}, ToolPose());
  world.initialize();
  const double l = world.suture()->link_length();
  double       worst = 0;
  for (int step = 1; step <= 500; ++step)
    {
      // the grasped end draws a circle of 10 mm radius in the y–z plane, then lifts
      const double a = 2 * M_PI * step / 500;
      ToolPose     pose;
      pose.position = Vector3d(0.005 * step / 500, 0.01 * std::sin(a), 0.01 * (1 - std::cos(a)));
      world.step({pose});
      const auto &x = world.system().nodes.x;
      for (auto i = world.system().suture.begin; i + 1 < world.system().suture.end; ++i)
        worst = std::max(worst, std::abs((x.col(i + 1) - x.col(i)).norm() - l));
    }
  std::printf("[ FTL ] largest link length error over 500 steps: %.2e m (l = %.2e m)\n", worst, l);
  EXPECT_LT(worst, 1e-12 * l / 1e-3 + 1e-15);
}

TEST(RealtimeModels, FollowTheLeaderTensionIsTheQuasiSpringFormula)
{
  const double k_q   = 250;
  auto         owner = test_support::held_ftl_suture("xpbd", {{"Quasi-spring constant", std::to_string(k_q)}});
  World       &world = *owner;
  const auto  &s     = world.system();
  ToolPose     right;
  right.position = Vector3d(0.02, 0, 0);

  const double n_links = 20, l = world.suture()->link_length();
  const auto   length  = [&] {
    double L = 0;
    for (auto i = s.suture.begin; i + 1 < s.suture.end; ++i)
      L += (s.nodes.x.col(i + 1) - s.nodes.x.col(i)).norm();
    return L;
  };

  // a straight pull along the axis by 5 %: the two passes are collinear and their
  // distance-weighted average spreads the stretch evenly, every link D/n
  {
    ToolPose pose = right;
    pose.position += Vector3d(0.05 * 0.02, 0, 0);
    const auto  &forces = world.step({ToolPose(), pose});
    const double D = (s.nodes.x.col(s.suture.end - 1) - s.nodes.x.col(s.suture.begin)).norm();
    for (auto i = s.suture.begin; i + 1 < s.suture.end; ++i)
      EXPECT_NEAR((s.nodes.x.col(i + 1) - s.nodes.x.col(i)).norm(), D / n_links, 1e-15);
    const double T = k_q * (D - n_links * l); // seed 002 §3, with the links all D/n
    EXPECT_NEAR(forces[0].force.norm(), T, 1e-9 * T);
    EXPECT_NEAR(forces[0].force[0], T, 1e-9 * T); // along +x, toward the next node
    EXPECT_NEAR(forces[1].force[0], -T, 1e-9 * T);
  }

  // then off the axis, slack and taut: the tension is always the formula of the links
  // the averaging produced (on a curved slack suture those come out longer than l, so
  // the seed's quasi-spring reports some tension even with the ends closer than its
  // length)
  unsigned taut = 0;
  for (const double stretch : {-0.1, 0.0, 0.01, 0.05})
    {
      ToolPose pose = right;
      pose.position += Vector3d(stretch * 0.02, 0.002, 0);
      const auto  &forces = world.step({ToolPose(), pose});
      const double T      = std::max(0.0, k_q * (length() - n_links * l));
      EXPECT_NEAR(forces[0].force.norm(), T, 1e-12 + 1e-9 * T) << "stretch " << stretch;
      EXPECT_NEAR(forces[1].force.norm(), T, 1e-12 + 1e-9 * T);
      if (T > 0)
        {
          EXPECT_GT(forces[0].force.dot(s.nodes.x.col(s.suture.begin + 1) - s.nodes.x.col(s.suture.begin)), 0);
          ++taut;
        }
      std::printf("[ FTL ] stretch %+.2f: tension %.6e N (formula %.6e N)\n", stretch,
                  forces[0].force.norm(), T);
    }
  std::printf("[ FTL ] taut at %u of the 4 stretches\n", taut);
  EXPECT_EQ(taut, 4u); // measured: the averaged links are longer than l in every pose
}

TEST(RealtimeModels, FollowTheLeaderCutInTwoPullsNeitherEndAndEachHalfFollowsItsOwn)
{
  // a thread held at both ends and drawn 5 % taut pulls both tools; cut in the middle
  // (a thread cut after a knot) it pulls neither, each half follows its own end with
  // links of length l, and the cut link parts
  const double k_q   = 250;
  auto         owner = test_support::held_ftl_suture("xpbd", {{"Quasi-spring constant", std::to_string(k_q)}});
  World       &world = *owner;
  const auto  &s     = world.system();
  const double l     = world.suture()->link_length();
  ToolPose     right;
  right.position = Vector3d(0.02 * 1.05, 0, 0);
  const double taut = world.step({ToolPose(), right})[0].force.norm();
  EXPECT_NEAR(taut, k_q * 0.05 * 0.02, 1e-9 * taut);
  world.cut_suture(10);
  ToolPose left;
  left.position = Vector3d(-0.002, 0.003, 0);
  const auto &forces = world.step({left, right});
  EXPECT_EQ(forces[0].force.norm(), 0);
  EXPECT_EQ(forces[1].force.norm(), 0);
  const auto link = [&](const std::uint32_t i) {
    return (s.nodes.x.col(s.suture.begin + i + 1) - s.nodes.x.col(s.suture.begin + i)).norm();
  };
  for (std::uint32_t i = 0; i < 20; ++i)
    {
      if (i == 10)
        continue;
      EXPECT_NEAR(link(i), l, 1e-12 * l) << "link " << i;
    }
  std::printf("[ FTL ] cut link 10 after the left end moved: %.4f l (the others l)\n", link(10) / l);
  EXPECT_GT(link(10), 1.1 * l);
  EXPECT_THROW(world.cut_suture(20), std::invalid_argument); // 20 links: 0-19
}

namespace
{
  /// Static equilibrium of a discrete elastic chain hanging between two supports: the
  /// segment forces T_i = T_0 − Σ_{j≤i} m_j g, each segment of length L0 + |T_i|/k along
  /// T_i; T_0 found by Newton (finite-difference Jacobian) so that the chain ends at the
  /// second support. Independent of the realtime code: the reference of the catenary test.
  std::vector<Vector3d>
  discrete_catenary(const Vector3d &a, const Vector3d &b, const std::vector<double> &mass,
                    const double L0, const double k, const Vector3d &g)
  {
    const std::size_t n     = mass.size() - 1; // segments
    const auto        shoot = [&](const Eigen::Vector2d &T0, std::vector<Vector3d> *nodes) {
      Vector3d x = a, T(T0[0], 0, T0[1]);
      if (nodes)
        nodes->assign(1, a);
      for (std::size_t i = 0; i < n; ++i)
        {
          if (i > 0)
            T -= mass[i] * g;
          x += (L0 + T.norm() / k) * T.normalized();
          if (nodes)
            nodes->push_back(x);
        }
      return Eigen::Vector2d(x[0] - b[0], x[2] - b[2]);
    };
    double          weight = 0;
    for (std::size_t i = 1; i < n; ++i)
      weight += mass[i] * g.norm();
    Eigen::Vector2d T0(weight, -weight / 2); // a guess: pulling right and down
    for (int it = 0; it < 100; ++it)
      {
        const Eigen::Vector2d r = shoot(T0, nullptr);
        if (r.norm() < 1e-15)
          break;
        Eigen::Matrix2d J;
        for (int c = 0; c < 2; ++c)
          {
            Eigen::Vector2d d = Eigen::Vector2d::Zero();
            d[c]              = 1e-7 * weight;
            J.col(c)          = (shoot(T0 + d, nullptr) - shoot(T0 - d, nullptr)) / (2 * d[c]);
          }
        T0 -= J.lu().solve(r);
      }
    std::vector<Vector3d> nodes;
    shoot(T0, &nodes);
    return nodes;
  }

  /// A heavy chain of 20 links (k = 100 N/m, about 1 g per node) held at both ends
  /// 0.85 L apart under gravity, run by @p integrator until @p time.
  double
  catenary_error(const std::string &integrator, const std::map<std::string, std::string> &values,
                 const double time, const unsigned substeps)
  {
    const double L = 0.1, EA = 100 * L / 20;
    WorldSetup   w;
    w.suture          = test_support::make_model<SutureModel::Registry>("mass-spring");
    w.suture_geometry = test_support::straight_suture(20, L, Vector3d::Zero(), Vector3d::UnitX(), EA,
                                                      0, 0.005, 2500);
    // start from a sagging polyline so that both integrators begin away from the answer
    for (std::size_t i = 0; i <= 20; ++i)
      w.suture_geometry.points[i] = Vector3d(0.85 * L * i / 20, 0, -0.02 * std::sin(M_PI * i / 20));
    w.integrator = test_support::make_model<Integrator::Registry>(integrator, values);
    w.gravity    = Vector3d(0, 0, -9.81);
    w.substeps   = substeps;
    World       world(std::move(w));
    const auto &s = world.system();
    world.add_tool("left", {s.suture.begin}, ToolPose());
    ToolPose right;
    right.position = s.nodes.x.col(s.suture.end - 1);
    world.add_tool("right", {s.suture.end - 1}, right);
    world.initialize();
    EXPECT_TRUE(world.warning().empty()) << world.warning();

    std::vector<double> mass(s.nodes.mass.data() + s.suture.begin, s.nodes.mass.data() + s.suture.end);
    // the chain's own rest length per link (the springs were built from the polyline)
    const auto *springs = dynamic_cast<const SpringSet *>(s.interactions.front().get());
    const auto  exact   = discrete_catenary(Vector3d::Zero(), right.position, mass,
                                         springs->rest_lengths().front(), springs->stiffnesses().front(),
                                         Vector3d(0, 0, -9.81));
    while (world.time() < time - 1e-12)
      world.step({ToolPose(), right});
    double error = 0, sag = 0;
    for (std::size_t i = 0; i < exact.size(); ++i)
      {
        error = std::max(error, (s.nodes.x.col(s.suture.begin + i) - exact[i]).norm());
        sag   = std::max(sag, -exact[i][2]);
      }
    return error / sag;
  }
} // namespace

TEST(RealtimeModels, QuasiStaticAndXpbdChainsSettleOnTheDiscreteCatenary)
{
  // quasi-static V = F/B is a gradient flow: it reaches the equilibrium itself
  const double quasi_static = catenary_error("quasi-static", {{"Suture damping", "0.5"}}, 10, 1);
  std::printf("[ catenary ] quasi-static, 10 s: max node error / sag %.2e\n", quasi_static);
  EXPECT_LT(quasi_static, 1e-10);

  // XPBD's steady state differs from the equilibrium by O(dt^2): each step projects with
  // constraint gradients taken between x and x* = x + dt^2 g, and XPBD drops the residual
  // that would correct for their rotation (Macklin et al. 2016, eq. 11, h ~ 0). The
  // error must fall at second order with dt and not depend on the iteration count.
  std::vector<double> error;
  for (const unsigned substeps : {1u, 2u, 4u, 8u})
    {
      error.push_back(catenary_error("xpbd", {{"Iterations", "50"}, {"Damping rate", "20"}}, 5, substeps));
      std::printf("[ catenary ] XPBD, dt = %.4f ms: max node error / sag %.3e", 1.0 / substeps, error.back());
      if (error.size() > 1)
        std::printf(", order %.2f", std::log2(error[error.size() - 2] / error.back()));
      std::printf("\n");
    }
  // the coarsest pair is pre-asymptotic (1.79); the rate is checked from dt = 0.5 ms on
  for (std::size_t k = 2; k < error.size(); ++k)
    EXPECT_GT(std::log2(error[k - 1] / error[k]), 1.9);
  EXPECT_LT(error.back(), 1e-5);
  const double more_iterations = catenary_error("xpbd", {{"Iterations", "200"}, {"Damping rate", "20"}}, 5, 1);
  EXPECT_NEAR(more_iterations, error.front(), 1e-3 * error.front());
}

TEST(RealtimeModels, XpbdStretchErrorFallsMonotonicallyWithIterations)
{
  // a stiff chain (3-0 suture EA) hanging from one end, 100 steps of 1 ms
  double last = std::numeric_limits<double>::infinity();
  for (const int iterations : {1, 2, 4, 8, 16, 32, 64})
    {
      WorldSetup w;
      w.suture          = test_support::make_model<SutureModel::Registry>("xpbd-rod");
      w.suture_geometry = test_support::straight_suture(50, 0.05, Vector3d::Zero(), Vector3d::UnitX(),
                                                        119, 3e-9, 1.1e-4, 1100);
      w.integrator =
        test_support::make_model<Integrator::Registry>("xpbd", {{"Iterations", std::to_string(iterations)}});
      w.gravity = Vector3d(0, 0, -9.81);
      World world(std::move(w));
      world.add_tool("grasp", {world.system().suture.begin}, ToolPose());
      world.initialize();
      for (int step = 0; step < 100; ++step)
        world.step({ToolPose()});
      double stretch = 0;
      for (const auto &i : world.system().interactions)
        if (const auto *springs = dynamic_cast<const SpringSet *>(i.get()))
          stretch = springs->max_violation(world.system().nodes.x);
      std::printf("[ XPBD ] %2d iterations: max stretch %.3e\n", iterations, stretch);
      EXPECT_LT(stretch, last) << iterations << " iterations";
      last = stretch;
    }
}

TEST(RealtimeModels, XpbdSutureIterationsResolveTheSutureAndLeaveTheTissueAlone)
{
  // a soft block under gravity and, apart from it, a stiff chain hanging from a grasper:
  // the extra sweeps over the suture's constraints must cut its stretch error and must
  // not change the tissue at all (they never visit its constraints)
  const auto run = [](const int suture_iterations, Matrix3Xd &tissue, double &stretch) {
    const auto  mesh = test_support::box_mesh(0.02, 0.02, 0.01, 4, 4, 2);
    WorldSetup  w;
    w.mesh     = &mesh;
    w.material = {6e3, 0.45, 1060, {}};
    w.tissue   = test_support::make_model<TissueModel::Registry>("volume");
    w.suture   = test_support::make_model<SutureModel::Registry>("xpbd-rod");
    w.suture_geometry =
      test_support::straight_suture(50, 0.05, Vector3d(0, 0, 0.05), Vector3d::UnitX(), 119, 3e-9, 1.1e-4, 1100);
    w.contact    = false;
    w.integrator = test_support::make_model<Integrator::Registry>(
      "xpbd", {{"Iterations", "1"}, {"Suture iterations", std::to_string(suture_iterations)}});
    w.gravity = Vector3d(0, 0, -9.81);
    World world(std::move(w));
    const auto bottom = mesh::vertices_with_tag(mesh::extract_boundary(mesh), 1);
    world.fix_vertices(bottom);
    ToolPose grasp;
    grasp.position = Vector3d(0, 0, 0.05);
    world.add_tool("grasp", {world.system().suture.begin}, grasp);
    world.initialize();
    for (int step = 0; step < 100; ++step)
      world.step({grasp});
    const auto &sys = world.system();
    tissue          = sys.nodes.x.leftCols(sys.tissue.end);
    stretch         = 0;
    for (auto i = sys.first_suture_interaction; i < sys.interactions.size(); ++i)
      if (const auto *springs = dynamic_cast<const SpringSet *>(sys.interactions[i].get()))
        stretch = std::max(stretch, springs->max_violation(sys.nodes.x));
  };
  Matrix3Xd tissue0, tissue8;
  double    stretch0 = 0, stretch8 = 0;
  run(0, tissue0, stretch0);
  run(8, tissue8, stretch8);
  std::printf("[ XPBD ] 1 iteration: suture stretch %.3e; + 8 suture iterations: %.3e\n", stretch0, stretch8);
  EXPECT_LT(stretch8, 0.25 * stretch0);
  EXPECT_EQ(tissue0, tissue8);
}

TEST(RealtimeModels, FollowTheLeaderSoftConstraintSplitsTheQuasiSpringTension)
{
  // seed 002 §3: a soft constraint between nodes, here at s = 7.5 mm of a 20 mm suture
  // held at both ends and pulled 2 mm aside there (a pierced tissue point). The segment
  // holding s is laid through the point, and each side's tension is k_q times the
  // thread's length from constraint to constraint minus the material length between them
  const double k_q   = 1000;
  auto         owner = test_support::held_ftl_suture("quasi-static", {{"Quasi-spring constant", std::to_string(k_q)}});
  World       &world = *owner;
  const auto  &s     = world.system();
  ToolPose     right;
  right.position = Vector3d(0.02, 0, 0);
  ASSERT_TRUE(world.suture()->takes_soft_constraints());

  const double                s_c = 0.0075, l = world.suture()->link_length();
  const Vector3d              p(0.0075, 0.002, 0);
  auto                       *model = const_cast<SutureModel *>(world.suture());
  model->set_soft_constraints({{s_c, p}});
  const auto &forces = world.step({ToolPose(), right});
  const auto  x      = [&](const int i) { return Vector3d(s.nodes.x.col(s.suture.begin + i)); };

  // the constrained segment (nodes 7, 8) passes through p at its fraction 0.5
  EXPECT_NEAR((0.5 * (x(7) + x(8)) - p).norm(), 0, 1e-12);
  EXPECT_NEAR((x(8) - x(7)).norm(), l, 1e-12);

  std::vector<SoftConstraintLoad> loads;
  model->soft_constraint_loads(s, s.nodes.x, {{s_c, p}}, loads);
  ASSERT_EQ(loads.size(), 1u);
  double before = (p - x(7)).norm(), after = (x(8) - p).norm();
  for (int i = 0; i < 7; ++i)
    before += (x(i + 1) - x(i)).norm();
  for (int i = 8; i < 20; ++i)
    after += (x(i + 1) - x(i)).norm();
  const double T_before = k_q * (before - s_c), T_after = k_q * (after - (0.02 - s_c));
  std::printf("[ FTL soft constraint ] tensions %.4f N (towards the first node), %.4f N (towards the last)\n",
              loads[0].before, loads[0].after);
  EXPECT_GT(T_before, 0);
  EXPECT_NEAR(loads[0].before, T_before, 1e-9 * T_before);
  EXPECT_NEAR(loads[0].after, T_after, 1e-9 * T_after);
  // the thread pulls the point back towards its straight line, along each side
  const Vector3d pull = loads[0].before * loads[0].to_before + loads[0].after * loads[0].to_after;
  EXPECT_LT(pull[1], -0.5 * (T_before + T_after) * 0.002 / 0.0125);
  // towards the first node: back along −x, tilted towards the line (not straight back)
  EXPECT_GT(loads[0].to_before[0], -0.9);
  EXPECT_LT(loads[0].to_before[0], 0);
  EXPECT_GT(loads[0].to_after[0], 0);
  // the hands feel the tension of their own section
  EXPECT_NEAR(forces[0].force.norm(), T_before, 1e-9 * T_before);
  EXPECT_NEAR(forces[1].force.norm(), T_after, 1e-9 * T_after);
}

TEST(RealtimeModels, FollowTheLeaderPerLinkTensionIsTheStrainOfLinksInSeries)
{
  // "Tension law = per link": a section of m/l links of stiffness k_q in series carries
  // T = k_q l (L − m)/m, so equal strains give equal tensions whatever the lengths (seed
  // 002's per-section law gives equal tensions for equal elongations instead, which is
  // why its short stitches stretch, seed 002 sec. 6). The slip rule's rates −∂T/∂m are
  // checked against central differences of the tensions in the constraint's coordinate.
  for (const std::string law : {"per link", "per section"})
    {
      const double k_q   = 1000;
      auto         owner = test_support::held_ftl_suture(
        "quasi-static", {{"Quasi-spring constant", std::to_string(k_q)}, {"Tension law", law}});
      World       &world = *owner;
      const auto  &s     = world.system();
      ToolPose     right;
      right.position = Vector3d(0.02, 0, 0);
      const double   s_c = 0.0075, l = world.suture()->link_length(), total = 0.02;
      const Vector3d p(0.0075, 0.002, 0);
      auto          *model = const_cast<SutureModel *>(world.suture());
      model->set_soft_constraints({{s_c, p}});
      world.step({ToolPose(), right});
      const auto x = [&](const int i) { return Vector3d(s.nodes.x.col(s.suture.begin + i)); };

      std::vector<SoftConstraintLoad> loads;
      model->soft_constraint_loads(s, s.nodes.x, {{s_c, p}}, loads);
      double before = (p - x(7)).norm(), after = (x(8) - p).norm();
      for (int i = 0; i < 7; ++i)
        before += (x(i + 1) - x(i)).norm();
      for (int i = 8; i < 20; ++i)
        after += (x(i + 1) - x(i)).norm();
      const double m_b = s_c, m_a = total - s_c;
      const double T_b = law == "per link" ? k_q * l * (before - m_b) / m_b : k_q * (before - m_b);
      const double T_a = law == "per link" ? k_q * l * (after - m_a) / m_a : k_q * (after - m_a);
      ASSERT_GT(T_b, 0);
      EXPECT_NEAR(loads[0].before, T_b, 1e-9 * T_b) << law;
      EXPECT_NEAR(loads[0].after, T_a, 1e-9 * T_a) << law;

      // rates: the same node positions, the constraint moved by ±h along the thread
      const double                    h = 1e-7;
      std::vector<SoftConstraintLoad> plus, minus;
      model->soft_constraint_loads(s, s.nodes.x, {{s_c + h, p}}, plus);
      model->soft_constraint_loads(s, s.nodes.x, {{s_c - h, p}}, minus);
      const double dTb = (plus[0].before - minus[0].before) / (2 * h);
      const double dTa = (plus[0].after - minus[0].after) / (2 * h);
      std::printf("[ FTL %s ] T = %.5f / %.5f N; -dT/dm = %.6g / %.6g N/m, differences %.6g / %.6g\n",
                  law.c_str(), loads[0].before, loads[0].after, loads[0].stiffness_before,
                  loads[0].stiffness_after, -dTb, dTa);
      // sliding the point towards the last node adds material to the section before
      EXPECT_NEAR(loads[0].stiffness_before, -dTb, 1e-5 * loads[0].stiffness_before) << law;
      EXPECT_NEAR(loads[0].stiffness_after, dTa, 1e-5 * loads[0].stiffness_after) << law;
      if (law == "per section")
        EXPECT_EQ(loads[0].stiffness_before, k_q);
      else // the shorter section is the stiffer: k_q l L/m² each
        EXPECT_GT(loads[0].stiffness_before, loads[0].stiffness_after);
    }
}

TEST(RealtimeModels, FollowTheLeaderTurnLengthMeasuresTheWrapOverOneLengthWhateverTheLinks)
{
  // A pierce point's friction grows with the thread's wrap there, N = N₀ + |T₋ê₋ + T₊ê₊|.
  // Here the 20 mm thread lies on a circle of radius R = 4 mm, the point at the middle
  // of its middle link (or a fifth of the way along it). Seed 002's directions point to
  // the first node beyond that link, 1 to 2 links away, so the wrap |ê₋ + ê₊| shrinks
  // with the link; with a turn length
  // L_t they point to the thread's point L_t along it, whose chord leaves the tangent
  // at L_t/(2R) on either side, so |ê₋ + ê₊| = 2 sin(L_t/(2R)) for any link short of L_t.
  const double R = 0.004, length = 0.02, turn = 0.001;
  const auto   wrap = [&](const unsigned n, const double turn_length, const double f = 0.5) {
    auto owner = test_support::held_ftl_suture("quasi-static", {{"Turn length", std::to_string(turn_length)}}, n);
    World      &world = *owner;
    const auto &s     = world.system();
    Matrix3Xd    x = s.nodes.x;
    const double l = length / n;
    for (unsigned i = 0; i <= n; ++i)
      {
        const double angle = (i * l - 0.5 * length) / R;
        x.col(s.suture.begin + i) = Vector3d(0.5 * length + R * std::sin(angle), R * (std::cos(angle) - 1), 0);
      }
    const unsigned                  k = n / 2;
    const Vector3d p = (1 - f) * x.col(s.suture.begin + k) + f * x.col(s.suture.begin + k + 1);
    std::vector<SoftConstraintLoad> loads;
    world.suture()->soft_constraint_loads(s, x, {{(k + f) * l, p}}, loads);
    // the wrap of the chords to the two held ends, for a turn length beyond them
    const Vector3d to_first = x.col(s.suture.begin) - p, to_last = x.col(s.suture.end - 1) - p;
    return std::make_pair((loads[0].to_before + loads[0].to_after).norm(),
                          (to_first.normalized() + to_last.normalized()).norm());
  };
  const double expected = 2 * std::sin(turn / (2 * R));
  for (const unsigned n : {40u, 80u, 160u, 320u})
    {
      const double seed = wrap(n, 0).first, measured = wrap(n, turn).first;
      std::printf("[ FTL turn ] %3u links (l = %.4f mm): wrap %.5f with L_t = 1 mm (2 sin(L_t/2R) = %.5f, "
                  "%.1e relative), %.5f with seed 002's\n",
                  n, 1e3 * length / n, measured, expected, std::abs(measured / expected - 1), seed);
      EXPECT_NEAR(measured, expected, 2e-3 * expected) << n;
      // off the link's middle the two sides walk different node sequences
      EXPECT_NEAR(wrap(n, turn, 0.2).first, expected, 2e-3 * expected) << n;
    }
  // seed 002's wrap halves with the link
  EXPECT_LT(wrap(320, 0).first, 0.15 * wrap(40, 0).first);
  // a turn length beyond the section: the chords to the held ends
  const auto beyond = wrap(40, 0.5);
  EXPECT_NEAR(beyond.first, beyond.second, 1e-12);
  EXPECT_GT(beyond.first, 1.8); // about 2 sin(10 mm/2R)
}

TEST(RealtimeModels, FollowTheLeaderKinkedHolesLetAPointPassANodeWithoutAJump)
{
  // A 20 mm thread of 1 mm links held at both ends and bent at one pierced point (a V), or
  // at two points 0.4 mm apart in material and 0.5 mm in space (a thread drawn across a
  // wound between its faces). The points slide 20 µm along the thread, across node 8.
  // Seed 002's placement lays the link holding a point straight through it along the
  // chord of its neighbours, so when the point passes into the next link a node jumps and
  // the tension beyond the point jumps with it: the slip reverses and the point chatters
  // about the node (the realtime stitch's pierce loads did, every few ms). Bent at the
  // points ('kink'), the nodes move by about the slide and the tension by its own change.
  const auto slide = [](const std::string &placement, const std::vector<SoftConstraint> &points,
                        const Vector3d &end) {
    auto owner = test_support::held_ftl_suture(
      "quasi-static", {{"Quasi-spring constant", "1000"}, {"Hole placement", placement}});
    World      &world = *owner;
    const auto &s     = world.system();
    ToolPose    right;
    right.position = end;
    auto *model    = const_cast<SutureModel *>(world.suture());
    const auto shifted = [&](const double shift) {
      std::vector<SoftConstraint> moved = points;
      for (auto &c : moved)
        c.s += shift;
      return moved;
    };
    const auto nodes = [&] { return Matrix3Xd(s.nodes.x.middleCols(s.suture.begin, s.suture.size())); };
    // settled just short of the node, then one step just past it
    model->set_soft_constraints(shifted(-1e-5));
    for (int step = 0; step < 400; ++step)
      world.step({ToolPose(), right});
    // the first point's tension on the far side: across to the second point, or to the end
    const auto tension = [&](const std::vector<SoftConstraint> &c) {
      std::vector<SoftConstraintLoad> loads;
      model->soft_constraint_loads(s, s.nodes.x, c, loads);
      return loads[0].after;
    };
    const Matrix3Xd before = nodes();
    const double    T      = tension(shifted(-1e-5));
    model->set_soft_constraints(shifted(1e-5));
    world.step({ToolPose(), right});
    // less its own change: k_q Δs as the last leg (per-section law) loses 20 µm of thread;
    // nothing when the section between two points slides whole
    const double own = points.size() == 1 ? 1000 * 2e-5 : 0;
    return std::make_pair((nodes() - before).colwise().norm().maxCoeff(), std::abs(tension(shifted(1e-5)) - T - own));
  };
  // legs as long as their material (a V that FTL lays straight, nothing stretched for
  // its two-sided averaging to share out), the first at 20° up, the last at 13° down
  const Vector3d up(std::cos(0.35), std::sin(0.35), 0), down(std::cos(0.23), -std::sin(0.23), 0);
  const Vector3d p = 0.008 * up, p2 = p + Vector3d(0.0005, 0, 0); // 0.4 mm of thread stretched to 0.5
  const std::vector<SoftConstraint> one = {{0.008, p}}, two = {{0.008, p}, {0.0084, p2}};
  const Vector3d                    end_one = p + 0.012 * down, end_two = p2 + 0.0116 * down;
  for (const auto &[name, points, end] :
       {std::make_tuple("one point", one, end_one), std::make_tuple("two points", two, end_two)})
    {
      const auto segment = slide("segment", points, end), kink = slide("kink", points, end);
      std::printf("[ FTL holes ] %s across a node: largest node jump %.4f mm, tension jump %.4f N (segment); "
                  "%.4f mm, %.4f N (kink)\n",
                  name, 1e3 * segment.first, segment.second, 1e3 * kink.first, kink.second);
      EXPECT_LT(kink.first, 4e-5) << name; // twice the slide
      EXPECT_LT(kink.second, 0.1 * segment.second) << name;
    }
}

TEST(RealtimeModels, VolumeStiffnessScalesMultiplyTheSpringAndBulkEnergies)
{
  // the calibration's parameters (issue 28): Spring stiffness scale s_k multiplies every
  // Van Gelder spring and Volume stiffness scale s_V every bulk constraint, so at one
  // deformed configuration each family's energy is s times the unscaled one
  const auto mesh   = test_support::box_mesh(0.02, 0.02, 0.01, 3, 3, 2);
  const auto energy = [&](const std::string &s_k, const std::string &s_V, const std::string &family) {
    WorldSetup w;
    w.mesh     = &mesh;
    w.material = {6e3, 0.45, 1060, {}};
    w.tissue   = test_support::make_model<TissueModel::Registry>(
      "volume", {{"Spring stiffness scale", s_k}, {"Volume stiffness scale", s_V}});
    w.contact    = false;
    w.integrator = test_support::make_model<Integrator::Registry>("xpbd");
    World world(std::move(w));
    world.initialize();
    const auto &sys = world.system();
    Matrix3Xd   x   = sys.nodes.x;
    Eigen::Matrix3d F;
    F << 1.05, 0.02, 0, 0, 0.97, 0.01, 0.03, 0, 1.02; // a general homogeneous deformation
    x = F * x;
    for (const auto &i : sys.interactions)
      if (i->name() == family)
        return i->energy(x);
    ADD_FAILURE() << "no interaction " << family;
    return 0.0;
  };
  const double springs = energy("1", "1", "tissue springs"), volumes = energy("1", "1", "volume constraints");
  ASSERT_GT(springs, 0);
  ASSERT_GT(volumes, 0);
  EXPECT_NEAR(energy("2.5", "0.4", "tissue springs"), 2.5 * springs, 1e-12 * springs);
  EXPECT_NEAR(energy("2.5", "0.4", "volume constraints"), 0.4 * volumes, 1e-12 * volumes);
}

namespace
{
  /// A block (20 × 20 × 10 mm, n × n × n/2 cubes of six tetrahedra, the bottom fixed)
  /// sagging under its weight with quasi-static steps of damping law @p law (B in N s/m
  /// per node, or the rate β in 1/s): how far its top centre has sagged after 40 ms, as a
  /// fraction of where it comes to rest (after 2 s).
  double
  sag_fraction(const unsigned n, const std::string &law, const std::string &value)
  {
    const auto mesh = test_support::box_mesh(0.02, 0.02, 0.01, n, n, n / 2);
    WorldSetup w;
    w.mesh     = &mesh;
    w.material = {1e4, 0.3, 1000, {}};
    w.tissue   = test_support::make_model<TissueModel::Registry>("volume");
    w.integrator =
      test_support::make_model<Integrator::Registry>("quasi-static", {{"Damping", law},
                                                                      {law == "per node" ? "Tissue damping" : "Tissue damping rate", value}});
    w.gravity = Vector3d(0, 0, -9.81);
    w.rate    = 4000;
    World world(std::move(w));
    world.fix_vertices(mesh::vertices_with_tag(mesh::extract_boundary(mesh), 1));
    world.initialize();
    EXPECT_TRUE(world.warning().empty()) << world.warning();
    std::uint32_t top = 0;
    for (Eigen::Index v = 0; v < mesh.vertices.cols(); ++v)
      if ((mesh.vertices.col(v) - Vector3d(0.01, 0.01, 0.01)).norm() < 1e-9)
        top = world.tissue()->node(v);
    const auto sag = [&] { return world.system().nodes.reference(2, top) - world.system().nodes.x(2, top); };
    while (world.time() < 0.04 - 1e-12)
      world.step({});
    const double early = sag();
    while (world.time() < 2 - 1e-12)
      world.step({});
    return early / sag();
  }
} // namespace

TEST(RealtimeModels, QuasiStaticDampingPerUnitMassRelaxesAlikeOnEveryMesh)
{
  // B = βM is the semi-discretisation of the drag β ρ u̇ = ∇·σ + ρ g, so the sag's
  // time course, as a fraction of its own rest value, has a mesh limit; one B per node
  // puts 8 times the damping per unit mass into each halving of the cubes, and the
  // block relaxes that much slower. β = 1e4 1/s: the slowest mode's rate
  // λ₁ ≈ (π/2)² E/(ρ β H²) = 25 1/s, so 40 ms is about one time constant. B = 0.53 N s/m
  // per node is β times the mean node mass on the coarsest mesh (4 × 4 × 2: 4 g on 75 nodes).
  std::vector<double> mass, node;
  for (const unsigned n : {4u, 8u, 16u})
    {
      mass.push_back(sag_fraction(n, "per unit mass", "1e4"));
      node.push_back(sag_fraction(n, "per node", "0.53"));
      std::printf("[ damping ] %2u cubes across: sag at 40 ms / at rest: per unit mass %.4f, per node %.4f\n", n,
                  mass.back(), node.back());
    }
  EXPECT_LT(std::abs(mass[2] - mass[1]), 0.5 * std::abs(mass[1] - mass[0]));
  EXPECT_LT(std::abs(mass[2] - mass[1]), 0.02 * mass[2]);
  EXPECT_GT(std::abs(node[2] - node[1]), 0.2 * node[1]);
}
