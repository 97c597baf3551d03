// Forces of every realtime interaction against central differences of its energy, and
// the spring stiffness rules against the closed forms they are derived from.
#include <suturesim/realtime/angle_springs.h>
#include <suturesim/realtime/curvature_springs.h>
#include <suturesim/realtime/home_springs.h>
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/volume_constraints.h>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <random>

#include "realtime/test_meshes.h"

using namespace suturesim;
using namespace suturesim::realtime;

namespace
{
  /// max |f − (−∂E/∂x)| / max |f| over a random configuration, by central differences.
  double
  force_error(const Interaction &interaction, const Matrix3Xd &x)
  {
    Matrix3Xd f = Matrix3Xd::Zero(3, x.cols());
    interaction.add_forces(x, f);
    const double scale = x.cwiseAbs().maxCoeff();
    const double h     = 1e-6 * scale;
    double       error = 0;
    Matrix3Xd    y     = x;
    for (Eigen::Index i = 0; i < x.size(); ++i)
      {
        y.data()[i]     = x.data()[i] + h;
        const double ep = interaction.energy(y);
        y.data()[i]     = x.data()[i] - h;
        const double em = interaction.energy(y);
        y.data()[i]     = x.data()[i];
        error           = std::max(error, std::abs(f.data()[i] + (ep - em) / (2 * h)));
      }
    return error / f.cwiseAbs().maxCoeff();
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
