#include <suturesim/rod/rotation.h>

#include <array>
#include <cmath>

namespace suturesim::rod
{
  namespace
  {
    // Coefficients of asin(√s)/√s = Σ a_n sⁿ, a_n = (2n)!/(4ⁿ (n!)² (2n+1)).
    constexpr int n_terms = 12;
    std::array<double, n_terms>
    series_coefficients()
    {
      std::array<double, n_terms> a{};
      double                      c = 1; // (2n)!/(4ⁿ (n!)²)
      for (int n = 0; n < n_terms; ++n)
        {
          if (n > 0)
            c *= (2.0 * n - 1) / (2.0 * n);
          a[n] = c / (2 * n + 1);
        }
      return a;
    }
  } // namespace

  LogFactor
  log_factor(const double s)
  {
    static const std::array<double, n_terms> a = series_coefficients();
    if (s <= 0.01)
      {
        // the closed forms below cancel for small s (r³F' is a difference of O(r)
        // terms); below s = 0.01 the series converges like 0.01ⁿ, 12 terms reach
        // round-off, and the closed forms lose at most ~1e-13 relative above it
        double F = 0, dF = 0, d2F = 0;
        for (int n = n_terms - 1; n >= 0; --n)
          {
            F = F * s + a[n];
            if (n >= 1)
              dF = dF * s + n * a[n];
            if (n >= 2)
              d2F = d2F * s + n * (n - 1.0) * a[n];
          }
        return {2 * F, 2 * dF, 2 * d2F};
      }
    const double r = std::sqrt(s), A = std::asin(r), root = std::sqrt(1 - s);
    const double P = r / root - A; // r³ F'(s) = P
    return {2 * A / r, P / (r * r * r), (r * r * r / (root * root * root) - 3 * P) / (2 * std::pow(r, 5))};
  }
} // namespace suturesim::rod
