// The suture's C¹ centreline (coupling/accurate/thread_curve.h), tested directly: it
// interpolates the nodes with the rod's tangent directors, its tangent direction is
// continuous at the nodes (where the chord polyline's is not), its derivatives agree with
// central differences, and the closest-point projection finds the foot of a
// perpendicular.
//
// The thread: 9 nodes on a helix of radius 4 mm and pitch 2π × 1.5 mm, 1.3 mm apart, each
// with a rotation whose director d₁ = R e₁ is the helix's tangent, twisted about it by a
// different angle at every node (the curve must see d₁ only).
#include <suturesim/coupling/accurate/thread_curve.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>

using namespace suturesim;
using coupling::HermiteSegment;
using coupling::ThreadCurve;

namespace
{
  constexpr double eps = std::numeric_limits<double>::epsilon();

  struct Helix
  {
    std::vector<rod::Vec3> x, tangent;
    std::vector<rod::Quat> q;
    std::vector<double>    lengths; ///< reference element lengths, m

    Helix()
    {
      const double R = 4e-3, pitch = 1.5e-3, dphi = 0.3;
      for (unsigned i = 0; i < 9; ++i)
        {
          const double phi = dphi * i;
          x.emplace_back(R * std::cos(phi), R * std::sin(phi), pitch * phi);
          tangent.push_back(rod::Vec3(-R * std::sin(phi), R * std::cos(phi), pitch).normalized());
          q.push_back(Eigen::AngleAxisd(0.7 * i - 1.0, tangent.back()) *
                      rod::Quat::FromTwoVectors(rod::Vec3::UnitX(), tangent.back()));
        }
      // the reference lengths differ from the current chords (a stretched thread)
      for (unsigned e = 0; e + 1 < x.size(); ++e)
        lengths.push_back(0.9 * (x[e + 1] - x[e]).norm());
    }
  };

  /// The angle between two directions, rad.
  double
  angle(const Eigen::Vector3d &a, const Eigen::Vector3d &b)
  {
    return std::atan2(a.cross(b).norm(), a.dot(b));
  }
} // namespace

TEST(ThreadCurve, InterpolatesTheNodesWithTheRodsDirectorsAsTangents)
{
  const Helix  h;
  ThreadCurve  thread;
  thread.attach(&h.x, h.lengths, &h.q);
  ASSERT_EQ(thread.n_elements(), h.x.size() - 1);
  for (std::size_t e = 0; e < thread.n_elements(); ++e)
    {
      const HermiteSegment c     = thread.segment(e);
      const double         chord = (h.x[e + 1] - h.x[e]).norm();
      // c(0) = x_a, c(1) = x_b: the Hermite basis is 1 and 0 there exactly
      EXPECT_LE((c.at(0) - h.x[e]).norm(), 4 * eps * h.x[e].norm());
      EXPECT_LE((c.at(1) - h.x[e + 1]).norm(), 4 * eps * h.x[e + 1].norm());
      // c′ = ℓ d₁ at both ends, d₁ the helix's tangent (FromTwoVectors and the twist
      // leave it to a few ε)
      EXPECT_LT(angle(c.rate(0), h.tangent[e]), 1e-14);
      EXPECT_LT(angle(c.rate(1), h.tangent[e + 1]), 1e-14);
      EXPECT_NEAR(c.rate(0).norm(), chord, 1e-14 * chord);
      EXPECT_NEAR(c.rate(1).norm(), chord, 1e-14 * chord);
    }
}

TEST(ThreadCurve, TangentIsContinuousAtTheNodesUnlikeThePolyline)
{
  const Helix h;
  ThreadCurve smooth, polyline;
  smooth.attach(&h.x, h.lengths, &h.q);
  polyline.attach(&h.x, h.lengths, nullptr);
  for (std::size_t e = 0; e + 1 < smooth.n_elements(); ++e)
    {
      // the node between elements e and e + 1, seen from either side
      EXPECT_LT(angle(smooth.segment(e).rate(1), smooth.segment(e + 1).rate(0)), 1e-14) << "node " << e + 1;
      // the chords turn by about dφ times the helix's curvature times its speed:
      // 0.3 × R / √(R² + pitch²) ≈ 0.28 rad; the test above would see that
      EXPECT_GT(angle(polyline.segment(e).rate(1), polyline.segment(e + 1).rate(0)), 0.2) << "node " << e + 1;
    }
  // without rotations each element is its chord: c(u) = (1 − u) x_a + u x_b
  const HermiteSegment chord = polyline.segment(3);
  for (const double u : {-0.5, 0.0, 0.3, 0.75, 1.0, 1.6})
    EXPECT_LE((chord.at(u) - ((1 - u) * h.x[3] + u * h.x[4])).norm(), 8 * eps * h.x[4].norm()) << "u = " << u;
}

TEST(ThreadCurve, DerivativesMatchCentralDifferences)
{
  // For the cubic c, (c(u + δ) − c(u − δ)) / 2δ = c′(u) + c‴ δ²/6 exactly, with the
  // constant c‴ = 12 (x_a − x_b) + 6 m_a + 6 m_b (third derivatives of the Hermite
  // basis: 12, 6, −12, 6); c′ is quadratic, so its central difference is c″ exactly.
  // The bounds add the round-off of the differences, 4 ε max|c| / δ.
  const Helix h;
  ThreadCurve thread;
  thread.attach(&h.x, h.lengths, &h.q);
  const double delta = 1e-4;
  unsigned     checked = 0;
  for (std::size_t e = 0; e < thread.n_elements(); ++e)
    {
      const HermiteSegment c = thread.segment(e);
      const double third = 12 * (c.xa - c.xb).norm() + 6 * c.ma.norm() + 6 * c.mb.norm();
      for (const double u : {-0.4, 0.0, 0.2, 0.5, 0.9, 1.0, 1.3})
        {
          const Eigen::Vector3d d1 = (c.at(u + delta) - c.at(u - delta)) / (2 * delta);
          const Eigen::Vector3d d2 = (c.rate(u + delta) - c.rate(u - delta)) / (2 * delta);
          const double          scale = std::max(c.xa.norm(), c.xb.norm()) + c.ma.norm() + c.mb.norm();
          EXPECT_LE((d1 - c.rate(u)).norm(), third * delta * delta / 6 + 4 * eps * 4 * scale / delta)
            << "element " << e << ", u = " << u;
          EXPECT_LE((d2 - c.bend(u)).norm(), 4 * eps * 12 * scale / delta) << "element " << e << ", u = " << u;
          // and the differences are not trivially small: c′ is of the order of the chord
          EXPECT_GT(c.rate(u).norm(), 0.5 * h.lengths[e]);
          ++checked;
        }
    }
  EXPECT_EQ(checked, 7 * thread.n_elements());
}

TEST(ThreadCurve, ClosestPointIsTheFootOfThePerpendicular)
{
  // x = c(u*) + r n, n ⊥ c′(u*), r a fifth of the element (far inside the radius of
  // curvature, ≈ 4.6 mm): u* is the closest point's parameter. Newton stops at steps
  // below 1e-14, so u lands within that of the root, which round-off of g = (x − c)·c′
  // moves by about ε |x| / |c′| ≈ 1e-14 more.
  const Helix h;
  ThreadCurve thread;
  thread.attach(&h.x, h.lengths, &h.q);
  unsigned checked = 0;
  for (std::size_t e = 0; e < thread.n_elements(); ++e)
    for (const double u_star : {0.1, 0.5, 0.85})
      for (const double turn : {0.0, 2.0, 4.0})
        {
          const HermiteSegment  c = thread.segment(e);
          const Eigen::Vector3d t = c.rate(u_star).normalized();
          const Eigen::Vector3d a = t.unitOrthogonal();
          const Eigen::Vector3d n = std::cos(turn) * a + std::sin(turn) * t.cross(a);
          const Eigen::Vector3d x = c.at(u_star) + 0.2 * h.lengths[e] * n;
          const double          u = c.closest(x, 0.5);
          EXPECT_NEAR(u, u_star, 1e-12) << "element " << e << ", u* = " << u_star << ", turn " << turn;
          EXPECT_LT(std::abs((x - c.at(u)).dot(c.rate(u).normalized())), 1e-15) << "element " << e;
          ++checked;
        }
  EXPECT_EQ(checked, 9 * thread.n_elements());
}

TEST(ThreadCurve, ArcLengthNamesTheElementAndTheWeightOfItsSecondNode)
{
  const Helix h;
  ThreadCurve thread;
  thread.attach(&h.x, h.lengths, &h.q);
  double s = 0;
  for (std::size_t e = 0; e < thread.n_elements(); ++e)
    {
      EXPECT_DOUBLE_EQ(thread.arc_length(e), s);
      const auto [at_node, xi_node] = thread.element(s);
      EXPECT_EQ(at_node, e);
      EXPECT_NEAR(xi_node, 0, 1e-12);
      const auto [inside, xi] = thread.element(s + 0.25 * h.lengths[e]);
      EXPECT_EQ(inside, e);
      EXPECT_NEAR(xi, 0.25, 1e-12);
      s += h.lengths[e];
    }
  EXPECT_DOUBLE_EQ(thread.length(), s);
  // beyond the ends: the first and the last element, the weight clamped
  EXPECT_EQ(thread.element(-1e-3), std::make_pair(std::size_t(0), 0.0));
  EXPECT_EQ(thread.element(s + 1e-3), std::make_pair(thread.n_elements() - 1, 1.0));
}

TEST(ThreadCurve, ReactionIsTheVirtualWorkOfTheForceAtTheCurvesPoint)
{
  // HermiteSegment::reaction(u, f) against central differences of f·c(u) over the 12
  // nodal unknowns at fixed u: positions moved by ±h, rotations turned by exp(±h ê)
  // (the rod's spatial increments). The end tangents' length, the chord ℓ, has third
  // derivatives of order 3/ℓ² in the positions, so the differences are exact to
  // (h/ℓ)² |f| (with h²/6, |t| < 1 and a factor 2 to spare), plus the round-off
  // 4 ε |f| |c| / h. Then the statics: the loads'
  // resultant is f and their moment about the origin c(u) × f (the force acts where the
  // curve is; the chord's weights miss the curve's bulge). Inside the element and 0.1
  // and 0.3 beyond either end (a pierce point on the curve continued, before its
  // carrier moves on), with and without directors (the chord).
  const Helix           h;
  const Eigen::Vector3d f(0.3, -1.1, 0.7); // N
  const double          step = 1e-7; // m and rad
  unsigned              checked = 0;
  for (const bool directors : {true, false})
    for (std::size_t e = 0; e + 1 < h.x.size(); ++e)
      for (const double u : {-0.3, -0.1, 0.0, 0.35, 0.8, 1.0, 1.1, 1.3})
        {
          SCOPED_TRACE("element " + std::to_string(e) + ", u = " + std::to_string(u) +
                       (directors ? "" : ", chord"));
          const auto work = [&](const unsigned c, const double by) {
            rod::Vec3 xa = h.x[e], xb = h.x[e + 1];
            rod::Quat qa = h.q[e], qb = h.q[e + 1];
            rod::Vec3 &y = c < 6 ? xa : xb;
            rod::Quat &q = c < 6 ? qa : qb;
            if (c % 6 >= 3)
              q = rod::quaternion_exp(by * rod::Vec3::Unit(c % 3)) * q;
            else
              y += by * rod::Vec3::Unit(c % 3);
            return f.dot(HermiteSegment::through(xa, qa, xb, qb, directors).at(u));
          };
          const HermiteSegment               c = HermiteSegment::through(h.x[e], h.q[e], h.x[e + 1], h.q[e + 1], directors);
          const Eigen::Matrix<double, 12, 1> r = c.reaction(u, f);
          const double                       size = c.at(u).norm() * f.norm();
          const double                       chord = (h.x[e + 1] - h.x[e]).norm();
          for (unsigned k = 0; k < 12; ++k)
            EXPECT_NEAR(r[k], (work(k, step) - work(k, -step)) / (2 * step),
                        std::pow(step / chord, 2) * f.norm() + 4 * eps * size / step)
              << "unknown " << k;
          const Eigen::Vector3d resultant = r.head<3>() + r.segment<3>(6);
          const Eigen::Vector3d moment =
            h.x[e].cross(r.head<3>()) + r.segment<3>(3) + h.x[e + 1].cross(r.segment<3>(6)) + r.segment<3>(9);
          EXPECT_LE((resultant - f).norm(), 8 * eps * f.norm());
          EXPECT_LE((moment - c.at(u).cross(f)).norm(), 64 * eps * size);
          if (!directors)
            {
              EXPECT_EQ(r.segment<3>(3).norm() + r.segment<3>(9).norm(), 0.0);
            }
          ++checked;
        }
  EXPECT_EQ(checked, 2 * 8 * (h.x.size() - 1));
}
