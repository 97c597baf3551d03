// Seed 004's node-access constraint (realtime/node_access.h): its gradient against central
// differences, its XPBD forces against its penalty forces, the segment that holds the access point as a straight suture slides, and the
// equilibrium of a suture pulled over the access point against the closed form of a
// thread over a frictionless peg.
#include <suturesim/realtime/node_access.h>
#include <suturesim/realtime/spring_set.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

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
