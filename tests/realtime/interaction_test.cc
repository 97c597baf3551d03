// Forces of every realtime interaction against central differences of its energy, and
// the spring stiffness rules against the closed forms they are derived from.
#include <suturesim/realtime/angle_springs.h>
#include <suturesim/realtime/curvature_springs.h>
#include <suturesim/realtime/home_springs.h>
#include <suturesim/realtime/neo_hookean_tetrahedra.h>
#include <suturesim/realtime/nodal_volumes.h>
#include <suturesim/realtime/node_access.h>
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/volume_constraints.h>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "realtime/test_meshes.h"
#include "realtime/test_worlds.h"

using namespace suturesim;
using namespace suturesim::realtime;

namespace
{
  /// max |f − (−∂E/∂x)| / max |f| at @p x, by central differences of @p energy with the
  /// step h = 1e-6 max |x|.
  template <typename Energy>
  double
  gradient_error(const Matrix3Xd &f, const Matrix3Xd &x, const Energy &energy)
  {
    const double scale = x.cwiseAbs().maxCoeff();
    const double h     = 1e-6 * scale;
    double       error = 0;
    Matrix3Xd    y     = x;
    for (Eigen::Index i = 0; i < x.size(); ++i)
      {
        y.data()[i]     = x.data()[i] + h;
        const double ep = energy(y);
        y.data()[i]     = x.data()[i] - h;
        const double em = energy(y);
        y.data()[i]     = x.data()[i];
        error           = std::max(error, std::abs(f.data()[i] + (ep - em) / (2 * h)));
      }
    return error / f.cwiseAbs().maxCoeff();
  }

  double
  force_error(const Interaction &interaction, const Matrix3Xd &x)
  {
    Matrix3Xd f = Matrix3Xd::Zero(3, x.cols());
    interaction.add_forces(x, f);
    return gradient_error(f, x, [&](const Matrix3Xd &y) { return interaction.energy(y); });
  }

  /// The same for a contact set at the state of its last detect(): what detection fixed
  /// (pairs, normals, weights) is held in E (system.h). Throws when it has no energy.
  double
  force_error(const ContactSet &contacts, const Matrix3Xd &x)
  {
    Matrix3Xd f = Matrix3Xd::Zero(3, x.cols());
    contacts.add_forces(x, f);
    return gradient_error(f, x, [&](const Matrix3Xd &y) { return contacts.energy(y).value(); });
  }

  Matrix3Xd
  perturbed(const Matrix3Xd &x, const double amount, const unsigned seed)
  {
    std::mt19937                           random(seed);
    std::uniform_real_distribution<double> u(-1, 1);
    Matrix3Xd                              y = x;
    for (Eigen::Index i = 0; i < y.size(); ++i)
      y.data()[i] += amount * u(random);
    return y;
  }
} // namespace

TEST(RealtimeInteractions, ForcesAreMinusTheEnergyGradient)
{
  const auto mesh = test_support::box_mesh(0.02, 0.01, 0.01, 2, 1, 1);
  std::vector<std::uint32_t> node(mesh.vertices.cols());
  for (std::uint32_t v = 0; v < node.size(); ++v)
    node[v] = v;
  const Matrix3Xd x = perturbed(mesh.vertices, 2e-3, 1);

  SpringSet springs("springs");
  add_volume_springs(springs, mesh, node, 1e4);
  EXPECT_LT(force_error(springs, x), 1e-6);

  VolumeConstraints volumes;
  volumes.add_mesh(mesh, node, 5e4);
  EXPECT_LT(force_error(volumes, x), 1e-6);

  NeoHookeanTetrahedra elements;
  elements.add_mesh(mesh, node, std::vector<double>(mesh.tetrahedra.size(), 2e4),
                    std::vector<double>(mesh.tetrahedra.size(), 9e4));
  EXPECT_LT(force_error(elements, x), 1e-6);

  NodalVolumes nodal;
  nodal.add_mesh(mesh, node, std::vector<double>(mesh.tetrahedra.size(), 9e4));
  EXPECT_LT(force_error(nodal, x), 1e-6);

  HomeSprings home;
  for (std::uint32_t v = 0; v < node.size(); v += 2)
    home.add(v, mesh.vertices.col(v), 10.0 + v);
  EXPECT_LT(force_error(home, x), 1e-6);

  AngleSprings angles;
  angles.add(4, 1, 7, mesh.vertices, 0.3);
  angles.add(4, 3, 5, mesh.vertices, 0.2);
  angles.add(10, 7, 11, mesh.vertices, 0.1);
  EXPECT_LT(force_error(angles, x), 1e-6);

  CurvatureSprings curvature;
  for (std::uint32_t v = 1; v + 1 < node.size(); ++v)
    curvature.add(v - 1, v, v + 1, 2.0);
  EXPECT_LT(force_error(curvature, x), 1e-6);
}

// The contact sets with a potential, at the state of a detection (their penalty laws,
// the forces the force-based integrators apply; XPBD's constraint forces are multipliers,
// not gradients): suture–tissue contact ½ k min(g, 0)² and seed 000's repelling force
// (k_c/k_o) exp(k_o (2d − o)). Without a potential, and so not checked here: seed 002's
// transient constraints (position corrections that hold nodes for a step; tested in
// self_collision_test.cc) and the FTL push-out of SurfaceContact::after_step (the same).
TEST(RealtimeInteractions, ContactForcesAreMinusTheEnergyGradient)
{
  std::mt19937                           random(3);
  std::uniform_real_distribution<double> u(-1, 1);
  {
    // a suture over the top of a block, every other node pressed 0.2–0.8 r into it, the
    // others within the skin (1.09–1.15 r above, listed within 1.25 r); the
    // tissue's nodes moved by up to 5 µm
    const double H = 0.01, r = 1e-4;
    const auto   mesh = test_support::box_mesh(0.02, 0.02, H, 4, 4, 2);
    WorldSetup   w;
    w.mesh              = &mesh;
    w.material          = {6e3, 0.45, 1060, {}};
    w.tissue            = test_support::make_model<TissueModel::Registry>("volume");
    w.suture            = test_support::make_model<SutureModel::Registry>("mass-spring");
    w.suture_geometry   = test_support::straight_suture(20, 0.016, Vector3d(0.002, 0.0101, H),
                                                        Vector3d::UnitX(), 1, 0, r, 1100);
    w.contact_stiffness = 100;
    w.contact_depth     = 1e-3;
    w.integrator        = test_support::make_model<Integrator::Registry>("quasi-static");
    World      world(std::move(w));
    const auto s = world.system().suture;
    Matrix3Xd  x = world.system().nodes.x;
    for (auto i = world.system().tissue.begin; i < world.system().tissue.end; ++i)
      x.col(i) += 5e-6 * Vector3d(u(random), u(random), u(random));
    for (auto i = s.begin; i < s.end; ++i)
      x(2, i) = H + r * ((i - s.begin) % 2 == 0 ? 0.5 + 0.3 * u(random) : 1.12 + 0.03 * u(random));
    auto &contact = dynamic_cast<SurfaceContact &>(*world.system().contacts.front());
    contact.detect(x);
    std::size_t pressed = 0;
    for (const auto &c : contact.list())
      pressed += contact.gap(c, x) < 0;
    std::printf("[ -grad E ] surface contact: %zu contacts, %zu pressed\n", contact.active(), pressed);
    EXPECT_EQ(pressed, 11u); // the even nodes
    EXPECT_EQ(contact.active(), 21u);
    EXPECT_LT(force_error(contact, x), 1e-6);
  }
  {
    // a suture folded across itself with its strands 0.3 mm apart (between 2r and the
    // cut-off 2d + ln(1000)/k_o = 0.745 mm), every node moved by up to 50 µm
    const double r = 1e-4;
    WorldSetup   w;
    w.suture                    = test_support::make_model<SutureModel::Registry>("mass-spring");
    w.suture_geometry           = test_support::folded_suture(3e-4, 1, 0, r);
    w.integrator                = test_support::make_model<Integrator::Registry>("quasi-static");
    w.self_collision            = "repelling-force";
    w.self_collision_parameters = test_support::parameters_of("repelling-force");
    World      world(std::move(w));
    Matrix3Xd  x = world.system().nodes.x;
    for (Eigen::Index i = 0; i < x.size(); ++i)
      x.data()[i] += 5e-5 * u(random);
    auto &repelling = dynamic_cast<SelfCollision &>(*world.system().contacts.front());
    repelling.detect(x);
    double least = std::numeric_limits<double>::infinity();
    for (const auto &c : repelling.list())
      least = std::min(least, c.distance);
    std::printf("[ -grad E ] repelling force: %zu pairs, least distance %.3e m\n", repelling.active(), least);
    EXPECT_GE(repelling.active(), 2u);
    EXPECT_LT(least, 2 * 2 * r); // into the exponential's steep part, F > k_c
    EXPECT_LT(force_error(repelling, x), 1e-6);
  }
  {
    // seed 002's constraints have none
    WorldSetup w;
    w.suture                    = test_support::make_model<SutureModel::Registry>("mass-spring");
    w.suture_geometry           = test_support::folded_suture(1e-4, 1, 0, 1e-4);
    w.integrator                = test_support::make_model<Integrator::Registry>("quasi-static");
    w.self_collision            = "transient-constraint";
    w.self_collision_parameters = test_support::parameters_of("transient-constraint");
    World world(std::move(w));
    EXPECT_FALSE(world.system().contacts.front()->energy(world.system().nodes.x).has_value());
  }
}

// The needle's penalty forms (force-based integrators) along a pass through a block: the
// tip's touch ½ k_c max(0, (x_m − x_tip)·n)² and each pierce point's tie ½ k⊥ |P⊥(p − c)|²
// across the thread, on the needle and on the suture (whose nodes it moves), at μ = 0 where
// the points slip freely; and the stick ½ k_t (ζ − ζ_a)² along the thread at a μ so high
// they never slip. Slip at μN > 0 (its force follows N = N₀ + |f⊥| and the anchor's
// history) and seed 002's soft constraints (one-sided tension loads) have no potential.
TEST(RealtimeInteractions, NodeAccessForcesAreMinusTheEnergyGradient)
{
  // seed 004's access constraint, E = ½ k C² over two accesses on a bent suture
  Matrix3Xd x(3, 4);
  x << 0.0, 1.1e-3, 1.9e-3, 3.0e-3, 0.0, 0.3e-3, 0.1e-3, -0.2e-3, 0.0, 0.0, -0.2e-3, 0.1e-3;
  NodeAccess access({0, 4}, 1e-3, 50);
  access.add(Vector3d(1.4e-3, -0.1e-3, 0.1e-3), 1);
  access.add(Vector3d(0.4e-3, 0.3e-3, -0.1e-3), 0);
  access.detect(x);
  EXPECT_LT(force_error(access, x), 1e-6);
}

TEST(RealtimeInteractions, NeedleTouchAndPiercePointForcesAreMinusTheEnergyGradient)
{
  const auto                mesh = test_support::box_mesh(0.04, 0.04, 0.01, 10, 10, 3);
  const tools::CurvedNeedle needle(0.008, tools::CurvedNeedle::arc_angle_of("3/8"), 4e-4);
  const auto                pass = test_support::block_pass(needle, 0.004);
  for (const double mu : {0.0, 1e3})
    {
      const auto start = pass.trajectory.pose(0);
      World      world(test_support::needle_block(mesh, needle, start));
      world.fix_vertices(mesh::vertices_with_tag(mesh::extract_boundary(mesh), 1));
      NeedleCouplingParameters p = test_support::needle_block_coupling(mu);
      p.pierce_model         = "node-path";
      world.add_needle(needle, p, start, true);
      world.initialize();
      const auto &coupling = *world.needle();

      std::size_t touches = 0, on_needle = 0, on_suture = 0, first_point = 0;
      double      worst = 0;
      const int   steps = static_cast<int>(pass.t_end * 1000);
      for (int k = 1; k <= steps; ++k)
        {
          world.step({pass.trajectory.pose(k * 1e-3)});
          const auto &points = coupling.pierce_points();
          if (first_point == 0 && !points.empty())
            first_point = k;
          // held fast, the points drag the tissue along: a hundred steps show the stick
          if (mu > 0 && first_point > 0 && k > static_cast<int>(first_point) + 100)
            break;
          const bool touch = coupling.puncture_state().touch() != nullptr && coupling.touch_force() > 0;
          if (k % 10 != 0 || (!touch && points.empty()))
            continue;
          touches += touch;
          for (const auto &q : points)
            (q.on_suture ? on_suture : on_needle) += 1;
          worst = std::max(worst, force_error(coupling, world.system().nodes.x));
        }
      std::printf("[ -grad E ] needle at mu = %g: %zu states with a touch, %zu points on the "
                  "needle, %zu on the suture; largest relative error %.2e\n",
                  mu, touches, on_needle, on_suture, worst);
      EXPECT_LT(worst, 1e-6) << mu;
      EXPECT_GT(touches, 0u) << mu;
      EXPECT_GT(on_needle, 0u) << mu;
      EXPECT_EQ(on_suture > 0, mu == 0) << mu; // held fast, no point reaches the suture
    }
}

TEST(RealtimeInteractions, VanGelderNetworkStoresTheDilatationEnergyOfBulkModulusTwoThirdsE)
{
  // Under x = (1 + e) X every edge stretches by e L: Σ ½ k L² e² = ½ E e² Σ_e Σ_{T∋e} V_T
  // = 3 E e² V, the continuum energy ½ 9K e² V of K = 2E/3 (spring_set.h), on any mesh.
  const auto mesh = test_support::box_mesh(0.03, 0.02, 0.01, 3, 2, 2);
  std::vector<std::uint32_t> node(mesh.vertices.cols());
  for (std::uint32_t v = 0; v < node.size(); ++v)
    node[v] = v;
  const double E = 7e3, e = 1e-3;
  SpringSet    springs("springs");
  add_volume_springs(springs, mesh, node, E);
  double V = 0;
  for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
    V += mesh.volume(t);
  const double expected = 0.5 * 9 * (2 * E / 3) * e * e * V;
  EXPECT_NEAR(springs.energy((1 + e) * mesh.vertices), expected, 1e-12 * expected);

  // with the volume constraints' K − 2E/3 the total is the continuum's K (to O(e³))
  const double      K = 5 * E;
  VolumeConstraints volumes;
  volumes.add_mesh(mesh, node, K - 2 * E / 3);
  const double total = springs.energy((1 + e) * mesh.vertices) + volumes.energy((1 + e) * mesh.vertices);
  EXPECT_NEAR(total, 0.5 * 9 * K * e * e * V, 1e-2 * 0.5 * 9 * K * e * e * V);
}

TEST(RealtimeInteractions, LayeredVanGelderNetworkSumsEachTetrahedronsOwnModulus)
{
  // Per-tetrahedron moduli (Tissue/Region moduli: dermis over hypodermis): each
  // tetrahedron adds E_T V_T / L² to its edges, so under x = (1 + e) X the springs store
  // 3 e² Σ_T E_T V_T (the identity above, tetrahedron by tetrahedron) and, with volume
  // constraints of K_T − 2E_T/3, the continuum's ½ 9 e² Σ_T K_T V_T. A modulus contrast
  // of 2600 (Tran et al. 2007: dermis 2.22 MPa, hypodermis 0.84 kPa shear moduli).
  const auto mesh = test_support::box_mesh(0.03, 0.02, 0.01, 3, 2, 2);
  std::vector<std::uint32_t> node(mesh.vertices.cols());
  for (std::uint32_t v = 0; v < node.size(); ++v)
    node[v] = v;
  const double        e = 1e-3;
  std::vector<double> E(mesh.tetrahedra.size()), bulk(mesh.tetrahedra.size());
  double              EV = 0, KV = 0;
  for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
    {
      double z = 0;
      for (const auto v : mesh.tetrahedra[t])
        z += mesh.vertices(2, v) / 4;
      const bool   upper = z > 0.005;
      const double K     = upper ? 29.6e6 : 36e3;
      E[t]               = upper ? 6.5e6 : 2.5e3;
      bulk[t]            = K - 2 * E[t] / 3;
      EV += E[t] * mesh.volume(t);
      KV += K * mesh.volume(t);
    }
  ASSERT_GT(EV, 0);
  SpringSet springs("springs");
  add_volume_springs(springs, mesh, node, E);
  const Matrix3Xd x = (1 + e) * mesh.vertices;
  EXPECT_NEAR(springs.energy(x), 3 * e * e * EV, 1e-12 * 3 * e * e * EV);
  VolumeConstraints volumes;
  volumes.add_mesh(mesh, node, bulk);
  EXPECT_NEAR(springs.energy(x) + volumes.energy(x), 4.5 * e * e * KV, 1e-2 * 4.5 * e * e * KV);
  // a uniform list is the single-modulus network, spring by spring
  SpringSet uniform("uniform"), listed("listed");
  add_volume_springs(uniform, mesh, node, 7e3);
  add_volume_springs(listed, mesh, node, std::vector<double>(mesh.tetrahedra.size(), 7e3));
  EXPECT_EQ(uniform.energy(x), listed.energy(x));
  EXPECT_THROW(add_volume_springs(listed, mesh, node, std::vector<double>(3, 7e3)), std::invalid_argument);
}

TEST(RealtimeInteractions, MembraneRuleIsExactForEquilateralTrianglesAtPoissonOneThird)
{
  // Plane-stress energy of a constant-strain triangle, ½ t A ε:C:ε with
  // C = E/(1 − ν²) [[1, ν, 0], [ν, 1, 0], [0, 0, (1 − ν)/2]] (engineering shear), against
  // the linearised Delingette springs for small random strains.
  const double E = 3e4, nu = 1.0 / 3, t = 1e-3, L = 2e-3;
  Matrix3Xd    X(3, 3);
  X.col(0) << 0, 0, 0;
  X.col(1) << L, 0, 0;
  X.col(2) << 0.5 * L, std::sqrt(3.0) / 2 * L, 0;
  SpringSet springs("membrane");
  add_membrane_springs(springs, X, {{0, 1, 2}}, {0, 1, 2}, E, nu, t);
  std::mt19937                           random(7);
  std::uniform_real_distribution<double> u(-1e-4, 1e-4);
  for (int trial = 0; trial < 5; ++trial)
    {
      const double    exx = u(random), eyy = u(random), gxy = u(random);
      Eigen::Matrix3d F   = Eigen::Matrix3d::Identity();
      F(0, 0) += exx;
      F(1, 1) += eyy;
      F(0, 1) += 0.5 * gxy;
      F(1, 0) += 0.5 * gxy;
      const double A         = std::sqrt(3.0) / 4 * L * L;
      const double continuum = 0.5 * t * A * E / (1 - nu * nu) *
                               (exx * exx + eyy * eyy + 2 * nu * exx * eyy + 0.5 * (1 - nu) * gxy * gxy);
      EXPECT_NEAR(springs.energy(F * X), continuum, 2e-3 * continuum);
    }
}

TEST(RealtimeInteractions, StrainLimitingBringsEverySpringWithinTheLimit)
{
  Matrix3Xd x(3, 4);
  x << 0, 1, 2.5, 2.6, 0, 0, 0, 0, 0, 0, 0, 0;
  SpringSet springs("chain");
  for (std::uint32_t i = 0; i < 3; ++i)
    springs.add(i, i + 1, 1.0, 1.0);
  VectorXd w = VectorXd::Ones(4);
  w[0]       = 0; // held
  springs.limit_strain(x, w, 0.1, 50);
  EXPECT_LE(springs.max_violation(x), 0.1 + 1e-9);
  EXPECT_EQ(x(0, 0), 0);
}

TEST(RealtimeInteractions, XpbdDistanceProjectionMeetsStiffConstraintsAndSharesByInverseMass)
{
  Matrix3Xd x(3, 2);
  x << 0, 1.5, 0, 0, 0, 0;
  SpringSet springs("one");
  springs.add(0, 1, 1.0, std::numeric_limits<double>::infinity());
  VectorXd w(2);
  w << 1, 3;
  springs.reset_multipliers();
  springs.prepare_projection(1e-3);
  springs.project(x, w, 1e-3);
  EXPECT_NEAR((x.col(1) - x.col(0)).norm(), 1.0, 1e-14);
  // the node of inverse mass 3 moved three times as far
  EXPECT_NEAR(-(x(0, 1) - 1.5) / x(0, 0), 3.0, 1e-12);
}

TEST(RealtimeInteractions, ASpringLeftOutExertsNothingAndProjectsNothingUntilGivenBack)
{
  // SpringSet::set_stiffness(s, 0): the spring stays in place (no topology change) but
  // has no force, no energy and, under XPBD, no correction (its α̃ the largest double, so
  // no ∞·0); given its rigid stiffness back, it is met again.
  Matrix3Xd x(3, 2);
  x << 0, 1.5, 0, 0, 0, 0;
  const Matrix3Xd start = x;
  SpringSet       springs("one");
  springs.add(0, 1, 1.0, std::numeric_limits<double>::infinity());
  springs.set_stiffness(0, 0);
  Matrix3Xd f = Matrix3Xd::Zero(3, 2);
  springs.add_forces(x, f);
  EXPECT_EQ(f.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(springs.energy(x), 0.0);
  VectorXd w(2);
  w << 1, 3;
  springs.reset_multipliers();
  springs.prepare_projection(1e-3);
  for (int sweep = 0; sweep < 10; ++sweep)
    springs.project(x, w, 1e-3);
  ASSERT_TRUE(x.allFinite());
  EXPECT_LT((x - start).cwiseAbs().maxCoeff(), 1e-300);
  springs.set_stiffness(0, std::numeric_limits<double>::infinity());
  springs.reset_multipliers();
  springs.prepare_projection(1e-3);
  springs.project(x, w, 1e-3);
  EXPECT_NEAR((x.col(1) - x.col(0)).norm(), 1.0, 1e-14);
  EXPECT_THROW(springs.set_stiffness(0, -1), std::invalid_argument);
  EXPECT_THROW(springs.set_stiffness(1, 1), std::out_of_range);
}
