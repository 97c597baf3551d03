#pragma once
/**
 * @file
 * A block-tridiagonal matrix of 6 × 6 blocks and its block LU factorisation: the linear
 * solve of a Newton iteration of an open Cosserat rod (rod_model.h), whose Jacobian
 * couples each node's six unknowns (Δx, θ) only with its two neighbours'.
 *
 * The matrix, n block rows,
 *   A = tridiag(L_{i−1}, D_i, U_i),  D_i = A_{i,i},  U_i = A_{i,i+1},  L_i = A_{i+1,i},
 * is factorised by block Gaussian elimination without pivoting between blocks (the
 * block form of the Thomas algorithm; Golub & Van Loan, "Matrix Computations", 4th ed.
 * 2013, §4.5.1):
 *   D̃_0 = D_0,   D̃_i = D_i − L_{i−1} C_{i−1},   C_i = D̃_i⁻¹ U_i,
 * each D̃_i by LU with partial pivoting within the block; a solve of A x = b is then
 *   y_0 = D̃_0⁻¹ b_0,   y_i = D̃_i⁻¹ (b_i − L_{i−1} y_{i−1}),
 *   x_{n−1} = y_{n−1},  x_i = y_i − C_i x_{i+1}.
 * O(n) work and storage against O(n³) for a dense LU, and no fill-in. Without pivoting
 * across blocks the elimination needs every D̃_i regular; it is stable when A is
 * block diagonally dominant (ibid. §4.5.2) or symmetric positive definite. A rod's
 * Jacobian is the Hessian of its energy plus terms of the order of its residual and
 * loads (rod_model.h), close to the latter near a stable equilibrium. A singular D̃_i is
 * not detected here (the rod's Newton solve checks its correction for NaN).
 */

#include <Eigen/Core>
#include <Eigen/LU>
#include <Eigen/SparseCore>

#include <cstddef>
#include <vector>

namespace suturesim::rod
{
  using Mat6 = Eigen::Matrix<double, 6, 6>;

  class BlockTridiagonal
  {
  public:
    using Block  = Mat6;
    using Vector = Eigen::Matrix<double, 6, 1>;

    /// Makes the matrix n × n blocks (n ≥ 1), all zero.
    void
    reset(std::size_t n);

    /// Number of block rows n.
    std::size_t
    size() const
    {
      return diag.size();
    }

    /// D_i = A_{i,i}.
    Block &
    diagonal(std::size_t i)
    {
      return diag[i];
    }
    const Block &
    diagonal(std::size_t i) const
    {
      return diag[i];
    }
    /// U_i = A_{i,i+1}, i < n − 1.
    Block &
    upper(std::size_t i)
    {
      return up[i];
    }
    const Block &
    upper(std::size_t i) const
    {
      return up[i];
    }
    /// L_i = A_{i+1,i}, i < n − 1.
    Block &
    lower(std::size_t i)
    {
      return low[i];
    }
    const Block &
    lower(std::size_t i) const
    {
      return low[i];
    }

    /// Adds the 12 × 12 matrix @p m coupling block rows i and i + 1 (a two-node
    /// element's tangent): its quadrants go to D_i, D_{i+1}, U_i and L_i.
    void
    add_pair(std::size_t i, const Eigen::Matrix<double, 12, 12> &m);

    /// Replaces row and column @p component of block row @p i by those of the identity
    /// (a constrained unknown: its equation decouples, x = b there).
    void
    constrain(std::size_t i, unsigned component);

    /// The block LU factorisation of the current blocks (see the file's description).
    void
    factorize();

    /// x = A⁻¹ b (6 n entries) with the last factorize(). Not const: it reuses a work
    /// vector, so that Newton iterations do not allocate.
    Eigen::VectorXd
    solve(const Eigen::VectorXd &b);

    /// A as a dense matrix (tests; O(n²) memory).
    Eigen::MatrixXd
    dense() const;

    /// Appends the nonzero entries of A to @p triplets, block row by block row (D_i,
    /// U_i, L_i), for a sparse matrix that adds couplings beyond the neighbours.
    void
    append_nonzeros(std::vector<Eigen::Triplet<double>> &triplets) const;

  private:
    std::vector<Block> diag, up, low;
    // the factorisation: LU of each D̃_i and C_i = D̃_i⁻¹ U_i; y of the forward sweep
    std::vector<Eigen::PartialPivLU<Block>> lu;
    std::vector<Block>                      C;
    std::vector<Vector>                     y;
  };
} // namespace suturesim::rod
