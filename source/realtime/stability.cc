#include <suturesim/realtime/stability.h>

#include <Eigen/Eigenvalues>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace suturesim::realtime
{
  EigenvalueEstimate
  largest_eigenvalue(const System &system, const Matrix3Xd &x, const VectorXd &diagonal,
                     const double tolerance, const unsigned max_iterations)
  {
    const Eigen::Index n = x.cols();
    Matrix3Xd          scale(3, n);
    for (Eigen::Index i = 0; i < n; ++i)
      scale.col(i).setConstant(!system.nodes.held[i] && diagonal[i] > 0 ? 1 / std::sqrt(diagonal[i])
                                                                       : 0.0);
    const Eigen::Index dim = 3 * n;
    const auto as_matrix   = [&](const Eigen::VectorXd &v) {
      return Eigen::Map<const Matrix3Xd>(v.data(), 3, n);
    };
    Matrix3Xd  u(3, n), Ku(3, n);
    const auto apply = [&](const Eigen::VectorXd &v, Eigen::VectorXd &result) {
      u = as_matrix(v).cwiseProduct(scale);
      system.stiffness_product(x, u, Ku);
      Ku = Ku.cwiseProduct(scale);
      result = Eigen::Map<const Eigen::VectorXd>(Ku.data(), dim);
    };

    std::mt19937                           random(12345);
    std::uniform_real_distribution<double> uniform(-1, 1);
    Eigen::VectorXd                        q(dim);
    for (Eigen::Index k = 0; k < dim; ++k)
      q[k] = uniform(random) * scale.data()[k];
    EigenvalueEstimate estimate;
    if (q.norm() == 0)
      return estimate;
    q.normalize();

    std::vector<Eigen::VectorXd> basis{q};
    std::vector<double>          alpha, beta;
    Eigen::VectorXd              w(dim);
    const unsigned               m = std::min<unsigned>(max_iterations, dim);
    for (unsigned j = 0; j < m; ++j)
      {
        apply(basis[j], w);
        alpha.push_back(basis[j].dot(w));
        // full reorthogonalisation, twice (Gram–Schmidt is otherwise unstable)
        for (unsigned pass = 0; pass < 2; ++pass)
          for (const auto &b : basis)
            w -= b.dot(w) * b;
        const double b_next = w.norm();

        const Eigen::Index size = alpha.size();
        Eigen::VectorXd    d    = Eigen::Map<Eigen::VectorXd>(alpha.data(), size);
        Eigen::VectorXd    e    = size > 1 ? Eigen::VectorXd(Eigen::Map<Eigen::VectorXd>(beta.data(), size - 1))
                                           : Eigen::VectorXd();
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> tridiagonal;
        tridiagonal.computeFromTridiagonal(d, e);
        const double theta    = tridiagonal.eigenvalues()[size - 1];
        const double residual = std::abs(b_next * tridiagonal.eigenvectors()(size - 1, size - 1));
        estimate              = {theta, residual, j + 1};
        if (residual <= tolerance * std::abs(theta) || b_next < 1e-300)
          break;
        beta.push_back(b_next);
        basis.push_back(w / b_next);
      }
    return estimate;
  }

  double
  symplectic_euler_limit(const double omega, const double c)
  {
    if (omega <= 0)
      return std::numeric_limits<double>::infinity();
    const double limit = (std::sqrt(c * c + 4 * omega * omega) - c) / (omega * omega);
    return c > 0 ? std::min(limit, 2 / c) : limit;
  }
} // namespace suturesim::realtime
