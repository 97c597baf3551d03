// Implicit dynamics through SUNDIALS IDA against the closed-form response of a fixed-free
// bar to suddenly applied axial gravity (tests/data/bar_dynamics.prm):
//   u(x, t) = Σ b_n sin(k_n x) (1 − cos ω_n t),  k_n = (2n − 1)π/(2L),  ω_n = c k_n,
//   b_n = (2/L) ∫₀ᴸ u_s(x) sin(k_n x) dx = 2 ρ g / (E L k_n³),
// the modal expansion of the static solution u_s = ρg/E (Lx − x²/2) (wave equation,
// e.g. Graff, Wave Motion in Elastic Solids, §2.1). Tip: sin(k_n L) = (−1)^(n+1).
#include "run_scene.h"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <complex>
#include <cstdio>

using namespace suturesim::test_support;

namespace
{
  double
  tip_series(const double t)
  {
    const double L = 0.08, rho = 1000, g = 10, E = 2e5, c = std::sqrt(E / rho);
    double       u = 0;
    for (int n = 1; n <= 2000; ++n)
      {
        const double k = (2 * n - 1) * M_PI / (2 * L);
        const double b = 2 * rho * g / (E * L * k * k * k);
        u += b * ((n % 2) ? 1.0 : -1.0) * (1 - std::cos(c * k * t));
      }
    return u;
  }
} // namespace

TEST(Dynamics, BarUnderSuddenGravityFollowsTheWaveEquation)
{
  const auto r = run_suturesim("bar_dynamics", {source_path("tests/data/bar_dynamics.prm")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ASSERT_EQ(r.summary["solver"]["integrator"], "ida");

  // forces.csv holds the tip history at every output time.
  std::string header;
  const auto  history = read_forces(r, &header);
  ASSERT_NE(header.find("tip_displacement_x [m]"), std::string::npos) << header;
  // columns: time, 3 reaction components of the fixed face, 3 tip components
  const double static_tip = 1000 * 10 * 0.08 * 0.08 / (2 * 2e5);
  unsigned     rows = 0;
  double       max_error = 0, peak = 0;
  for (const auto &v : history)
    {
      ASSERT_EQ(v.size(), 7u);
      max_error = std::max(max_error, std::abs(v[4] - tip_series(v[0])));
      peak      = std::max(peak, v[4]);
      ++rows;
    }
  EXPECT_GE(rows, 30u);
  // The series' peak is 2 u_s at t = T/2 = 11.3 ms; the FE + BDF history stays within
  // 2 % of that peak over more than one period (8 Q2 elements resolve mode 1 to
  // < 0.1 %; the residual error is the dispersion of the higher modes of the load jump).
  EXPECT_NEAR(peak, 2 * static_tip, 0.02 * 2 * static_tip);
  EXPECT_LE(max_error, 0.02 * 2 * static_tip);
}

namespace
{
  /// Bar 0 < x < L with u(0, t) = u(L, t) = g(t) = A(ωt − sin ωt): u = g + Σ q_n sin(nπx/L),
  /// q̈_n + ω_n² q_n = −c_n g̈, c_n = 4/(nπ) (odd n), q_n(0) = q̇_n(0) = 0, so
  /// q_n = −c_n A ω² (sin ωt − (ω/ω_n) sin ω_n t) / (ω_n² − ω²). Returns the elastic part
  /// w(L/2, t) and the sum of the support forces ρ a [L g̈ + Σ q̈_n 2L/(nπ)] (a: section).
  std::pair<double, double>
  driven_bar(const double t)
  {
    const double L = 0.08, rho = 1000, E = 2e5, c = std::sqrt(E / rho), a = 1e-4;
    const double A = 1e-4, w = 300;
    double       mid = 0, inertia = L * A * w * w * std::sin(w * t);
    for (int n = 1; n < 4000; n += 2)
      {
        const double wn = n * M_PI * c / L, cn = 4 / (n * M_PI);
        const double k  = -cn * A * w * w / (wn * wn - w * w);
        mid += k * (std::sin(w * t) - (w / wn) * std::sin(wn * t)) * ((n % 4 == 1) ? 1 : -1);
        inertia += k * (-w * w * std::sin(w * t) + w * wn * std::sin(wn * t)) * 2 * L / (n * M_PI);
      }
    return {mid, rho * a * inertia};
  }
} // namespace

TEST(Dynamics, BarDrivenAtBothEndsFollowsTheWaveEquation)
{
  const auto r = run_suturesim("bar_translation", {source_path("tests/data/bar_translation.prm")});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  // columns: time, boundary_0 R (3), boundary_1 R (3), middle u (3)
  const double A = 1e-4, w = 300;
  std::vector<std::array<double, 5>> rows; // t, w_fe, w_exact, R_fe, R_exact
  double max_w = 0, max_r = 0;
  for (const auto &v : read_forces(r))
    {
      ASSERT_EQ(v.size(), 10u);
      const double t        = v[0];
      const auto [mid, force] = driven_bar(t);
      rows.push_back({{t, v[7] - A * (w * t - std::sin(w * t)), mid, v[1] + v[4], force}});
      max_w = std::max(max_w, std::abs(mid));
      max_r = std::max(max_r, std::abs(force));
    }
  ASSERT_GE(rows.size(), 40u);
  for (const auto &row : rows)
    {
      // 16 Q2 elements resolve the modes that carry the response (ω_1 = 555 rad/s,
      // drive 300 rad/s). Measured: 1.0e-4 (w) and 4.0e-4 (reactions) of the peaks.
      EXPECT_NEAR(row[1], row[2], 0.002 * max_w) << "t = " << row[0];
      EXPECT_NEAR(row[3], row[4], 0.005 * max_r) << "t = " << row[0];
    }
}

namespace
{
  /// The same bar and load with Rayleigh damping C = a_M M + a_K K (a fixed-free bar's
  /// modes are orthogonal under both, so each mode keeps its own equation)
  ///   q̈_n + (a_M + a_K ω_n²) q̇_n + ω_n² q_n = ω_n² b_n,  q_n(0) = q̇_n(0) = 0,
  /// whose step response is q_n = b_n [1 + (s₂ e^{s₁t} − s₁ e^{s₂t}) / (s₁ − s₂)] with
  /// s₁,₂ the roots of s² + (a_M + a_K ω²) s + ω² (complex when under-damped: then
  /// 1 − e^{−ζωt}(cos ω_D t + ζ/√(1−ζ²) sin ω_D t), ζ = a_M/(2ω) + a_K ω/2; Chopra,
  /// Dynamics of Structures, §4.3 and §11.4).
  double
  damped_tip_series(const double t, const double a_M, const double a_K)
  {
    const double L = 0.08, rho = 1000, g = 10, E = 2e5, c = std::sqrt(E / rho);
    double       u = 0;
    for (int n = 1; n <= 2000; ++n)
      {
        const double               k = (2 * n - 1) * M_PI / (2 * L), w = c * k;
        const double               b = 2 * rho * g / (E * L * k * k * k);
        const double               damping = a_M + a_K * w * w;
        const std::complex<double> root  = std::sqrt(std::complex<double>(damping * damping - 4 * w * w, 0));
        const std::complex<double> s1    = 0.5 * (-damping + root), s2 = 0.5 * (-damping - root);
        const double               q = b * (1.0 + (s2 * std::exp(s1 * t) - s1 * std::exp(s2 * t)) / (s1 - s2)).real();
        u += q * ((n % 2) ? 1.0 : -1.0);
      }
    return u;
  }
} // namespace

TEST(Dynamics, RayleighDampingDecaysTheBarsModesAtTheirModalRates)
{
  // tests/data/bar_dynamics.prm with damping: mass-proportional a_M = 100 1/s (every
  // mode's amplitude falls as e^{−a_M t/2}, to 0.22 by 30 ms), then stiffness-
  // proportional a_K = 5e-4 s (ζ₁ = a_K ω₁/2 = 0.069; the higher modes more, beyond
  // ω = 2/a_K = 4e3 rad/s over-damped). The FE + IDA histories follow the damped
  // series to 1 % of the undamped peak 2 u_s (measured 0.47 % and 0.65 %, 2026-11-25: the
  // 8 Q2 elements' dispersion, as undamped); the undamped series misses them by 34 %
  // and 17 %, so the damping's closed form is what is met.
  const double static_tip = 1000 * 10 * 0.08 * 0.08 / (2 * 2e5);
  unsigned     runs       = 0;
  for (const auto &[a_M, a_K] : std::vector<std::pair<double, double>>{{100, 0}, {0, 5e-4}})
    {
      const auto r = run_suturesim("bar_rayleigh", {source_path("tests/data/bar_dynamics.prm"), "--set",
                                                    "Time/ida/Rayleigh mass coefficient=" + std::to_string(a_M),
                                                    "--set",
                                                    "Time/ida/Rayleigh stiffness coefficient=" + std::to_string(a_K)});
      ASSERT_EQ(r.exit_code, 0) << r.output;
      double   max_error = 0, max_undamped = 0;
      unsigned rows      = 0;
      for (const auto &v : read_forces(r))
        {
          ASSERT_EQ(v.size(), 7u);
          max_error    = std::max(max_error, std::abs(v[4] - damped_tip_series(v[0], a_M, a_K)));
          max_undamped = std::max(max_undamped, std::abs(v[4] - tip_series(v[0])));
          ++rows;
        }
      std::printf("[ Rayleigh ] a_M = %g 1/s, a_K = %g s: %u rows, max |u_FE - u_damped| = %.3e m, "
                  "max |u_FE - u_undamped| = %.3e m (static tip %.3e m)\n",
                  a_M, a_K, rows, max_error, max_undamped, static_tip);
      EXPECT_GE(rows, 30u);
      EXPECT_LE(max_error, 0.01 * 2 * static_tip) << "a_M = " << a_M << ", a_K = " << a_K;
      EXPECT_GT(max_undamped, 0.1 * 2 * static_tip) << "a_M = " << a_M << ", a_K = " << a_K;
      ++runs;
    }
  EXPECT_EQ(runs, 2u);
}
