#include <suturesim/coupling/accurate/thread_curve.h>

#include <algorithm>
#include <cmath>

namespace suturesim::coupling
{
  HermiteSegment
  HermiteSegment::through(const rod::Vec3 &xa, const rod::Quat &qa, const rod::Vec3 &xb, const rod::Quat &qb,
                          const bool directors)
  {
    if (!directors)
      return {xa, xb - xa, xb, xb - xa, false};
    const double chord = (xb - xa).norm();
    return {xa, chord * (qa * Eigen::Vector3d::UnitX()), xb, chord * (qb * Eigen::Vector3d::UnitX()), true};
  }

  Eigen::Matrix<double, 12, 1>
  HermiteSegment::reaction(const double u, const Eigen::Vector3d &f) const
  {
    Eigen::Matrix<double, 12, 1> r = Eigen::Matrix<double, 12, 1>::Zero();
    const double                 chord = (xb - xa).norm();
    if (!directors || chord == 0)
      {
        r.head<3>()       = (1 - u) * f;
        r.segment<3>(6)   = u * f;
        return r;
      }
    const Eigen::Vector4d h = basis(u);
    const double          h00 = h[0], h10 = h[1], h01 = h[2], h11 = h[3];
    const Eigen::Vector3d e = (xb - xa) / chord, da = ma / chord, db = mb / chord;
    // the end tangents' length is the chord's: moving a node along it stretches both
    const double along = (h10 * da + h11 * db).dot(f);
    r.head<3>()        = h00 * f - along * e;
    r.segment<3>(3)    = chord * h10 * da.cross(f);
    r.segment<3>(6)    = h01 * f + along * e;
    r.segment<3>(9)    = chord * h11 * db.cross(f);
    return r;
  }

  double
  HermiteSegment::closest(const Eigen::Vector3d &x, const double u0) const
  {
    double u = u0;
    for (unsigned iteration = 0; iteration < 50; ++iteration)
      {
        const Eigen::Vector3d d = x - at(u), c1 = rate(u);
        const double          a = c1.squaredNorm();
        double                slope = -a + d.dot(bend(u));
        if (slope > -0.1 * a)
          slope = -a;
        const double step = -d.dot(c1) / slope;
        u                 = std::clamp(u + step, -1.0, 2.0);
        if (std::abs(step) < 1e-14)
          break;
      }
    return u;
  }

  void
  ThreadCurve::attach(const std::vector<rod::Vec3> *thread_nodes, const std::vector<double> &element_lengths,
                      const std::vector<rod::Quat> *thread_rotations)
  {
    nodes     = thread_nodes;
    rotations = thread_rotations;
    s.assign(1, 0.0);
    for (const double l : element_lengths)
      s.push_back(s.back() + l);
  }

  std::pair<std::size_t, double>
  ThreadCurve::element(const double at) const
  {
    const std::size_t n = s.size() - 1;
    const std::size_t e =
      std::min<std::size_t>(n - 1, std::upper_bound(s.begin(), s.end(), std::max(0.0, at)) - s.begin() - 1);
    const double xi = std::clamp((at - s[e]) / (s[e + 1] - s[e]), 0.0, 1.0);
    return {e, xi};
  }

  std::pair<rod::Vec3, rod::Quat>
  ThreadCurve::node(const std::size_t i) const
  {
    return {(*nodes)[i], rotations ? (*rotations)[i] : rod::Quat::Identity()};
  }

  HermiteSegment
  ThreadCurve::segment(const std::size_t e) const
  {
    const auto [xa, qa] = node(e);
    const auto [xb, qb] = node(e + 1);
    return segment(xa, qa, xb, qb);
  }
} // namespace suturesim::coupling
