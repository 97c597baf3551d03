// The composite centroid rule on triangles (mesh::subtriangle_centroids) that turns the
// realtime tractions into consistent nodal loads (Realtime/Traction subdivision).
#include <suturesim/mesh/simplex_mesh.h>

#include <gtest/gtest.h>

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
