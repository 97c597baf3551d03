#include <suturesim/collision/proximity.h>
#include <suturesim/realtime/self_collision.h>

namespace suturesim::realtime
{
  SelfCollision::SelfCollision(const SelfCollisionSetup &s)
    : setup(s)
  {
    tree.build(s.positions->middleCols(s.suture.begin, s.suture.size()), s.radius);
    pairs.reserve(16 * s.suture.size());
    candidates.reserve(16 * s.suture.size());
  }

  void
  SelfCollision::find_pairs(const Matrix3Xd &x, const double reach)
  {
    const auto points = x.middleCols(setup.suture.begin, setup.suture.size());
    tree.refit_all(points);
    // leaf spheres already carry one radius each; the margin adds what the reach needs
    tree.self_overlaps(std::max(0.0, reach - 2 * setup.radius), candidates);
    pairs.clear();
    for (const auto &[a, b] : candidates)
      {
        // arc length between the segments' facing ends: neighbours always touch
        if ((b - a - 1) * setup.link <= reach)
          continue;
        const Vector3d p0 = points.col(a), p1 = points.col(a + 1);
        const Vector3d q0 = points.col(b), q1 = points.col(b + 1);
        const auto [s, t] = collision::segment_closest_parameters(p0, p1, q0, q1);
        const Vector3d d  = (p0 + s * (p1 - p0)) - (q0 + t * (q1 - q0));
        const double   o  = d.norm();
        if (o >= reach || !(o > 0))
          continue;
        pairs.push_back({a, b, s, t, o, d / o});
      }
  }

  std::unique_ptr<ContactSet>
  make_self_collision(const std::string &name, const ParameterValues &values,
                      const SelfCollisionSetup &setup)
  {
    if (name == "off")
      return nullptr;
    return SelfCollision::Registry::instance().get(name).create(values, setup);
  }
} // namespace suturesim::realtime
