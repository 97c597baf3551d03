#include <suturesim/study/curve_metrics.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace suturesim::study
{
  double
  Curve::operator()(const double at) const
  {
    if (x.empty())
      throw std::invalid_argument("an empty curve");
    if (at <= x.front())
      return y.front();
    if (at >= x.back())
      return y.back();
    const auto   k = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), at) - x.begin());
    const double s = (at - x[k - 1]) / (x[k] - x[k - 1]);
    return (1 - s) * y[k - 1] + s * y[k];
  }

  namespace
  {
    /// [a, b] with every sample of either curve inside it.
    std::vector<double>
    breakpoints(const Curve &c, const Curve &r, const double a, const double b)
    {
      std::vector<double> points{a, b};
      for (const Curve *curve : {&c, &r})
        for (const double x : curve->x)
          if (x > a && x < b)
            points.push_back(x);
      std::sort(points.begin(), points.end());
      points.erase(std::unique(points.begin(), points.end()), points.end());
      return points;
    }
  } // namespace

  CurveErrors
  curve_errors(const Curve &candidate, const Curve &reference, const double a, const double b)
  {
    if (!(a < b))
      throw std::invalid_argument("an empty interval");
    for (const Curve *curve : {&candidate, &reference})
      if (curve->x.size() < 2 || curve->x.size() != curve->y.size() || a < curve->front() || b > curve->back())
        throw std::invalid_argument("the interval is not inside both curves");

    const auto points = breakpoints(candidate, reference, a, b);
    double     diff2 = 0, ref2 = 0, max_diff = 0, max_ref = 0, max_candidate = 0;
    for (std::size_t k = 0; k + 1 < points.size(); ++k)
      {
        // On one piece both interpolants are linear, so d² and r² are quadratics:
        // Simpson's rule integrates them exactly.
        const double x0 = points[k], x1 = points[k + 1], xm = 0.5 * (x0 + x1), h = x1 - x0;
        const double d0 = candidate(x0) - reference(x0), d1 = candidate(x1) - reference(x1);
        const double dm = candidate(xm) - reference(xm);
        const double r0 = reference(x0), r1 = reference(x1), rm = reference(xm);
        diff2 += h / 6 * (d0 * d0 + 4 * dm * dm + d1 * d1);
        ref2 += h / 6 * (r0 * r0 + 4 * rm * rm + r1 * r1);
      }
    for (const double x : points)
      {
        max_diff      = std::max(max_diff, std::abs(candidate(x) - reference(x)));
        max_ref       = std::max(max_ref, std::abs(reference(x)));
        max_candidate = std::max(max_candidate, std::abs(candidate(x)));
      }
    if (ref2 <= 0 || max_ref <= 0)
      throw std::invalid_argument("the reference vanishes on the interval");
    return {std::sqrt(diff2 / ref2), max_diff / max_ref, (max_candidate - max_ref) / max_ref};
  }

  namespace
  {
    void
    check_events(const std::vector<double> &events, const char *whose)
    {
      for (std::size_t k = 1; k < events.size(); ++k)
        if (!(events[k] > events[k - 1]))
          throw std::invalid_argument(std::string("the ") + whose + " events are not increasing");
    }
  } // namespace

  Curve
  warp_to_events(const Curve &candidate, const std::vector<double> &from, const std::vector<double> &to)
  {
    if (from.size() != to.size() || from.size() < 2)
      throw std::invalid_argument("the runs have different events");
    check_events(from, "candidate's");
    check_events(to, "reference's");
    Curve warped = candidate;
    for (double &x : warped.x)
      {
        if (x <= from.front())
          x += to.front() - from.front();
        else if (x >= from.back())
          x += to.back() - from.back();
        else
          {
            const auto k = static_cast<std::size_t>(std::upper_bound(from.begin(), from.end(), x) - from.begin()) - 1;
            x            = to[k] + (x - from[k]) * (to[k + 1] - to[k]) / (from[k + 1] - from[k]);
          }
      }
    return warped;
  }

  std::vector<CurveErrors>
  phase_errors(const Curve &candidate, const Curve &reference, const std::vector<double> &candidate_events,
               const std::vector<double> &reference_events)
  {
    const Curve              warped = warp_to_events(candidate, candidate_events, reference_events);
    std::vector<CurveErrors> phases;
    for (std::size_t k = 0; k + 1 < reference_events.size(); ++k)
      phases.push_back(curve_errors(warped, reference, reference_events[k], reference_events[k + 1]));
    return phases;
  }

  double
  relative_error(const double value, const double reference)
  {
    if (reference == 0)
      throw std::invalid_argument("a relative error against a zero reference");
    return (value - reference) / std::abs(reference);
  }
} // namespace suturesim::study
