#include <suturesim/collision/proximity.h>
#include <suturesim/rod/self_contact.h>

#include <algorithm>
#include <array>

namespace suturesim::rod
{
  void
  SelfContact::setup(const ContactParameters &parameters, const std::vector<Vec3> &points,
                     const std::vector<double> &rest_lengths)
  {
    prm = parameters;
    arc.assign(points.size(), 0);
    for (std::size_t e = 0; e < rest_lengths.size(); ++e)
      arc[e + 1] = arc[e] + rest_lengths[e];
    if (prm.enabled)
      bvh.build(points, prm.radius);
  }

  std::pair<double, double>
  SelfContact::closest_parameters(const Vec3 &p0, const Vec3 &p1, const Vec3 &q0, const Vec3 &q1)
  {
    return collision::segment_closest_parameters(p0, p1, q0, q1);
  }

  std::array<double, 3>
  SelfContact::penalty(const double g) const
  {
    const double k = prm.stiffness, d = prm.smoothing;
    if (g >= 0)
      return {{0, 0, 0}};
    if (g > -d)
      return {{-k * g * g * g / (6 * d), k * g * g / (2 * d), -k * g / d}};
    return {{k * (0.5 * g * g + 0.5 * d * g + d * d / 6), -k * (g + 0.5 * d), k}};
  }

  const std::vector<ContactPair> &
  SelfContact::update(const std::vector<Vec3> &x)
  {
    active.clear();
    if (!prm.enabled)
      return active;
    bvh.refit(x);
    const double contact = 2 * prm.radius;
    bvh.self_overlaps(contact, candidates);
    for (const auto &[a, b] : candidates)
      {
        // segments closer along the rest centreline than the contact distance always
        // touch in any configuration; they are neighbours, not contact partners
        if (arc[b] - arc[a + 1] <= contact)
          continue;
        const auto [s, t] = closest_parameters(x[a], x[a + 1], x[b], x[b + 1]);
        const Vec3   p    = (1 - s) * x[a] + s * x[a + 1];
        const Vec3   q    = (1 - t) * x[b] + t * x[b + 1];
        const double dist = (p - q).norm();
        const double gap  = dist - contact;
        if (gap >= 0)
          continue;
        if (dist < 1e-14 * contact)
          continue; // centrelines intersect: no direction to push along
        const auto phi = penalty(gap);
        active.push_back({a, b, s, t, gap, (p - q) / dist, phi[1], phi[2], dist});
      }
    return active;
  }

  double
  SelfContact::energy() const
  {
    double e = 0;
    for (const auto &c : active)
      e += penalty(c.gap)[0];
    return e;
  }
} // namespace suturesim::rod
