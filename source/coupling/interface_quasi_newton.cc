#include <suturesim/coupling/interface_quasi_newton.h>

#include <Eigen/QR>

#include <algorithm>
#include <stdexcept>

namespace suturesim::coupling
{
  double
  InterfaceQuasiNewton::update(Eigen::VectorXd &x, const Eigen::VectorXd &target)
  {
    if (x.size() != target.size() || x.size() % 3 != 0)
      throw std::invalid_argument("interface quasi-Newton: x and H(x) must have the same size, 3 per point");
    if (!residuals.empty() && residuals.back().size() != x.size())
      reset();
    const Eigen::VectorXd r       = target - x;
    double                largest = 0;
    for (Eigen::Index k = 0; k < r.size(); k += 3)
      largest = std::max(largest, r.segment<3>(k).norm());
    residuals.push_back(r);
    targets.push_back(target);
    // at most as many differences as unknowns: more are dependent anyway
    while (residuals.size() > static_cast<std::size_t>(x.size()) + 1)
      {
        residuals.erase(residuals.begin());
        targets.erase(targets.begin());
      }
    if (residuals.size() == 1)
      {
        x += omega * r;
        return largest;
      }
    // newest differences first, so that dropping a dependent column drops an old one
    for (;;)
      {
        const std::size_t m = residuals.size() - 1;
        Eigen::MatrixXd   V(x.size(), m), W(x.size(), m);
        for (std::size_t j = 0; j < m; ++j)
          {
            const std::size_t i = residuals.size() - 1 - j;
            V.col(j)             = residuals.back() - residuals[i - 1];
            W.col(j)             = targets.back() - targets[i - 1];
          }
        const Eigen::HouseholderQR<Eigen::MatrixXd> qr(V);
        const Eigen::MatrixXd                        R = qr.matrixQR().topRows(m).triangularView<Eigen::Upper>();
        double                                       big = 0;
        for (std::size_t j = 0; j < m; ++j)
          big = std::max(big, std::abs(R(j, j)));
        std::size_t weak = m;
        for (std::size_t j = 0; j < m; ++j)
          if (std::abs(R(j, j)) <= 1e-10 * big)
            weak = j;
        if (weak < m && m > 1)
          {
            // the column j pairs the newest with the (m − j)-th oldest: drop that one
            const std::size_t i = residuals.size() - 1 - weak - 1;
            residuals.erase(residuals.begin() + i);
            targets.erase(targets.begin() + i);
            continue;
          }
        if (big == 0)
          {
            x += omega * r;
            return largest;
          }
        const Eigen::VectorXd c = qr.solve(Eigen::VectorXd(-r));
        x                       = target + W * c;
        return largest;
      }
  }
} // namespace suturesim::coupling
