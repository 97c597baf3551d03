#include <suturesim/rod/block_tridiagonal.h>

namespace suturesim::rod
{
  void
  BlockTridiagonal::reset(const std::size_t n)
  {
    diag.resize(n);
    up.resize(n - 1);
    low.resize(n - 1);
    for (auto *blocks : {&diag, &up, &low})
      for (auto &b : *blocks)
        b.setZero();
  }

  void
  BlockTridiagonal::add_pair(const std::size_t i, const Eigen::Matrix<double, 12, 12> &m)
  {
    diag[i] += m.topLeftCorner<6, 6>();
    diag[i + 1] += m.bottomRightCorner<6, 6>();
    up[i] += m.topRightCorner<6, 6>();
    low[i] += m.bottomLeftCorner<6, 6>();
  }

  void
  BlockTridiagonal::constrain(const std::size_t i, const unsigned c)
  {
    const std::size_t n = size();
    diag[i].row(c).setZero();
    diag[i].col(c).setZero();
    diag[i](c, c) = 1;
    if (i + 1 < n)
      {
        up[i].row(c).setZero();
        low[i].col(c).setZero();
      }
    if (i > 0)
      {
        low[i - 1].row(c).setZero();
        up[i - 1].col(c).setZero();
      }
  }

  void
  BlockTridiagonal::factorize()
  {
    const std::size_t n = size();
    lu.resize(n);
    C.resize(n);
    y.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      {
        Block D = diag[i];
        if (i > 0)
          D -= low[i - 1] * C[i - 1];
        lu[i].compute(D);
        if (i + 1 < n)
          C[i] = lu[i].solve(up[i]);
      }
  }

  Eigen::VectorXd
  BlockTridiagonal::solve(const Eigen::VectorXd &b)
  {
    const std::size_t n = size();
    Eigen::VectorXd   x(6 * n);
    for (std::size_t i = 0; i < n; ++i)
      {
        Vector rhs = b.segment<6>(6 * i);
        if (i > 0)
          rhs -= low[i - 1] * y[i - 1];
        y[i] = lu[i].solve(rhs);
      }
    x.segment<6>(6 * (n - 1)) = y[n - 1];
    for (std::size_t i = n - 1; i-- > 0;)
      x.segment<6>(6 * i) = y[i] - C[i] * x.segment<6>(6 * (i + 1));
    return x;
  }

  Eigen::MatrixXd
  BlockTridiagonal::dense() const
  {
    const std::size_t n = size();
    Eigen::MatrixXd   A = Eigen::MatrixXd::Zero(6 * n, 6 * n);
    for (std::size_t i = 0; i < n; ++i)
      {
        A.block<6, 6>(6 * i, 6 * i) += diag[i];
        if (i + 1 < n)
          {
            A.block<6, 6>(6 * i, 6 * i + 6) += up[i];
            A.block<6, 6>(6 * i + 6, 6 * i) += low[i];
          }
      }
    return A;
  }

  void
  BlockTridiagonal::append_nonzeros(std::vector<Eigen::Triplet<double>> &t) const
  {
    const auto add_block = [&](const std::size_t a, const std::size_t b, const Block &m) {
      for (int i = 0; i < 6; ++i)
        for (int j = 0; j < 6; ++j)
          if (m(i, j) != 0)
            t.emplace_back(6 * a + i, 6 * b + j, m(i, j));
    };
    const std::size_t n = size();
    for (std::size_t i = 0; i < n; ++i)
      {
        add_block(i, i, diag[i]);
        if (i + 1 < n)
          {
            add_block(i, i + 1, up[i]);
            add_block(i + 1, i, low[i]);
          }
      }
  }
} // namespace suturesim::rod
