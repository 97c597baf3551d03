// The block-tridiagonal LU of the rod's Newton solve (rod/block_tridiagonal.h) against a
// dense LU of the same matrix on random systems.
//
// Tolerances: both solves are backward stable, so their solutions differ by about
// κ(A) ε (Higham, "Accuracy and Stability of Numerical Algorithms", 2nd ed. 2002,
// §7.1 and §9.3) times a modest growth factor. Each test asserts κ(A) < 100, so the
// relative difference 1e-12 leaves a factor of more than 40 over κ ε for growth; the
// residual ‖Ax − b‖ / (‖A‖ ‖x‖) of a backward-stable solve is a few ε, checked at 1e-13.
#include <suturesim/rod/block_tridiagonal.h>

#include <Eigen/LU>
#include <Eigen/SVD>
#include <Eigen/SparseCore>

#include <gtest/gtest.h>

#include <random>

using namespace suturesim::rod;

namespace
{
  std::mt19937 rng(2024);

  Mat6
  random_block(const double scale)
  {
    std::uniform_real_distribution<double> u(-scale, scale);
    Mat6 m;
    for (int i = 0; i < 6; ++i)
      for (int j = 0; j < 6; ++j)
        m(i, j) = u(rng);
    return m;
  }

  Eigen::VectorXd
  random_vector(const std::size_t n)
  {
    std::uniform_real_distribution<double> u(-1, 1);
    Eigen::VectorXd v(n);
    for (auto &x : v)
      x = u(rng);
    return v;
  }

  double
  condition_number(const Eigen::MatrixXd &A)
  {
    const Eigen::BDCSVD<Eigen::MatrixXd> svd(A);
    return svd.singularValues()(0) / svd.singularValues()(svd.singularValues().size() - 1);
  }

  /// Solves A x = b with the blocks and densely; checks κ(A), the agreement and the residual.
  void
  expect_solves_like_dense(BlockTridiagonal &A, const Eigen::VectorXd &b)
  {
    const Eigen::MatrixXd dense = A.dense();
    ASSERT_LT(condition_number(dense), 100) << "the stated tolerance assumes κ(A) < 100";
    A.factorize();
    const Eigen::VectorXd x         = A.solve(b);
    const Eigen::VectorXd reference = dense.partialPivLu().solve(b);
    EXPECT_LT((x - reference).norm(), 1e-12 * reference.norm()) << "n = " << A.size();
    EXPECT_LT((dense * x - b).norm(), 1e-13 * dense.norm() * x.norm()) << "n = " << A.size();
  }
} // namespace

TEST(BlockTridiagonal, RandomDiagonallyDominantSystemsMatchADenseSolve)
{
  for (const std::size_t n : {1, 2, 3, 10, 60})
    {
      BlockTridiagonal A;
      A.reset(n);
      for (std::size_t i = 0; i < n; ++i)
        {
          A.diagonal(i) = random_block(1);
          if (i + 1 < n)
            {
              A.upper(i) = random_block(1);
              A.lower(i) = random_block(1);
            }
        }
      // strict row diagonal dominance by a margin of 1 on the scalar matrix
      const Eigen::MatrixXd dense = A.dense();
      for (std::size_t i = 0; i < n; ++i)
        for (int c = 0; c < 6; ++c)
          {
            const auto row = dense.row(6 * i + c);
            A.diagonal(i)(c, c) = row.cwiseAbs().sum() - std::abs(row(6 * i + c)) + 1;
          }
      expect_solves_like_dense(A, random_vector(6 * n));
    }
}

TEST(BlockTridiagonal, PivotsWithinBlocksWhoseDiagonalIsZero)
{
  // D_i = 4 P (a cyclic permutation, zero diagonal) plus noise: D̃_i needs row exchanges,
  // which the block LU makes inside each block; ‖D_i⁻¹‖ (‖L‖ + ‖U‖) < 1 keeps the
  // elimination across blocks stable without them.
  Mat6 P = Mat6::Zero();
  for (int i = 0; i < 6; ++i)
    P(i, (i + 1) % 6) = 4;
  const std::size_t n = 20;
  BlockTridiagonal  A;
  A.reset(n);
  for (std::size_t i = 0; i < n; ++i)
    {
      A.diagonal(i) = P + random_block(0.05);
      if (i + 1 < n)
        {
          A.upper(i) = random_block(0.1);
          A.lower(i) = random_block(0.1);
        }
    }
  for (std::size_t i = 0; i < n; ++i)
    ASSERT_LT(A.diagonal(i).diagonal().cwiseAbs().maxCoeff(), 0.05);
  expect_solves_like_dense(A, random_vector(6 * n));
}

TEST(BlockTridiagonal, ConstrainedComponentsDecoupleWithUnitRows)
{
  const std::size_t n = 8;
  BlockTridiagonal  A;
  A.reset(n);
  for (std::size_t i = 0; i < n; ++i)
    {
      A.diagonal(i) = random_block(0.3) + 6 * Mat6::Identity();
      if (i + 1 < n)
        {
          A.upper(i) = random_block(0.3);
          A.lower(i) = random_block(0.3);
        }
    }
  // the ends held in translation, a middle node in one rotation (the rod's supports)
  const std::vector<std::pair<std::size_t, unsigned>> fixed{{0, 0}, {0, 1}, {0, 2}, {4, 5}, {7, 0}, {7, 1}, {7, 2}};
  for (const auto &[i, c] : fixed)
    A.constrain(i, c);
  const Eigen::MatrixXd dense = A.dense();
  for (const auto &[i, c] : fixed)
    {
      const Eigen::Index k = 6 * i + c;
      EXPECT_EQ(dense.row(k), Eigen::RowVectorXd::Unit(6 * n, k));
      EXPECT_EQ(dense.col(k), Eigen::VectorXd::Unit(6 * n, k));
    }
  const Eigen::VectorXd b = random_vector(6 * n);
  expect_solves_like_dense(A, b);
  const Eigen::VectorXd x = A.solve(b);
  for (const auto &[i, c] : fixed)
    EXPECT_NEAR(x[6 * i + c], b[6 * i + c], 1e-15);
}

TEST(BlockTridiagonal, ElementPairsAndNonzerosAssembleTheSameMatrix)
{
  // add_pair() puts a two-node element's 12 × 12 tangent on block rows e, e + 1;
  // append_nonzeros() lists exactly the nonzero entries of dense().
  const std::size_t n = 5;
  BlockTridiagonal  A;
  A.reset(n);
  Eigen::MatrixXd expected = Eigen::MatrixXd::Zero(6 * n, 6 * n);
  std::uniform_real_distribution<double> u(-1, 1);
  for (std::size_t e = 0; e + 1 < n; ++e)
    {
      Eigen::Matrix<double, 12, 12> m;
      for (auto &v : m.reshaped())
        v = u(rng);
      m(3, 4) = 0; // a zero entry, which append_nonzeros() leaves out
      A.add_pair(e, m);
      expected.block<12, 12>(6 * e, 6 * e) += m;
    }
  EXPECT_EQ(A.dense(), expected);

  std::vector<Eigen::Triplet<double>> triplets;
  A.append_nonzeros(triplets);
  EXPECT_EQ(static_cast<Eigen::Index>(triplets.size()), (expected.array() != 0).count());
  Eigen::SparseMatrix<double> sparse(6 * n, 6 * n);
  sparse.setFromTriplets(triplets.begin(), triplets.end());
  EXPECT_EQ(Eigen::MatrixXd(sparse), expected);
}
