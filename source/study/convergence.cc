#include <suturesim/study/convergence.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace suturesim::study
{
  ConvergenceEstimate
  estimate_convergence(std::vector<double> h, std::vector<double> f)
  {
    if (h.size() != f.size() || h.size() < 3)
      throw std::invalid_argument("a convergence estimate needs three (h, f) pairs or more");
    std::vector<std::size_t> order(h.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](auto a, auto b) { return h[a] < h[b]; });
    const double h1 = h[order[0]], h2 = h[order[1]], h3 = h[order[2]];
    const double f1 = f[order[0]], f2 = f[order[1]], f3 = f[order[2]];
    if (!(h1 > 0) || !(h2 > h1) || !(h3 > h2))
      throw std::invalid_argument("a convergence estimate needs three distinct positive sizes");

    ConvergenceEstimate e;
    const double        r21 = h2 / h1, r32 = h3 / h2, e21 = f2 - f1, e32 = f3 - f2;
    if (e21 == 0 || e32 == 0)
      {
        e.converged    = false;
        e.extrapolated = f1;
        return e;
      }
    const double s = e32 / e21 > 0 ? 1.0 : -1.0;
    e.oscillatory  = s < 0;
    double p       = std::abs(std::log(std::abs(e32 / e21))) / std::log(r21);
    bool settled = false;
    for (int it = 0; it < 100 && !settled; ++it)
      {
        const double q    = std::log((std::pow(r21, p) - s) / (std::pow(r32, p) - s));
        const double next = std::abs(std::log(std::abs(e32 / e21)) + q) / std::log(r21);
        if (!std::isfinite(next))
          break;
        settled = std::abs(next - p) < 1e-12 * std::max(1.0, p);
        p       = next;
      }
    e.converged = settled;
    e.diverging = std::log(std::abs(e32 / e21)) + std::log((std::pow(r21, p) - s) / (std::pow(r32, p) - s)) < 0;
    const double rp = std::pow(r21, p);
    e.order         = p;
    e.extrapolated  = (rp * f1 - f2) / (rp - 1);
    e.gci_fine      = 1.25 * std::abs((f1 - f2) / f1) / (rp - 1);
    return e;
  }
} // namespace suturesim::study
