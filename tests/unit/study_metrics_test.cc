// The study's error metrics (study/curve_metrics.h) and trade-off (study/pareto.h) on
// synthetic data whose answers are known in closed form.
#include <suturesim/study/convergence.h>
#include <suturesim/study/curve_metrics.h>
#include <suturesim/study/pareto.h>
#include <suturesim/study/reference_series.h>
#include <suturesim/study/surface_error.h>

#include "run_scene.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <stdexcept>

using namespace suturesim::study;

namespace
{
  Curve
  sampled(const double a, const double b, const std::size_t n, double (*f)(double))
  {
    Curve c;
    for (std::size_t k = 0; k <= n; ++k)
      {
        c.x.push_back(a + (b - a) * k / n);
        c.y.push_back(f(c.x.back()));
      }
    return c;
  }
} // namespace

TEST(StudyMetrics, CurveErrorsOfAConstantOffsetAndAScaledCurve)
{
  // r = 1 + x on [0, 2]; c = r + 0.1: ∫ 0.01 dx / ∫ (1 + x)² dx = 0.02 / (26/3), so
  // e₂ = sqrt(0.06/26); e∞ = 0.1/3; peak (3.1 − 3)/3.
  const Curve r = sampled(0, 2, 4, [](const double x) { return 1 + x; });
  // the candidate sampled elsewhere (7 pieces): interpolation of a line is exact
  const Curve c  = sampled(0, 2, 7, [](const double x) { return 1.1 + x; });
  const auto  e  = curve_errors(c, r, 0, 2);
  EXPECT_NEAR(e.relative_l2, std::sqrt(0.06 / 26), 1e-14);
  EXPECT_NEAR(e.relative_linf, 0.1 / 3, 1e-14);
  EXPECT_NEAR(e.peak, 0.1 / 3, 1e-14);

  // c = 0.8 r: every relative error is 0.2, the peak 20 % low
  const Curve low = sampled(0, 2, 3, [](const double x) { return 0.8 * (1 + x); });
  const auto  f   = curve_errors(low, r, 0.5, 1.5);
  EXPECT_NEAR(f.relative_l2, 0.2, 1e-14);
  EXPECT_NEAR(f.relative_linf, 0.2, 1e-14);
  EXPECT_NEAR(f.peak, -0.2 * 2.5 / 2.5, 1e-14);
}

TEST(StudyMetrics, L2IsExactForPiecewiseLinearCurvesSampledApart)
{
  // r = 1 on [0, 1] (samples at the ends only); c = h·hat, the hat of height 1 at 0.5
  // (samples 0, 0.5, 1): ∫ (c − r)² = ∫ (h·hat − 1)² = h²/3 − h + 1 (∫hat = 1/2,
  // ∫hat² = 1/3), ∫ r² = 1; a quadrature on the samples of one curve only would miss it.
  const double h = 3;
  Curve        r{{0, 1}, {1, 1}};
  Curve        c{{0, 0.5, 1}, {0, h, 0}};
  const auto   e = curve_errors(c, r, 0, 1);
  EXPECT_NEAR(e.relative_l2, std::sqrt(1 - h + h * h / 3), 1e-14);
  EXPECT_NEAR(e.relative_linf, h - 1, 1e-14);
  EXPECT_NEAR(e.peak, h - 1, 1e-14);
}

TEST(StudyMetrics, EventWarpAlignsPhasesSoThatAShiftedCurveHasNoError)
{
  // The reference rises on [1, 2] and falls on [2, 4]; the candidate does the same on
  // [1.5, 2.1] and [2.1, 3.0]: after the warp its phases coincide with the reference's.
  const auto shape = [](const double s, const int phase) { return phase == 0 ? s : 1 - 0.5 * s; };
  Curve      r, c;
  // both sampled at their events (the kinks), as runs record the step of an event
  for (int k = 0; k <= 60; ++k)
    {
      const double s = k / 60.0;
      r.x.push_back(1 + 3 * s);
      r.y.push_back(r.x.back() < 2 ? shape(r.x.back() - 1, 0) : shape((r.x.back() - 2) / 2, 1));
    }
  for (int k = 0; k <= 30; ++k)
    {
      const double x = 1.5 + 1.5 * k / 30.0;
      c.x.push_back(x);
      c.y.push_back(x < 2.1 ? shape((x - 1.5) / 0.6, 0) : shape((x - 2.1) / 0.9, 1));
    }
  const std::vector<double> ce{1.5, 2.1, 3.0}, re{1, 2, 4};
  const auto                phases = phase_errors(c, r, ce, re);
  ASSERT_EQ(phases.size(), 2u);
  for (const auto &p : phases)
    {
      EXPECT_LT(p.relative_l2, 1e-14);
      EXPECT_LT(p.relative_linf, 1e-14);
    }
  // without the warp the same curves differ
  EXPECT_GT(curve_errors(c, r, 1.5, 3.0).relative_l2, 0.1);
  EXPECT_THROW(warp_to_events(c, {1.5, 2.1}, re), std::invalid_argument);
  EXPECT_THROW(warp_to_events(c, {2.1, 1.5, 3.0}, re), std::invalid_argument);
}

TEST(StudyMetrics, RelativeErrorsRefuseAVanishingReference)
{
  EXPECT_DOUBLE_EQ(relative_error(4.47, 8.94), -0.5);
  EXPECT_THROW(relative_error(1, 0), std::invalid_argument);
  const Curve zero{{0, 1}, {0, 0}}, one{{0, 1}, {1, 1}};
  EXPECT_THROW(curve_errors(one, zero, 0, 1), std::invalid_argument);
  EXPECT_THROW(curve_errors(one, one, 0.5, 2), std::invalid_argument);
  EXPECT_THROW(curve_errors(one, one, 0.5, 0.5), std::invalid_argument);
}

TEST(StudyPareto, FrontOfASyntheticSetAgainstBruteForce)
{
  // A known set: (cost, error) with a front (1, 9), (2, 5), (4, 2), (8, 1); dominated
  // and failed cases around it.
  std::vector<TradeOff> cases{{4, 2},   {1, 9},   {3, 6},          {2, 5},  {8, 1},
                              {9, 1},   {2, 7},   {0.5, 0.1, false}, {5, 2}, {8, 1.5}};
  const auto front = pareto_front(cases);
  EXPECT_EQ(front, (std::vector<std::size_t>{1, 3, 0, 4}));
  EXPECT_EQ(cheapest_within(cases, 5.0), std::optional<std::size_t>(3));
  EXPECT_EQ(cheapest_within(cases, 1.0), std::optional<std::size_t>(4));
  EXPECT_FALSE(cheapest_within(cases, 0.5).has_value()) << "a failed case was chosen";

  // random sets: the front is exactly the completed cases no completed case dominates
  std::mt19937                           random(11);
  std::uniform_int_distribution<int>     value(0, 20);
  std::bernoulli_distribution            failed(0.1);
  std::size_t                            checked = 0;
  for (int trial = 0; trial < 200; ++trial)
    {
      std::vector<TradeOff> set;
      for (int i = 0; i < 30; ++i)
        set.push_back({double(value(random)), double(value(random)), !failed(random)});
      std::vector<std::size_t> brute;
      for (std::size_t i = 0; i < set.size(); ++i)
        {
          if (!set[i].completed)
            continue;
          bool dominated = false;
          for (std::size_t j = 0; j < set.size(); ++j)
            dominated |= set[j].completed && set[j].cost <= set[i].cost && set[j].error <= set[i].error &&
                         (set[j].cost < set[i].cost || set[j].error < set[i].error);
          if (!dominated)
            brute.push_back(i);
        }
      auto front_set = pareto_front(set);
      std::sort(front_set.begin(), front_set.end());
      EXPECT_EQ(front_set, brute) << "trial " << trial;
      checked += brute.size();
    }
  EXPECT_GT(checked, 200u);
}

TEST(StudyConvergence, ExactPowerLawsGiveTheirOrderAndLimit)
{
  // f(h) = 3 + 0.5 h^p: Celik et al.'s order and Richardson's limit are exact for it,
  // with a constant refinement ratio (q = 0) and with unequal ratios (the iteration)
  for (const double p : {1.0, 2.0, 3.0})
    for (const std::vector<double> &h : {std::vector<double>{0.01, 0.02, 0.04}, std::vector<double>{0.04, 0.013, 0.02}})
      {
        std::vector<double> f;
        for (const double x : h)
          f.push_back(3 + 0.5 * std::pow(x, p));
        const auto e = estimate_convergence(h, f);
        EXPECT_TRUE(e.converged);
        EXPECT_FALSE(e.oscillatory);
        EXPECT_FALSE(e.diverging);
        EXPECT_NEAR(e.order, p, 1e-9 * p);
        EXPECT_NEAR(e.extrapolated, 3.0, 1e-12);
        // GCI = 1.25 |(f1 - f2)/f1| / (r21^p - 1), r21 = h2/h1 of the two finest
        const double h1 = *std::min_element(h.begin(), h.end());
        const double h2 = 0.02; // the second finest in both sets
        const double f1 = 3 + 0.5 * std::pow(h1, p), f2 = 3 + 0.5 * std::pow(h2, p);
        EXPECT_NEAR(e.gci_fine, 1.25 * std::abs((f1 - f2) / f1) / (std::pow(h2 / h1, p) - 1), 1e-12);
      }
}

TEST(StudyConvergence, OscillationAndStagnationAreFlagged)
{
  // f1 < f2 > f3: oscillatory; the order from |e32/e21| = 2 with ratio 2 is 1
  const auto osc = estimate_convergence({1, 2, 4}, {1.0, 1.1, 0.9});
  EXPECT_TRUE(osc.oscillatory);
  EXPECT_GT(osc.order, 0);
  // no change between the two finest: no order
  EXPECT_FALSE(estimate_convergence({1, 2, 4}, {1.0, 1.0, 1.2}).converged);
  EXPECT_FALSE(osc.diverging);
  // f = 3 + 0.5/h: the differences grow under refinement (order -1), which |.| in p
  // would report as order 1 and converging
  const auto grows = estimate_convergence({1, 2, 4}, {3.5, 3.25, 3.125});
  EXPECT_TRUE(grows.diverging);
  EXPECT_FALSE(grows.oscillatory);
  for (const double p : {1.0, 2.0})
    EXPECT_FALSE(estimate_convergence({1, 2, 4}, {3 + 0.5, 3 + 0.5 * std::pow(2, p), 3 + 0.5 * std::pow(4, p)}).diverging);
  EXPECT_THROW(estimate_convergence({1, 1, 2}, {1, 2, 3}), std::invalid_argument);
  EXPECT_THROW(estimate_convergence({1, 2}, {1, 2}), std::invalid_argument);
}

namespace
{
  /// A run at mesh size @p h whose scalar "f" and probe "p" (x component) are @p f.
  RunData
  run_at(const double h, const double f)
  {
    RunData r;
    r.summary = {{"mesh", {{"representative_size", h}}},
                 {"metrics", {{"f", f}, {"p_displacement_x", f}, {"p_displacement_y", 0.0}, {"p_displacement_z", 1.0}}}};
    return r;
  }
} // namespace

TEST(StudySeriesReference, AMonotoneSeriesIsExtrapolatedAndAnOscillatingOneIsNot)
{
  MetricsSpec spec;
  spec.scalars = {"f"};
  spec.probes  = {"p"};
  // f(h) = 2 - 0.3 h^2 (h in mm-like units), listed fine first: the order and the
  // limit are exact, and the limit replaces the finest run's values
  const std::vector<double> h{0.5, 1.0, 2.0};
  std::vector<RunData>      runs;
  for (const double x : h)
    runs.push_back(run_at(x, 2 - 0.3 * x * x));
  const auto s = series_reference(spec, runs, {"fine", "medium", "coarse"});
  const auto &f = s.account["metrics"]["f"];
  EXPECT_EQ(f["used"], "extrapolated");
  EXPECT_NEAR(f["observed_order"].get<double>(), 2.0, 1e-9);
  EXPECT_NEAR(*s.data.metric("f"), 2.0, 1e-12);
  EXPECT_NEAR(*s.data.metric("p_displacement_x"), 2.0, 1e-12);
  EXPECT_EQ(s.account["runs"][0]["name"], "coarse"); // coarse to fine
  // a constant component is not extrapolated, and stays
  EXPECT_EQ(s.account["metrics"]["p_displacement_z"]["used"], "finest");
  EXPECT_EQ(*s.data.metric("p_displacement_z"), 1.0);

  // 1.0, 1.1, 0.9 from coarse to fine: oscillatory, the finest value stands
  const auto o = series_reference(spec, {run_at(4, 1.0), run_at(2, 1.1), run_at(1, 0.9)}, {"a", "b", "c"});
  EXPECT_EQ(o.account["metrics"]["f"]["used"], "finest");
  EXPECT_EQ(o.account["metrics"]["f"]["why"], "oscillatory: no asymptotic range");
  EXPECT_EQ(*o.data.metric("f"), 0.9);

  // two runs of one size, a run without a size, a metric a run lacks
  EXPECT_THROW(series_reference(spec, {run_at(1, 1), run_at(1, 2), run_at(2, 3)}, {"a", "b", "c"}),
               std::invalid_argument);
  auto no_size = run_at(1, 1);
  no_size.summary.erase("mesh");
  EXPECT_THROW(series_reference(spec, {no_size, run_at(2, 1), run_at(4, 1)}, {"a", "b", "c"}), std::invalid_argument);
  auto no_metric = run_at(1, 1);
  no_metric.summary["metrics"].erase("f");
  EXPECT_THROW(series_reference(spec, {no_metric, run_at(2, 1), run_at(4, 1)}, {"a", "b", "c"}), MissingMetric);

  // given sizes replace the measured ones (a locally refined series: the whole mesh's
  // size changes by less than the refined cells'): the same values measured at 1.0,
  // 0.8, 0.7 give another order; at the given 2, 1, 0.5 the exact one, and a run
  // without a size of its own is fine when given one
  std::vector<RunData> local{run_at(1.0, 2 - 0.3 * 4), run_at(0.8, 2 - 0.3 * 1), run_at(0.7, 2 - 0.3 * 0.25)};
  local[2].summary.erase("mesh");
  const auto g = series_reference(spec, local, {"L0", "L1", "L2"}, {{"L0", 2.0}, {"L1", 1.0}, {"L2", 0.5}});
  EXPECT_NEAR(g.account["metrics"]["f"]["observed_order"].get<double>(), 2.0, 1e-9);
  EXPECT_NEAR(*g.data.metric("f"), 2.0, 1e-12);
  EXPECT_EQ(g.account["runs"][2]["h"], 0.5);
  local[2] = run_at(0.7, 2 - 0.3 * 0.25);
  const auto measured = series_reference(spec, local, {"L0", "L1", "L2"});
  EXPECT_GT(std::abs(measured.account["metrics"]["f"]["observed_order"].get<double>() - 2.0), 0.5);
}

namespace
{
  /// The unit square z = @p z triangulated n × n, with displacement @p u(X).
  suturesim::io::SurfaceField
  square(const int n, const double z, const std::function<Eigen::Vector3d(const Eigen::Vector3d &)> &u)
  {
    suturesim::io::SurfaceField s;
    s.reference.resize(3, (n + 1) * (n + 1));
    s.displacement.resize(3, (n + 1) * (n + 1));
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        {
          const int k            = j * (n + 1) + i;
          s.reference.col(k)     = Eigen::Vector3d(double(i) / n, double(j) / n, z);
          s.displacement.col(k)  = u(s.reference.col(k));
        }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        {
          const std::uint32_t a = j * (n + 1) + i, b = a + 1, c = a + n + 1, d = c + 1;
          s.triangles.push_back({{a, b, d}});
          s.triangles.push_back({{a, d, c}});
        }
    return s;
  }
} // namespace

TEST(StudySurface, LinearFieldsInterpolateExactlyAndAnOffsetIsMeasured)
{
  // a linear reference field on a coarse surface is interpolated exactly at a finer
  // one's vertices: no error, and the two surfaces coincide
  const auto linear = [](const Eigen::Vector3d &X) { return Eigen::Vector3d(1 + 2 * X.x(), -X.y(), 0.5 * X.x()); };
  const auto exact  = surface_errors(square(7, 0, linear), square(3, 0, linear));
  EXPECT_NEAR(exact.relative_l2, 0, 1e-14);
  EXPECT_NEAR(exact.relative_max, 0, 1e-14);
  EXPECT_NEAR(exact.distance, 0, 1e-15);

  // a constant reference u_r = (1, 0, 0) and a candidate u_r + delta: every vertex is
  // off by |delta|, the lumped areas sum to the square's 1, so e2 = e_max = |delta|;
  // the candidate 1 mm above the reference's plane: dmax = 1 mm
  const Eigen::Vector3d delta(0.03, -0.04, 0); // |delta| = 0.05
  const auto            ref = [](const Eigen::Vector3d &) { return Eigen::Vector3d(1, 0, 0); };
  const auto            off = surface_errors(square(5, 1e-3, [&](const Eigen::Vector3d &X) -> Eigen::Vector3d { return ref(X) + delta; }),
                                  square(2, 0, ref));
  EXPECT_NEAR(off.relative_l2, 0.05, 1e-14);
  EXPECT_NEAR(off.relative_max, 0.05, 1e-14);
  EXPECT_NEAR(off.distance, 1e-3, 1e-15);

  // e2 weighs by area, e_max does not: a candidate wrong at one corner vertex only
  auto corner                = square(4, 0, ref);
  // |error| 1 at (0, 0), in two triangles of area 1/32: lumped area 2 (1/32)/3 = 1/48
  corner.displacement.col(0) = Eigen::Vector3d(2, 0, 0);
  const auto one             = surface_errors(corner, square(4, 0, ref));
  EXPECT_NEAR(one.relative_max, 1.0, 1e-14);
  EXPECT_NEAR(one.relative_l2, std::sqrt(1.0 / 48), 1e-14);

  EXPECT_THROW(surface_errors(corner, square(2, 0, [](const Eigen::Vector3d &) { return Eigen::Vector3d::Zero(); })),
               std::invalid_argument);
}

TEST(StudySurface, FieldFilesRoundTripAndBadOnesAreNamed)
{
  const auto s    = square(2, 0, [](const Eigen::Vector3d &X) { return Eigen::Vector3d(X.x(), 0, 0); });
  const auto file = suturesim::test_support::scratch_path() / "surface_roundtrip.json";
  s.write(file.string());
  const auto back = suturesim::io::SurfaceField::read(file.string());
  EXPECT_EQ(back.triangles, s.triangles);
  EXPECT_EQ((back.reference - s.reference).norm(), 0);
  EXPECT_EQ((back.displacement - s.displacement).norm(), 0);
  std::ofstream(file) << R"({"time": 0, "reference": [[0,0,0]], "displacement": [[0,0,0]], "triangles": [[0,1,2]]})";
  try
    {
      suturesim::io::SurfaceField::read(file.string());
      ADD_FAILURE() << "an out-of-range vertex was read";
    }
  catch (const std::runtime_error &e)
    {
      EXPECT_NE(std::string(e.what()).find("surface_roundtrip.json: a triangle's vertex 1 is out of range"),
                std::string::npos)
        << e.what();
    }
  std::filesystem::remove(file);
}
