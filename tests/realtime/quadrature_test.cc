// The composite centroid rule on triangles (mesh::subtriangle_centroids) that turns the
// realtime tractions into consistent nodal loads (Realtime/Traction subdivision).
#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/mesh/spread_kernel.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using suturesim::mesh::subtriangle_centroids;

TEST(TriangleRule, WeightsSumToOneAndLinearFunctionsAreExact)
{
  for (const unsigned n : {1u, 2u, 3u, 6u, 16u})
    {
      const auto rule = subtriangle_centroids(n);
      ASSERT_EQ(rule.size(), n * n);
      double w = 0, first = 0;
      for (const auto &q : rule)
        {
          w += q.weight;
          first += q.weight * q.barycentric[1];
          for (const double l : q.barycentric)
            EXPECT_TRUE(l > 0 && l < 1) << "a point outside the triangle, n = " << n;
        }
      // ∫ λ₁ dA / A = 1/3 (a linear function: exact for every n)
      EXPECT_NEAR(w, 1.0, 1e-14);
      EXPECT_NEAR(first, 1.0 / 3, 1e-14);
    }
  EXPECT_THROW(subtriangle_centroids(0), std::invalid_argument);
}

TEST(TriangleRule, ConsistentLoadOfALinearTractionConvergesAtSecondOrder)
{
  // on the reference triangle, t = λ₁: f₁ = ∫ λ₁ N₁ dA / A = ∫ λ₁² dA / A = 1/6 and
  // f₂ = ∫ λ₁ λ₂ dA / A = 1/12 (the mass matrix of the linear triangle); the centroid
  // rule on n² sub-triangles is off by O(n⁻²)
  double previous = 0;
  for (const unsigned n : {2u, 4u, 8u, 16u})
    {
      double f1 = 0, f2 = 0;
      for (const auto &q : subtriangle_centroids(n))
        {
          f1 += q.weight * q.barycentric[1] * q.barycentric[1];
          f2 += q.weight * q.barycentric[1] * q.barycentric[2];
        }
      const double error = std::abs(f1 - 1.0 / 6) + std::abs(f2 - 1.0 / 12);
      if (previous > 0)
        {
          const double order = std::log2(previous / error);
          std::printf("[ triangle rule ] n = %2u: error %.3e, order %.3f\n", n, error, order);
          EXPECT_NEAR(order, 2.0, 0.05);
        }
      previous = error;
    }
}

TEST(TriangleRule, AJumpIsSampledInProportionToTheAreas)
{
  // a traction that is 1 where λ₁ > 1/2 (a corner triangle of a quarter of the area)
  // and 0 elsewhere, as the edge of a pressure patch that crosses a triangle: the
  // centroid alone (n = 1) sees none of it, the composite rule its area
  const auto loaded = [](const unsigned n) {
    double a = 0;
    for (const auto &q : subtriangle_centroids(n))
      a += q.barycentric[1] > 0.5 ? q.weight : 0;
    return a;
  };
  EXPECT_EQ(loaded(1), 0.0);
  EXPECT_NEAR(loaded(6), 0.25, 0.25 / 6);
  EXPECT_NEAR(loaded(16), 0.25, 0.25 / 16);
}

TEST(SpreadWeights, APartitionOfUnityWithinTheRadiusWeightedByMassAndCentredOnASymmetricGrid)
{
  // the realtime path's nodal rule for a spread pierce load (mesh/spread_kernel.h): a
  // 9 x 9 x 9 grid of 1 mm, the point at its centre node, radius 2.5 mm
  const double    a = 1e-3, rho = 2.5e-3;
  Eigen::Matrix3Xd X(3, 729);
  for (int k = 0, n = 0; k < 9; ++k)
    for (int j = 0; j < 9; ++j)
      for (int i = 0; i < 9; ++i, ++n)
        X.col(n) = a * Eigen::Vector3d(i, j, k);
  Eigen::VectorXd mass = Eigen::VectorXd::Constant(729, 1e-6);
  const Eigen::Vector3d centre = 4 * a * Eigen::Vector3d::Ones();
  const std::uint32_t   middle = 4 + 9 * (4 + 9 * 4), right = middle + 1;
  std::vector<std::uint32_t> nodes;
  std::vector<double>        weights;
  ASSERT_TRUE(suturesim::mesh::spread_weights(X, mass, 0, 729, centre, rho, nodes, weights));
  double          sum = 0;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (std::size_t j = 0; j < nodes.size(); ++j)
    {
      EXPECT_LT((X.col(nodes[j]) - centre).norm(), rho);
      sum += weights[j];
      mean += weights[j] * X.col(nodes[j]);
    }
  // nodes within 2.5 mm of a node of a 1 mm grid: 1 + 6 + 12 + 8 + 6 + 24 + 24 = 81
  EXPECT_EQ(nodes.size(), 81u);
  EXPECT_NEAR(sum, 1, 1e-14);
  EXPECT_LT((mean - centre).norm(), 1e-15); // the grid's symmetry: a linear field reproduced
  const auto weight_of = [&](const std::uint32_t node) {
    const auto at = std::find(nodes.begin(), nodes.end(), node);
    return at == nodes.end() ? 0.0 : weights[at - nodes.begin()];
  };
  EXPECT_NEAR(weight_of(right) / weight_of(middle), suturesim::mesh::spread_kernel(a / rho), 1e-14);
  EXPECT_NEAR(suturesim::mesh::spread_kernel(a / rho), (1 - 0.16) * (1 - 0.16), 1e-15);
  // twice the mass, twice the weight of its mirror image; only the nodes of the range
  mass[right] *= 2;
  nodes.clear();
  weights.clear();
  ASSERT_TRUE(suturesim::mesh::spread_weights(X, mass, middle, 729, centre, rho, nodes, weights));
  EXPECT_NEAR(weight_of(right) / weight_of(middle + 9 * 9), 2, 1e-14); // vs. one layer up
  EXPECT_EQ(weight_of(middle - 1), 0.0);
  // no node within the radius: nothing appended
  nodes.clear();
  weights.clear();
  EXPECT_FALSE(suturesim::mesh::spread_weights(X, mass, 0, 729, Eigen::Vector3d(1, 1, 1), rho, nodes, weights));
  EXPECT_TRUE(nodes.empty() && weights.empty());
}
