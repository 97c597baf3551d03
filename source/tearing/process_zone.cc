#include <suturesim/tearing/process_zone.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace suturesim::tearing
{
  Point3
  closest_on_segment(const Point3 &x, const Point3 &a, const Point3 &b)
  {
    Point3 ab{};
    double length2 = 0, along = 0;
    for (int i = 0; i < 3; ++i)
      {
        ab[i] = b[i] - a[i];
        length2 += ab[i] * ab[i];
        along += ab[i] * (x[i] - a[i]);
      }
    // The closest point's parameter on [a, b], clamped to the ends (a point if a = b).
    const double t = length2 > 0 ? std::clamp(along / length2, 0.0, 1.0) : 0.0;
    Point3       c{};
    for (int i = 0; i < 3; ++i)
      c[i] = a[i] + t * ab[i];
    return c;
  }

  double
  distance_to_segment(const Point3 &x, const Point3 &a, const Point3 &b)
  {
    const Point3 c  = closest_on_segment(x, a, b);
    double       d2 = 0;
    for (int i = 0; i < 3; ++i)
      d2 += (x[i] - c[i]) * (x[i] - c[i]);
    return std::sqrt(d2);
  }

  void
  ZoneSample::add(const double weight, const double value, const Point3 &where, const Point3 &direction)
  {
    volume += weight;
    integral += weight * value;
    if (value > peak)
      {
        peak           = value;
        peak_location  = where;
        peak_direction = direction;
      }
  }

  void
  ZoneSample::merge(const ZoneSample &other)
  {
    volume += other.volume;
    integral += other.integral;
    if (other.peak > peak)
      {
        peak           = other.peak;
        peak_location  = other.peak_location;
        peak_direction = other.peak_direction;
      }
  }

  double
  ZoneSample::mean() const
  {
    return volume > 0 ? integral / volume : std::numeric_limits<double>::quiet_NaN();
  }

  ProcessZones::ProcessZones(std::vector<Tract> tracts, const double radius, Separates cut)
    : tracts(std::move(tracts))
    , ell(radius)
    , cut(std::move(cut))
  {
    if (!(radius > 0))
      throw std::invalid_argument("process zone radius must be > 0 m");
  }

  void
  ProcessZones::zones_containing(const Point3 &X, std::vector<unsigned int> &zones) const
  {
    zones.clear();
    for (unsigned int i = 0; i < tracts.size(); ++i)
      if (distance_to_segment(X, tracts[i].entry, tracts[i].exit) <= ell &&
          !(cut && cut(X, closest_on_segment(X, tracts[i].entry, tracts[i].exit))))
        zones.push_back(i);
  }
} // namespace suturesim::tearing
