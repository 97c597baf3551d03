// The accurate path's suture–tissue contact (coupling/accurate/suture_contact.h) and the
// list that joins it to the needle's point loads (tissue/point_load_list.h), on the
// boundary of a tetrahedral box: which nodes are contacts, the penalty on both sides
// (equal and opposite), their Jacobians against central differences, and when the set
// changes (a grow-only detection keeps each contact on its triangle).
#include "../realtime/test_meshes.h"

#include <suturesim/coupling/accurate/suture_contact.h>
#include <suturesim/tissue/point_load_list.h>

#include <gtest/gtest.h>

using suturesim::coupling::SutureContact;
using suturesim::coupling::SutureContactParameters;
using suturesim::rod::Vec3;

namespace
{
  // a 10 × 10 × 4 mm box, its top at z = 4 mm; a suture of radius 0.1 mm
  constexpr double r = 1e-4, k = 5e4, depth = 1e-3, top = 0.004;

  struct Box
  {
    suturesim::mesh::SimplexMesh      mesh = suturesim::test_support::box_mesh(0.01, 0.01, top, 4, 4, 2);
    suturesim::mesh::BoundarySurface surface = suturesim::mesh::extract_boundary(mesh);
  };

  Eigen::Vector3d
  at(const dealii::Point<3> &p)
  {
    return {p[0], p[1], p[2]};
  }
} // namespace

TEST(SutureContact, NodesNearTheSurfaceAreContactsAndOnlyThoseWithinTheRadiusArePushed)
{
  const Box     box;
  SutureContact contact(SutureContactParameters{k, r, depth}, box.surface.triangles, box.mesh.vertices);
  // over the top at 0.5 r (pushed by k r/2), at 1.1 r (listed, no force), at 2 r (not
  // listed), 0.5 mm below it (pushed out), 1.5 mm below (deeper than Depth: inside on
  // purpose), and one skipped
  const std::vector<Vec3> nodes{{0.003, 0.004, top + 0.5 * r}, {0.006, 0.004, top + 1.1 * r},
                                {0.005, 0.005, top + 2 * r},   {0.004, 0.006, top - 5e-4},
                                {0.005, 0.003, top - 1.5e-3},  {0.007, 0.007, top}};
  contact.set_suture(&nodes);
  std::vector<char> skip(nodes.size(), 0);
  skip[5] = 1;
  ASSERT_TRUE(contact.detect(box.mesh.vertices, nodes, skip));
  ASSERT_EQ(contact.contacts().size(), 3u);
  EXPECT_EQ(contact.contact_of(0), 0);
  EXPECT_EQ(contact.contact_of(1), 1);
  EXPECT_EQ(contact.contact_of(2), -1);
  EXPECT_EQ(contact.contact_of(3), 2);
  EXPECT_EQ(contact.contact_of(4), -1);
  EXPECT_EQ(contact.contact_of(5), -1);
  // the surface points are the nodes' closest points on the top, in the reference box
  for (std::size_t c = 0; c < 3; ++c)
    {
      const Eigen::Vector3d X = at(contact.points()[c]), p = nodes[contact.contacts()[c].node];
      EXPECT_NEAR((X - Eigen::Vector3d(p[0], p[1], top)).norm(), 0, 1e-15);
      EXPECT_NEAR((contact.contacts()[c].normal - Eigen::Vector3d::UnitZ()).norm(), 0, 1e-15);
    }
  // the tissue not moved: the forces are k times the overlap, along +z on the node
  contact.set_tissue_positions(contact.points());
  EXPECT_NEAR(contact.total_force(nodes), k * (0.5 * r + (5e-4 + r)), 1e-9);
  for (std::size_t c = 0; c < 3; ++c)
    {
      const std::size_t i = contact.contacts()[c].node;
      suturesim::rod::Vec6 residual = suturesim::rod::Vec6::Zero();
      suturesim::rod::Mat6 jacobian = suturesim::rod::Mat6::Zero();
      contact.add_node_terms(i, nodes[i], residual, jacobian);
      dealii::Tensor<1, 3> f;
      dealii::Tensor<2, 3> df;
      contact.force(c, contact.points()[c], f, df);
      const double expected = c == 1 ? 0.0 : k * (r - (nodes[i][2] - top));
      EXPECT_NEAR(-residual[2], expected, 1e-9) << "contact " << c;
      // equal and opposite: the node's −residual is the force on it, f the tissue's
      for (unsigned d = 0; d < 3; ++d)
        EXPECT_NEAR(-residual[d] + f[d], 0, 1e-12) << "contact " << c;
    }
  // unchanged nodes on unchanged triangles: not a new set (the tissue keeps its loads)
  EXPECT_FALSE(contact.detect(box.mesh.vertices, nodes, skip));
  skip[5] = 0;
  EXPECT_TRUE(contact.detect(box.mesh.vertices, nodes, skip));
  EXPECT_EQ(contact.contacts().size(), 4u);
}

TEST(SutureContact, AGrowOnlyDetectionKeepsEachContactOnItsTriangleAndOnlyAddsNodes)
{
  const Box     box;
  SutureContact contact(SutureContactParameters{k, r, depth}, box.surface.triangles, box.mesh.vertices);
  // nodes 0 and 1 over the top at 0.5 r, node 2 far above, node 3 skipped for now
  std::vector<Vec3> nodes{{0.003, 0.004, top + 0.5 * r}, {0.006, 0.004, top + 0.5 * r}, {0.005, 0.005, top + 0.01},
                          {0.007, 0.007, top}};
  contact.set_suture(&nodes);
  std::vector<char> skip{0, 0, 0, 1};
  ASSERT_TRUE(contact.detect(box.mesh.vertices, nodes, skip));
  ASSERT_EQ(contact.contacts().size(), 2u);
  const auto triangle0 = contact.contacts()[0].triangle;
  // node 0 slides 2.5 mm over the top, onto another triangle; node 1 lifts out of the
  // band (2 r above); node 3 comes in
  nodes[0][0] += 2.5e-3;
  nodes[1][2] = top + 2 * r;
  skip[3]     = 0;
  {
    SutureContact fresh(SutureContactParameters{k, r, depth}, box.surface.triangles, box.mesh.vertices);
    fresh.set_suture(&nodes);
    ASSERT_TRUE(fresh.detect(box.mesh.vertices, nodes, skip));
    ASSERT_EQ(fresh.contact_of(0), 0);
    ASSERT_NE(fresh.contacts()[0].triangle, triangle0); // the slide does change triangle
    ASSERT_EQ(fresh.contact_of(1), -1);
  }
  ASSERT_TRUE(contact.detect(box.mesh.vertices, nodes, skip, true)); // node 3 is new
  ASSERT_EQ(contact.contacts().size(), 3u);
  EXPECT_EQ(contact.contact_of(0), 0);
  EXPECT_EQ(contact.contacts()[0].triangle, triangle0); // kept on its triangle
  EXPECT_EQ(contact.contact_of(1), 1);                  // kept, out of the band
  EXPECT_EQ(contact.contact_of(3), 2);
  // the kept contact out of the band carries no force
  contact.set_tissue_positions(contact.points());
  suturesim::rod::Vec6 residual = suturesim::rod::Vec6::Zero();
  suturesim::rod::Mat6 jacobian = suturesim::rod::Mat6::Zero();
  contact.add_node_terms(1, nodes[1], residual, jacobian);
  EXPECT_EQ(residual.norm(), 0.0);
  // nothing new: unchanged, however the nodes moved
  EXPECT_FALSE(contact.detect(box.mesh.vertices, nodes, skip, true));
  // a fresh detection drops node 1 and moves node 0 to its new triangle
  EXPECT_TRUE(contact.detect(box.mesh.vertices, nodes, skip));
  EXPECT_EQ(contact.contacts().size(), 2u);
  EXPECT_EQ(contact.contact_of(1), -1);
  EXPECT_NE(contact.contacts()[0].triangle, triangle0);
}

TEST(SutureContact, BothSidesJacobiansMatchCentralDifferences)
{
  const Box     box;
  SutureContact contact(SutureContactParameters{k, r, depth}, box.surface.triangles, box.mesh.vertices);
  // a node pressed into a slanted part of the surface is not needed: the frozen normal
  // makes the law linear in both positions; the check guards the signs and the blocks
  std::vector<Vec3> nodes{{0.0031, 0.0042, top - 3e-5}};
  contact.set_suture(&nodes);
  ASSERT_TRUE(contact.detect(box.mesh.vertices, nodes, {0}));
  // the tissue's point moved a little off its reference place
  const dealii::Point<3> q = contact.points()[0] + dealii::Point<3>(1e-6, -2e-6, 1e-5);
  contact.set_tissue_positions({q});
  const double h = 1e-9;
  // node side: residual and Jacobian in the node's position
  suturesim::rod::Vec6 r0 = suturesim::rod::Vec6::Zero();
  suturesim::rod::Mat6 J  = suturesim::rod::Mat6::Zero();
  contact.add_node_terms(0, nodes[0], r0, J);
  ASSERT_GT(r0.norm(), 1);
  for (unsigned j = 0; j < 3; ++j)
    {
      suturesim::rod::Vec6 rp = suturesim::rod::Vec6::Zero(), rm = rp;
      suturesim::rod::Mat6 ignored;
      Vec3                 xp = nodes[0], xm = nodes[0];
      xp[j] += h;
      xm[j] -= h;
      contact.add_node_terms(0, xp, rp, ignored);
      contact.add_node_terms(0, xm, rm, ignored);
      const suturesim::rod::Vec6 fd = (rp - rm) / (2 * h);
      for (unsigned i = 0; i < 6; ++i)
        EXPECT_NEAR(J(i, j), fd[i], 1e-6 * k) << i << ", " << j;
    }
  // tissue side: f and ∂f/∂x at the tissue point
  dealii::Tensor<1, 3> f;
  dealii::Tensor<2, 3> df;
  contact.force(0, q, f, df);
  for (unsigned j = 0; j < 3; ++j)
    {
      dealii::Point<3> qp = q, qm = q;
      qp[j] += h;
      qm[j] -= h;
      dealii::Tensor<1, 3> fp, fm;
      dealii::Tensor<2, 3> ignored;
      contact.force(0, qp, fp, ignored);
      contact.force(0, qm, fm, ignored);
      for (unsigned i = 0; i < 3; ++i)
        EXPECT_NEAR(df[i][j], (fp[i] - fm[i]) / (2 * h), 1e-6 * k) << i << ", " << j;
    }
}

// The rounded law (Suture/Tissue contact/Smoothing width δ): the sharp penalty k (−g)
// wherever the node presses by δ or more, nothing from g = δ on, and between them the
// quadratic k (δ − g)²/(4δ), meeting both with value and slope (C¹). Its slope on both
// sides is the derivative of its force, across the band's ends too, where the sharp law's
// jumps from 0 to k at g = 0.
TEST(SutureContact, TheRoundedPenaltyIsTheSharpOneBeyondItsBandAndC1AcrossIt)
{
  const Box     box;
  const double  delta = 2e-6;
  SutureContact rounded(SutureContactParameters{k, r, depth, delta}, box.surface.triangles, box.mesh.vertices);
  SutureContact sharp(SutureContactParameters{k, r, depth}, box.surface.triangles, box.mesh.vertices);
  std::vector<Vec3> nodes{{0.0031, 0.0042, top + r}};
  for (SutureContact *c : {&rounded, &sharp})
    {
      c->set_suture(&nodes);
      ASSERT_TRUE(c->detect(box.mesh.vertices, nodes, {0}));
      c->set_tissue_positions(c->points());
    }
  // the force on the node and its slope along the normal (+z) at gap g
  const auto at_gap = [&](const SutureContact &c, const double g) {
    suturesim::rod::Vec6 residual = suturesim::rod::Vec6::Zero();
    suturesim::rod::Mat6 jacobian = suturesim::rod::Mat6::Zero();
    c.add_node_terms(0, Vec3(0.0031, 0.0042, top + r + g), residual, jacobian);
    return std::pair<double, double>{-residual[2], jacobian(2, 2)};
  };
  for (const double g : {-50 * delta, -3 * delta, -delta * (1 + 1e-9)})
    {
      EXPECT_NEAR(at_gap(rounded, g).first, -k * g, 1e-12) << g;
      EXPECT_NEAR(at_gap(rounded, g).second, k, 1e-9 * k) << g; // the gap's round-off over δ
      EXPECT_NEAR(at_gap(sharp, g).first, at_gap(rounded, g).first, 1e-12) << g;
    }
  for (const double g : {-0.5 * delta, 0.0, 0.5 * delta})
    EXPECT_NEAR(at_gap(rounded, g).first, k * (delta - g) * (delta - g) / (4 * delta), 1e-12) << g;
  EXPECT_NEAR(at_gap(rounded, 0).first, k * delta / 4, 1e-12);  // the sharp law: 0
  EXPECT_NEAR(at_gap(rounded, 0).second, k / 2, 1e-9 * k);        // the sharp law: 0 or k
  EXPECT_EQ(at_gap(rounded, delta * (1 + 1e-9)).first, 0.0);
  EXPECT_EQ(at_gap(rounded, 5 * delta).first, 0.0);
  // the slope is the force's derivative everywhere, the band's ends included
  const double h = 1e-3 * delta;
  for (const double g : {-2 * delta, -delta, -0.3 * delta, 0.0, 0.7 * delta, delta})
    {
      const double fd = (at_gap(rounded, g - h).first - at_gap(rounded, g + h).first) / (2 * h);
      EXPECT_NEAR(at_gap(rounded, g).second, fd, 1e-3 * k) << g;
    }
  // the tissue's side: the same force, opposite, and its slope
  dealii::Tensor<1, 3> f;
  dealii::Tensor<2, 3> df;
  nodes[0] = Vec3(0.0031, 0.0042, top + r - 0.4 * delta);
  rounded.force(0, rounded.points()[0], f, df);
  EXPECT_NEAR(f[2], -k * 1.4 * 1.4 * delta / 4, 1e-12);
  EXPECT_NEAR(df[2][2], -k * 1.4 / 2, 1e-9 * k);
}

TEST(PointLoadList, JoinsPartsInOrderAndSendsEachPointToItsOwnPart)
{
  // two contact sets on one box as the parts (the pass joins the needle's points and the
  // suture's contacts the same way): offsets, points and forces pass through unchanged
  const Box               box;
  const std::vector<Vec3> a{{0.003, 0.004, top - 2e-5}}, b{{0.006, 0.004, top - 4e-5}, {0.004, 0.006, top - 6e-5}};
  SutureContact           first(SutureContactParameters{k, r, depth}, box.surface.triangles, box.mesh.vertices);
  SutureContact           second(SutureContactParameters{k, r, depth}, box.surface.triangles, box.mesh.vertices);
  first.set_suture(&a);
  second.set_suture(&b);
  ASSERT_TRUE(first.detect(box.mesh.vertices, a, {0}));
  ASSERT_TRUE(second.detect(box.mesh.vertices, b, {0, 0}));
  suturesim::tissue::PointLoadList list;
  list.set({&first, &second});
  ASSERT_EQ(list.points().size(), 3u);
  EXPECT_EQ(list.offset(0), 0u);
  EXPECT_EQ(list.offset(1), 1u);
  const std::vector<std::pair<const SutureContact *, std::size_t>> owner{{&first, 0}, {&second, 0}, {&second, 1}};
  for (std::size_t p = 0; p < 3; ++p)
    {
      dealii::Tensor<1, 3> f, g;
      dealii::Tensor<2, 3> df, dg;
      list.force(p, list.points()[p], f, df);
      owner[p].first->force(owner[p].second, owner[p].first->points()[owner[p].second], g, dg);
      EXPECT_EQ(list.points()[p], owner[p].first->points()[owner[p].second]);
      EXPECT_GT(f.norm(), 0);
      EXPECT_EQ(f, g) << "point " << p;
      EXPECT_EQ(df, dg) << "point " << p;
    }
}
