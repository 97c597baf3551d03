#include <suturesim/collision/proximity.h>
#include <suturesim/realtime/self_collision.h>

#include <algorithm>
#include <tuple>

namespace suturesim::realtime
{
  SelfCollision::SelfCollision(const SelfCollisionSetup &s, const double reach)
    : setup(s)
  {
    tree.build(s.positions->middleCols(s.suture.begin, s.suture.size()), s.radius);
    pairs.reserve(16 * s.suture.size());
    candidates.reserve(16 * s.suture.size());
    counted.reach = reach;
  }

  Vector3d
  SelfCollision::separation(const Matrix3Xd &x, const std::uint32_t a, const std::uint32_t b, double &s,
                            double &t) const
  {
    const std::uint32_t b0 = setup.suture.begin;
    const Vector3d      p0 = x.col(b0 + a), p1 = x.col(b0 + a + 1);
    const Vector3d      q0 = x.col(b0 + b), q1 = x.col(b0 + b + 1);
    std::tie(s, t)         = collision::segment_closest_parameters(p0, p1, q0, q1);
    return (p0 + s * (p1 - p0)) - (q0 + t * (q1 - q0));
  }

  double
  SelfCollision::distance(const Matrix3Xd &x, const std::uint32_t a, const std::uint32_t b) const
  {
    double s, t;
    return separation(x, a, b, s, t).norm();
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
        double         s, t;
        const Vector3d d = separation(x, a, b, s, t);
        const double   o = d.norm();
        if (o >= reach || !(o > 0))
          continue;
        pairs.push_back({a, b, s, t, o, d / o, o});
      }
  }

  bool
  SelfCollision::remeasure(const Matrix3Xd &x, const double reach)
  {
    bool closer = false;
    for (auto &p : pairs)
      {
        const Vector3d d = separation(x, p.a, p.b, p.s, p.t);
        p.distance       = d.norm();
        if (p.distance > 0)
          p.normal = d / p.distance; // else the last normal: apart along it
        closer = closer || p.distance < reach;
      }
    return closer;
  }

  void
  SelfCollision::count_pairs()
  {
    counted.pair_steps += pairs.size();
    counted.max_pairs = std::max(counted.max_pairs, pairs.size());
    for (const auto &p : pairs)
      {
        counted.min_distance_detected = std::min(counted.min_distance_detected, p.distance);
        counted.min_distance          = std::min(counted.min_distance, p.distance);
      }
  }

  void
  SelfCollision::count_after(const Matrix3Xd &x)
  {
    counted.pair_steps += pairs.size();
    counted.max_pairs = std::max(counted.max_pairs, pairs.size());
    for (const auto &p : pairs)
      {
        counted.min_distance_detected = std::min(counted.min_distance_detected, p.detected);
        counted.min_distance          = std::min(counted.min_distance, distance(x, p.a, p.b));
      }
  }

  namespace
  {
    /// Finds the pairs closer than 2r after each step and leaves them be.
    class DetectOnly : public SelfCollision
    {
    public:
      explicit DetectOnly(const SelfCollisionSetup &s)
        : SelfCollision(s, 2 * s.radius)
      {}

      std::string
      name() const override
      {
        return "self-collision detection without a response";
      }
      void
      detect(const Matrix3Xd &) override
      {}
      void
      add_forces(const Matrix3Xd &, Matrix3Xd &) const override
      {}
      void
      after_step(Nodes &n) override
      {
        find_pairs(n.x, 2 * setup.radius);
        count_pairs();
      }
    };

    const bool registered = SelfCollision::Registry::instance().add(
      {"detect-only",
       "finds the segments closer than the suture's diameter after each step and applies "
       "nothing: counts (summary.json metrics.self_collision) for a run that moves as with "
       "'off'.",
       nullptr,
       [](const ParameterValues &, const SelfCollisionSetup &s) {
         return std::unique_ptr<SelfCollision>(new DetectOnly(s));
       }});
  } // namespace

  std::unique_ptr<SelfCollision>
  make_self_collision(const std::string &name, const ParameterValues &values,
                      const SelfCollisionSetup &setup)
  {
    if (name == "off")
      return nullptr;
    return SelfCollision::Registry::instance().get(name).create(values, setup);
  }
} // namespace suturesim::realtime
