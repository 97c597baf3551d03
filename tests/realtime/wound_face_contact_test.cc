// The wound's faces kept apart in the realtime path (realtime/wound_face_contact.h): a
// node of face A against a square of face B, the plane x = 0 with lip B beyond it (x > 0)
// and its outward normal −x; the node starts in the gap, 0.1 mm on A's side.
#include <suturesim/realtime/wound_face_contact.h>

#include <gtest/gtest.h>

using namespace suturesim;
using namespace suturesim::realtime;

namespace
{
  constexpr double mm = 1e-3, k = 2e3;

  /// Nodes 0–3: face B's square (1 mm, x = 0), wound outward to −x; node 4: face A's
  /// node at (−0.1, 0.3, 0.4) mm; node 5: a node of face A that is also B's corner 0.
  System
  faces()
  {
    System s;
    for (const Vector3d &X : {Vector3d(0, 0, 0), Vector3d(0, mm, 0), Vector3d(0, mm, mm), Vector3d(0, 0, mm),
                              Vector3d(-0.1 * mm, 0.3 * mm, 0.4 * mm)})
      s.nodes.add(X, 1e-6, 0);
    s.finalize();
    return s;
  }
  const std::vector<mesh::Triangle> face_b{{{0, 2, 1}}, {{0, 3, 2}}};
} // namespace

TEST(WoundFaceContact, PairsAtRestPushesANodeBackOutOfTheOtherLipAndItsForcesAreMinusTheEnergyGradient)
{
  System           s = faces();
  WoundFaceContact c(s, {4, 0}, face_b, k, 5e-5, false);
  Matrix3Xd        x = s.nodes.reference;
  // in the gap: the pair is not listed (its gap 0.1 mm is above the 50 µm margin)
  c.detect(x);
  EXPECT_EQ(c.active(), 0u);
  // face A's node 0.05 mm inside lip B: listed, gap −0.05 mm, pushed back to −x by k 0.05 mm,
  // the square's corners by as much to +x (face A's node 0, B's corner, is not paired)
  x(0, 4) = 0.05 * mm;
  c.detect(x);
  ASSERT_EQ(c.active(), 1u);
  const auto &pair = c.list().front();
  EXPECT_EQ(pair.node, 4u);
  EXPECT_NEAR(c.gap(pair, x), -0.05 * mm, 1e-15);
  EXPECT_NEAR(pair.bary.sum(), 1, 1e-14);
  const Vector3d closest = pair.bary[0] * x.col(pair.triangle[0]) + pair.bary[1] * x.col(pair.triangle[1]) +
                           pair.bary[2] * x.col(pair.triangle[2]);
  EXPECT_NEAR((closest - Vector3d(0, 0.3 * mm, 0.4 * mm)).norm(), 0, 1e-15);
  Matrix3Xd f = Matrix3Xd::Zero(3, x.cols());
  c.add_forces(x, f);
  EXPECT_NEAR(f(0, 4), -k * 0.05 * mm, 1e-12);
  EXPECT_NEAR(f.leftCols(4).row(0).sum(), k * 0.05 * mm, 1e-12);
  EXPECT_NEAR(f.rowwise().sum().norm(), 0, 1e-15); // no net force
  // forces against central differences of the energy (pair and normal held)
  const double h = 1e-9;
  for (Eigen::Index i = 0; i < 5; ++i)
    for (int d = 0; d < 3; ++d)
      {
        Matrix3Xd xp = x, xm = x;
        xp(d, i) += h;
        xm(d, i) -= h;
        const double fd = -(*c.energy(xp) - *c.energy(xm)) / (2 * h);
        EXPECT_NEAR(f(d, i), fd, 1e-6 * k * 0.05 * mm) << "node " << i << " direction " << d;
      }
  // the stable step's estimate: k at the node, Σ b² k at the corners
  std::vector<double> stiffness(5, 0);
  c.add_potential_stiffness(stiffness);
  EXPECT_DOUBLE_EQ(stiffness[4], k);
  EXPECT_NEAR(stiffness[0] + stiffness[1] + stiffness[2] + stiffness[3],
              k * pair.bary.squaredNorm(), 1e-9 * k);
  EXPECT_THROW(WoundFaceContact(s, {}, face_b, k, 0, false), std::invalid_argument);
  EXPECT_THROW(WoundFaceContact(s, {4}, face_b, 0, 0, false), std::invalid_argument);
}

TEST(WoundFaceContact, XpbdProjectsANodeBackOntoTheFace)
{
  // the inequality g ≥ 0 with compliance 1/k: one projection of a stiff pair moves the
  // node and the square's corners by their inverse masses until the gap closes
  System           s = faces();
  WoundFaceContact c(s, {4}, face_b, 1e12, 5e-5, true);
  EXPECT_TRUE(c.has_projection());
  Matrix3Xd x = s.nodes.reference;
  x(0, 4)     = 0.05 * mm;
  c.detect(x);
  c.reset_multipliers();
  const VectorXd w = VectorXd::Constant(5, 1e6);
  c.project(x, w, 1e-3);
  EXPECT_NEAR(c.gap(c.list().front(), x), 0, 1e-9 * mm);
  // a node on A's side is not pulled across
  Matrix3Xd y = s.nodes.reference;
  y(0, 4)     = -0.01 * mm;
  c.detect(y);
  c.reset_multipliers();
  const Matrix3Xd before = y;
  c.project(y, w, 1e-3);
  EXPECT_EQ(y, before);
}
