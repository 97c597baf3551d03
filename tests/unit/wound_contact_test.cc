// Contact between an incision's faces (coupling/accurate/wound_contact.h) on a V-shaped
// wound of two faces that share their bottom edge (the incision's front) and gape by
// 0.2 mm at the top: the pairing, the margin, the penalty's direction and size, and the
// tangent it gives the tissue (each point's own block through the point loads, the
// blocks between the two points of a pair through the condensed body's G) against
// central differences of the forces.
#include <suturesim/coupling/accurate/wound_contact.h>

#include <gtest/gtest.h>

using namespace suturesim;
using namespace dealii;

namespace
{
  constexpr double h = 1e-3, g = 1e-4; // face height, half the gap at the top (m)

  struct Wound
  {
    Eigen::Matrix3Xd                          X;
    std::vector<std::array<std::uint32_t, 3>> triangles{
      {{0, 1, 2}}, {{1, 3, 2}}, {{0, 4, 1}}, {{1, 4, 5}}};
    std::vector<types::boundary_id>           ids{3, 3, 4, 4};
    Wound()
      : X(3, 6)
    {
      // 0, 1: the shared front at the bottom; 2, 3: face A's top (x < 0); 4, 5: B's
      X << 0, 0, -g, -g, g, g, //
        0, h, 0, h, 0, h,      //
        0, 0, h, h, h, h;
    }
  };
} // namespace

TEST(WoundContact, PairsFaceAWithFaceBAndPushesThemApartWithTheExactTangent)
{
  const Wound                     w;
  const double                    k = 5e4;
  coupling::WoundContact          contact({k, 5e-5}, w.X, w.triangles, w.ids, 3, 4);
  // the front's vertices are on both faces: only A's top two are paired, each with
  // B's vertex across (B's normal points back at A)
  ASSERT_EQ(contact.pairs().size(), 2u);
  for (const auto &p : contact.pairs())
    {
      EXPECT_TRUE(p.vertex == 2 || p.vertex == 3);
      EXPECT_LT(p.normal[0], -0.99);
    }
  EXPECT_FALSE(contact.detect(w.X)); // 0.2 mm open, beyond the 50 µm margin: none loaded
  EXPECT_TRUE(contact.loaded().empty());

  // A's top pushed 0.3 mm across: 0.1 mm through B, both pairs loaded
  Eigen::Matrix3Xd now = w.X;
  now(0, 2) += 3 * g;
  now(0, 3) += 3 * g;
  ASSERT_TRUE(contact.detect(now));
  ASSERT_EQ(contact.points().size(), 4u); // P, P, Q, Q
  std::vector<Point<3>> x(4);
  for (std::size_t j = 0; j < 2; ++j)
    {
      const auto &pair = contact.pairs()[contact.loaded()[j]];
      const auto  q    = pair.weights[0] * now.col(pair.triangle[0]) + pair.weights[1] * now.col(pair.triangle[1]) +
                     pair.weights[2] * now.col(pair.triangle[2]);
      x[j]     = Point<3>(now(0, pair.vertex), now(1, pair.vertex), now(2, pair.vertex));
      x[2 + j] = Point<3>(q[0], q[1], q[2]);
    }
  Eigen::MatrixXd G;
  std::string     failure;
  ASSERT_TRUE(contact.equilibrate(x, G, failure));
  EXPECT_EQ(contact.n_touching(), 2u);
  EXPECT_NEAR(contact.least_gap(), -g * std::abs(contact.pairs()[0].normal[0]), 1e-12);
  Tensor<1, 3> f, f_q;
  Tensor<2, 3> unused;
  contact.force(0, x[0], f, unused);
  contact.force(2, x[2], f_q, unused);
  EXPECT_NEAR(f.norm(), k * g * std::abs(contact.pairs()[0].normal[0]), 1e-9); // k |g|
  EXPECT_LT(f[0], 0);                                     // P is pushed back to A's side
  EXPECT_NEAR((f + f_q).norm(), 0, 1e-12);               // and Q as much the other way

  // the tissue's tangent −∂f/∂x over all four points: own blocks −∂f_k/∂x_k from the
  // point loads, the rest from G; against central differences (the forces are linear
  // in contact, so they must agree to round-off)
  Eigen::MatrixXd tangent = G;
  for (std::size_t k = 0; k < 4; ++k)
    {
      Tensor<1, 3> fk;
      Tensor<2, 3> df;
      contact.force(k, x[k], fk, df);
      for (unsigned a = 0; a < 3; ++a)
        for (unsigned b = 0; b < 3; ++b)
          tangent(3 * k + a, 3 * k + b) -= df[a][b];
    }
  const auto forces = [&](const std::vector<Point<3>> &y) {
    Eigen::MatrixXd unused_G;
    contact.equilibrate(y, unused_G, failure);
    Eigen::VectorXd all(12);
    for (std::size_t k = 0; k < 4; ++k)
      {
        Tensor<1, 3> fk;
        Tensor<2, 3> df;
        contact.force(k, y[k], fk, df);
        for (unsigned a = 0; a < 3; ++a)
          all[3 * k + a] = fk[a];
      }
    return all;
  };
  const double    step = 1e-9;
  Eigen::MatrixXd fd(12, 12);
  for (std::size_t k = 0; k < 4; ++k)
    for (unsigned b = 0; b < 3; ++b)
      {
        auto plus = x, minus = x;
        plus[k][b] += step;
        minus[k][b] -= step;
        fd.col(3 * k + b) = -(forces(plus) - forces(minus)) / (2 * step);
      }
  EXPECT_LT((tangent - fd).norm(), 1e-6 * tangent.norm()) << "tangent\n" << tangent << "\ndifferences\n" << fd;
  EXPECT_GT(G.norm(), 0.5 * k); // the cross blocks are there

  // drawn apart again to 20 µm open (inside the margin): loaded, but no force
  std::vector<Point<3>> open = x;
  for (std::size_t j = 0; j < 2; ++j)
    open[j][0] = x[2 + j][0] - 2e-5 / std::abs(contact.pairs()[contact.loaded()[j]].normal[0]);
  ASSERT_TRUE(contact.equilibrate(open, G, failure));
  EXPECT_EQ(contact.n_touching(), 0u);
  EXPECT_EQ(G.norm(), 0.0);
  contact.force(0, open[0], f, unused);
  EXPECT_EQ(f.norm(), 0.0);
}

TEST(WoundContact, RefusesAFaceTheMeshDoesNotHave)
{
  const Wound w;
  EXPECT_THROW(coupling::WoundContact({5e4, 5e-5}, w.X, w.triangles, w.ids, 3, 7), std::invalid_argument);
}
