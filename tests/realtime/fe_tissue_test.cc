// The realtime finite-element tissue (tissue model "fe", neo_hookean_tetrahedra.h)
// against what linear tetrahedra of a hyperelastic material must do: no force under
// rigid motions, linear elasticity's (E, ν) at small strain, the patch test at finite
// strain; its scales. Its integrators: vbd_test.cc.
#include <suturesim/realtime/neo_hookean_tetrahedra.h>
#include <suturesim/realtime/tissue_model.h>

#include <Eigen/Geometry>
#include <gtest/gtest.h>

#include <random>

#include "realtime/test_meshes.h"
#include "realtime/test_worlds.h"

using namespace suturesim;
using namespace suturesim::realtime;

namespace
{
  constexpr double E = 1e4, nu = 0.45; // Pa, 1: a soft, nearly incompressible tissue

  /// The tissue model "fe" of (E, ν) built on @p mesh, its one interaction returned.
  struct FeBody
  {
    System                       system;
    std::unique_ptr<TissueModel> model;

    FeBody(const mesh::SimplexMesh &mesh, const std::map<std::string, std::string> &values = {})
        : model(test_support::make_model<TissueModel::Registry>("fe", values))
    {
      model->build(system, mesh, mesh::extract_boundary(mesh), { E, nu, 1000, {} }, false);
      system.finalize();
    }
    const Interaction &
    elements() const
    {
      return *system.interactions.at(0);
    }
    Matrix3Xd
    forces(const Matrix3Xd &x) const
    {
      Matrix3Xd f = Matrix3Xd::Zero(3, x.cols());
      elements().add_forces(x, f);
      return f;
    }
  };

  /// Whether vertex @p v of the box [0, a]³ lies on its boundary.
  bool
  on_boundary(const mesh::SimplexMesh &mesh, const Eigen::Index v, const double a)
  {
    const Vector3d X = mesh.vertices.col(v);
    return X.minCoeff() < 1e-12 * a || X.maxCoeff() > a * (1 - 1e-12);
  }
} // namespace

TEST(FeTissue, RestStateAndRigidMotionsAreForceAndEnergyFree)
{
  const auto mesh = test_support::box_mesh(0.02, 0.01, 0.01, 2, 1, 1);
  FeBody     body(mesh);
  ASSERT_EQ(body.system.interactions.size(), 1u);
  const double scale = E * 0.01 * 0.01; // a force of E times a face's area
  EXPECT_LT(body.forces(mesh.vertices).cwiseAbs().maxCoeff(), 1e-12 * scale);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const Matrix3Xd       x = (R * mesh.vertices).colwise() + Vector3d(0.3, -0.1, 0.2);
  EXPECT_LT(body.forces(x).cwiseAbs().maxCoeff(), 1e-10 * scale);
  EXPECT_LT(std::abs(body.elements().energy(x)), 1e-12 * E * mesh.total_volume());
}

TEST(FeTissue, SmallStrainIsLinearElasticityOfTheMaterialsYoungsModulusAndPoissonRatio)
{
  // A homogeneous uniaxial stress σ_xx = E e: F = diag(1 + e, 1 − ν e, 1 − ν e). The
  // internal forces on the face x = a sum to −E e times its area, those on y = b to zero,
  // and the energy is ½ E e² V (Lamé constants μ = E/(2(1 + ν)), λ = Eν/((1 + ν)(1 − 2ν))
  // through λ̂ = λ + μ; linearisation errors O(e) = 1e-5).
  const double    a = 0.02, b = 0.01, c = 0.01, e = 1e-5;
  const auto      mesh = test_support::box_mesh(a, b, c, 3, 2, 2);
  FeBody          body(mesh);
  const Matrix3Xd x     = Vector3d(1 + e, 1 - nu * e, 1 - nu * e).asDiagonal() * mesh.vertices;
  const Matrix3Xd f     = body.forces(x);
  Vector3d        right = Vector3d::Zero(), back = Vector3d::Zero();
  for (Eigen::Index v = 0; v < x.cols(); ++v)
    {
      if (mesh.vertices(0, v) > a * (1 - 1e-12))
        right += f.col(v);
      if (mesh.vertices(1, v) > b * (1 - 1e-12))
        back += f.col(v);
    }
  const double resultant = E * e * b * c;
  EXPECT_NEAR(right[0], -resultant, 1e-4 * resultant);
  EXPECT_LT(right.tail<2>().norm(), 1e-4 * resultant);
  EXPECT_LT(back.norm(), 1e-4 * resultant);
  const double expected = 0.5 * E * e * e * a * b * c;
  EXPECT_NEAR(body.elements().energy(x), expected, 1e-3 * expected);
}

TEST(FeTissue, PassesThePatchTestAtFiniteStrainOnADistortedMesh)
{
  // Any homogeneous deformation x = F₀X is an equilibrium of the interior nodes of any
  // mesh: each node's forces are −V₀ P Σ bᵢ over its tetrahedra, and P is the same in
  // all of them. A spring network fails this on a distorted mesh.
  const double                           a    = 0.02;
  auto                                   mesh = test_support::box_mesh(a, a, a, 3, 3, 3);
  std::mt19937                           random(5);
  std::uniform_real_distribution<double> u(-1e-3, 1e-3); // 15 % of the cube's edge
  for (Eigen::Index v = 0; v < mesh.vertices.cols(); ++v)
    if (!on_boundary(mesh, v, a))
      for (int d = 0; d < 3; ++d)
        mesh.vertices(d, v) += u(random);
  for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
    ASSERT_GT(mesh.volume(t), 0);
  FeBody          body(mesh);
  Eigen::Matrix3d F0;
  F0 << 1.3, 0.2, 0.0, -0.1, 0.8, 0.15, 0.05, 0.0, 1.1;
  const Matrix3Xd x        = F0 * mesh.vertices;
  const Matrix3Xd f        = body.forces(x);
  double          interior = 0, boundary = 0;
  for (Eigen::Index v = 0; v < x.cols(); ++v)
    (on_boundary(mesh, v, a) ? boundary : interior)
        = std::max(on_boundary(mesh, v, a) ? boundary : interior, f.col(v).norm());
  EXPECT_GT(boundary, 0);
  EXPECT_LT(interior, 1e-10 * boundary);
}

TEST(FeTissue, ScalesMultiplyTheShearAndBulkModuli)
{
  // μ and K scaled: the uniaxial-strain energy ½ (K + 4μ/3) e² V changes accordingly
  const auto      mesh = test_support::box_mesh(0.01, 0.01, 0.01, 1, 1, 1);
  const double    e    = 1e-5;
  const Matrix3Xd x    = Vector3d(1 + e, 1, 1).asDiagonal() * mesh.vertices;
  const double    mu = E / (2 * (1 + nu)), K = E / (3 * (1 - 2 * nu)), V = mesh.total_volume();
  for (const auto &[s_mu, s_K] : { std::pair{ 1.0, 1.0 }, std::pair{ 2.0, 1.0 }, std::pair{ 1.0, 0.5 } })
    {
      FeBody body(
          mesh, { { "Shear stiffness scale", std::to_string(s_mu) }, { "Bulk stiffness scale", std::to_string(s_K) } });
      const double expected = 0.5 * (s_K * K + 4 * s_mu * mu / 3) * e * e * V;
      EXPECT_NEAR(body.elements().energy(x), expected, 1e-3 * expected) << s_mu << ", " << s_K;
    }
}
