// Knot diagrams (knot/diagram.h): the crossings, Gauss codes and spans of ropes drawn
// from parametric knots, whose diagrams are known, and the Reidemeister reductions.
#include <suturesim/knot/curves.h>
#include <suturesim/knot/diagram.h>

#include <gtest/gtest.h>

#include <cmath>
#include <functional>

using namespace suturesim::knot;
using Eigen::Vector3d;

namespace
{
  /// @p n + 1 nodes of the curve @p f over [t0, t1].
  Eigen::Matrix3Xd
  sample(const std::function<Vector3d(double)> &f, const double t0, const double t1, const int n)
  {
    Eigen::Matrix3Xd x(3, n + 1);
    for (int k = 0; k <= n; ++k)
      x.col(k) = f(t0 + (t1 - t0) * k / n);
    return x;
  }

  /// @p text's closed knot, for GaussCode::is_cut_of().
  GaussCode
  closed(const std::string &text)
  {
    return GaussCode::parse(text);
  }

  const Projection along_z(Vector3d::UnitZ());
} // namespace

TEST(KnotDiagram, StraightAndPlanarRopesHaveNoCrossingAndOneSpan)
{
  const KnotDiagram straight(sample([](double t) { return Vector3d(t, 0, 0); }, 0, 1, 20), along_z);
  EXPECT_TRUE(straight.crossings().empty());
  EXPECT_EQ(straight.spans(), 1u);
  EXPECT_EQ(straight.gauss_code().text(), "");
  // a C-shaped rope seen from above, its plane tilted: still no crossing
  const KnotDiagram arc(sample([](double t) { return Vector3d(std::cos(t), std::sin(t), 0.3 * std::cos(t)); }, 0, 5,
                               50),
                        along_z);
  EXPECT_TRUE(arc.crossings().empty());
}

TEST(KnotDiagram, OneLoopHasOneCrossingWhoseOverStrandIsTheHigher)
{
  // a prolate cycloid's loop: the rope comes back across itself at x = 0 (t = ±1.4958),
  // rising along it, so the later strand is the higher
  const auto loop = [](double t) { return Vector3d(t - 1.5 * std::sin(t), 1 - 1.5 * std::cos(t), 1e-3 * t); };
  // seen from above the later strand is over; from below (n = −z) the earlier one
  for (const double sign : {1.0, -1.0})
    {
      const KnotDiagram d(sample(loop, -2.5, 2.5, 200), Projection(sign * Vector3d::UnitZ()));
      ASSERT_EQ(d.crossings().size(), 1u);
      EXPECT_EQ(d.gauss_code().text(), sign > 0 ? "U1 O1" : "O1 U1");
      EXPECT_EQ(d.spans(), 3u);
      // the occurrences bound the middle span, which is the loop
      const auto &c = d.crossings().front();
      EXPECT_EQ(d.span_of(0.5 * (c.a + c.b)), 1u);
      EXPECT_EQ(d.span_of(0), 0u);
      EXPECT_EQ(d.span_of(200), 2u);
      // the two occurrences are one point in the plane
      const Vector3d pa = d.point(c.a), pb = d.point(c.b);
      EXPECT_NEAR((along_z.in_plane(pa) - along_z.in_plane(pb)).norm(), 0, 1e-12);
      // a twist loop is Reidemeister I: nothing is knotted
      EXPECT_EQ(d.gauss_code().reduced().crossings(), 0u);
    }
}

TEST(KnotDiagram, CutTrefoilReadsTheAlternatingCodeOfThreeCrossings)
{
  // cut open away from a crossing, at every sampling of the curve
  for (const int n : {60, 150, 400})
    {
      const KnotDiagram d(sample(trefoil, 0.1, 0.1 + 2 * M_PI - 1e-3, n), along_z);
      const std::string code = d.gauss_code().text();
      EXPECT_TRUE(code == "O1 U2 O3 U1 O2 U3" || code == "U1 O2 U3 O1 U2 O3") << code;
      EXPECT_TRUE(d.gauss_code().is_cut_of(closed("O1 U2 O3 U1 O2 U3")));
      EXPECT_FALSE(d.gauss_code().is_cut_of(closed("O1 U2 O3 U4 O2 U1 O4 U3")));
      EXPECT_EQ(d.spans(), 7u);
      // alternating and minimal: the moves leave it as it is
      EXPECT_EQ(d.gauss_code().reduced().text(), code);
    }
  // the mirror image (z → −z) swaps over and under
  const KnotDiagram d(sample(trefoil, 0.1, 0.1 + 2 * M_PI - 1e-3, 150), along_z);
  const KnotDiagram m(sample([](double t) { return Vector3d(trefoil(t).cwiseProduct(Vector3d(1, 1, -1))); }, 0.1,
                             0.1 + 2 * M_PI - 1e-3, 150),
                      along_z);
  EXPECT_EQ(m.gauss_code().text(), d.gauss_code().mirrored().text());
}

TEST(KnotDiagram, CutFigureEightReducesToItsFourCrossings)
{
  const KnotDiagram d(sample(figure_eight, 0.05, 0.05 + 2 * M_PI - 1e-3, 600), along_z);
  const GaussCode   reduced = d.gauss_code().reduced();
  ASSERT_EQ(reduced.crossings(), 4u) << d.gauss_code().text();
  // where the closed knot is cut moves the start of its code round: some rotation of the
  // figure-eight's code, or of its mirror image's (the figure-eight is amphichiral)
  EXPECT_TRUE(reduced.is_cut_of(closed("O1 U2 O3 U4 O2 U1 O4 U3"))) << reduced.text();
  EXPECT_FALSE(reduced.is_cut_of(closed("O1 U2 O3 U1 O2 U3")));
  // no crossing is a cut of the unknot's diagram only
  EXPECT_TRUE(GaussCode().is_cut_of(GaussCode()));
  EXPECT_FALSE(GaussCode().is_cut_of(closed("O1 U2 O3 U1 O2 U3")));
}

TEST(KnotDiagram, ReidemeisterTwoRemovesAStrandLaidAcrossAnotherAndBackAndOneATailAcrossTheOther)
{
  // strand 1 passes over strand 2 twice, nothing else: unknotted
  EXPECT_EQ(GaussCode::parse("O1 O2 U2 U1").reduced().text(), "");
  EXPECT_EQ(GaussCode::parse("O1 O2 U1 U2").reduced().text(), "");
  // over then under is a clasp, not a Reidemeister II pair: it stays
  EXPECT_EQ(GaussCode::parse("O1 U2 U1 O2").reduced().text(), "O1 U2 U1 O2");
  // a trefoil with a twist and a pair laid over it reduces to the trefoil
  EXPECT_EQ(GaussCode::parse("O1 U2 O7 U7 O3 O8 O9 U1 O2 U3 U9 U8").reduced().text(), "O1 U2 O3 U1 O2 U3");
  // the first span crossing the last: a twist loop through the arc that closes the rope
  EXPECT_EQ(GaussCode::parse("U1 O2 U3 O4 U2 O3 U4 O1").reduced().text(), "O1 U2 O3 U1 O2 U3");
  EXPECT_EQ(GaussCode::parse("O1 U1").reduced().text(), "");
}

TEST(KnotDiagram, RefusesAMalformedCodeAndAZeroNormal)
{
  EXPECT_THROW(GaussCode::parse("O1 U2"), std::invalid_argument);
  EXPECT_THROW(GaussCode::parse("O1 O1"), std::invalid_argument);
  EXPECT_THROW(GaussCode::parse("X1 U1"), std::invalid_argument);
  EXPECT_THROW(Projection(Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW(KnotDiagram(Eigen::Matrix3Xd(3, 1), along_z), std::invalid_argument);
}

TEST(KnotDiagram, TheClosedKnotsStrandsPassAtTheirClearance)
{
  // the least distance between points of the curve more than 0.9 apart in t, at 2000
  // points per turn (any bound from 0.5 to 1.3 gives the same: the pair is on two
  // strands), against the constants the knot specimen's input check uses (a sampled
  // least distance is at most a few 1e-5 above the curve's)
  for (const auto &[f, clearance] : {std::pair{trefoil, trefoil_clearance},
                                     std::pair{figure_eight, figure_eight_clearance},
                                     std::pair{cinquefoil, cinquefoil_clearance}})
    {
      const int n     = 2000;
      double    least = 1e9;
      for (int i = 0; i < n; ++i)
        for (int j = i + 1; j < n; ++j)
          {
            const double dt = 2 * M_PI * (j - i) / n;
            if (std::min(dt, 2 * M_PI - dt) > 0.9)
              least = std::min(least, (f(2 * M_PI * i / n) - f(2 * M_PI * j / n)).norm());
          }
      EXPECT_GE(least, clearance);
      EXPECT_LT(least, clearance + 2e-4);
    }
}

TEST(KnotDiagram, TheDeterminantNamesTheKnotOnEveryDiagram)
{
  // |Δ(−1)|: 1 for the unknot, 3 for the trefoil, 5 for the figure-eight (Rolfsen's
  // table; Lickorish 1997), the same for the mirror image, for a cut anywhere, and for
  // diagrams with twists and strands laid across (which the reductions remove)
  EXPECT_EQ(GaussCode().determinant(), 1);
  EXPECT_EQ(closed("O1 U1").determinant(), 1);
  EXPECT_EQ(closed("O1 O2 U2 U1").determinant(), 1);
  EXPECT_EQ(closed("O1 U2 O3 U1 O2 U3").determinant(), 3);
  EXPECT_EQ(closed("U1 O2 U3 O1 U2 O3").determinant(), 3);
  EXPECT_EQ(closed("O1 U2 O7 U7 O3 O8 O9 U1 O2 U3 U9 U8").determinant(), 3);
  EXPECT_EQ(closed("O1 U2 O3 U4 O2 U1 O4 U3").determinant(), 5);
  EXPECT_EQ(closed("O1 U2 O3 U1 O4 U3 O2 U4").determinant(), 5); // cut elsewhere
  // the figure-eight seen along z, its curve cut at every sampled point: the raw codes
  // (before the reductions) differ, the determinant does not
  for (const double cut : {0.05, 0.7, 1.9, 3.3, 5.1})
    {
      const KnotDiagram d(sample(figure_eight, cut, cut + 2 * M_PI - 1e-3, 600), along_z);
      EXPECT_EQ(d.gauss_code().determinant(), 5) << d.gauss_code().text();
      const KnotDiagram t(sample(trefoil, cut, cut + 2 * M_PI - 1e-3, 600), along_z);
      EXPECT_EQ(t.gauss_code().determinant(), 3) << t.gauss_code().text();
    }
  // the (2, 5) torus knot, the cinquefoil: 5 too (the determinant does not tell it from
  // the figure-eight; its crossing number does)
  const KnotDiagram c(sample(cinquefoil, 0.05, 0.05 + 2 * M_PI - 1e-3, 800), along_z);
  EXPECT_EQ(c.gauss_code().reduced().crossings(), 5u) << c.gauss_code().text();
  EXPECT_EQ(c.gauss_code().determinant(), 5);
}

TEST(KnotDiagram, TheWritheTellsTheSquareKnotFromTheGranny)
{
  // the trefoil's three crossings turn one way, its mirror image's (z → −z) the other;
  // the figure-eight is its own mirror image: its minimal (alternating) diagram has
  // writhe 0 (Tait's conjecture, proved by Murasugi and by Thistlethwaite: the writhe of
  // a reduced alternating diagram is the knot's)
  const auto mirror = [](const Vector3d &x) { return Vector3d(x.x(), x.y(), -x.z()); };
  const auto turned = [](const Vector3d &x) { return Vector3d(-x.x(), -x.y(), x.z()); }; // π about z
  const int  w      = KnotDiagram(sample(trefoil, 0.1, 0.1 + 2 * M_PI - 1e-3, 300), along_z).gauss_code().writhe();
  EXPECT_EQ(std::abs(w), 3);
  EXPECT_EQ(KnotDiagram(sample([&](double t) { return mirror(trefoil(t)); }, 0.1, 0.1 + 2 * M_PI - 1e-3, 300),
                        along_z)
              .gauss_code()
              .writhe(),
            -w);
  EXPECT_EQ(KnotDiagram(sample([&](double t) { return turned(trefoil(t)); }, 0.1, 0.1 + 2 * M_PI - 1e-3, 300),
                        along_z)
              .gauss_code()
              .writhe(),
            w)
    << "turned in its plane, the same knot";
  const GaussCode eight = KnotDiagram(sample(figure_eight, 0.05, 0.05 + 2 * M_PI - 1e-3, 600), along_z).gauss_code();
  EXPECT_EQ(eight.reduced().writhe(), 0);

  // two trefoils joined (the connected sum): the first cut open at its lobe on −y
  // (t = π, at (0, −3)), the second the first turned by π about z and moved 8 down, cut
  // at the same lobe, now facing the first; the rope runs through the first, across to
  // the second, through it and back up beside, where its two ends meet (the closing arc
  // reduced() assumes crosses nothing). With the second the first's mirror image, it is
  // the square knot's diagram; the same knot twice, the granny's.
  const auto joined = [&](const bool mirrored) {
    const Eigen::Matrix3Xd first = sample(trefoil, M_PI + 0.05, 3 * M_PI - 0.05, 300);
    const Eigen::Matrix3Xd second =
      sample([&](double t) { return Vector3d(turned(mirrored ? mirror(trefoil(t)) : trefoil(t)) - Vector3d(0, 8, 0)); },
             M_PI + 0.05, 3 * M_PI - 0.05, 300);
    Eigen::Matrix3Xd rope(3, first.cols() + second.cols());
    rope << first, second;
    return KnotDiagram(rope, along_z).gauss_code().reduced();
  };
  const GaussCode square = joined(true), granny = joined(false);
  EXPECT_EQ(square.crossings(), 6u) << square.text();
  EXPECT_EQ(granny.crossings(), 6u) << granny.text();
  // the determinant multiplies over the sum, 3 × 3, for both: it does not tell them apart
  EXPECT_EQ(square.determinant(), 9);
  EXPECT_EQ(granny.determinant(), 9);
  // the writhe does
  EXPECT_EQ(square.writhe(), 0);
  EXPECT_EQ(granny.writhe(), 2 * w);
  // a code read from text has no sign
  EXPECT_EQ(closed("O1 U2 O3 U1 O2 U3").writhe(), 0);
}
