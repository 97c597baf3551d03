#include <suturesim/collision/proximity.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace suturesim::collision
{
  std::pair<double, double>
  segment_closest_parameters(const Eigen::Vector3d &p0, const Eigen::Vector3d &p1,
                             const Eigen::Vector3d &q0, const Eigen::Vector3d &q1)
  {
    // minimise |p0 + s a − q0 − t b|² over the unit square (clamped two-step solve)
    const Eigen::Vector3d a = p1 - p0, b = q1 - q0, w = p0 - q0;
    const double aa = a.dot(a), bb = b.dot(b), ab = a.dot(b), aw = a.dot(w), bw = b.dot(w);
    const double det = aa * bb - ab * ab;
    double       s   = det > 1e-14 * aa * bb ? std::clamp((ab * bw - bb * aw) / det, 0.0, 1.0) : 0.0;
    double       t   = std::clamp((ab * s + bw) / bb, 0.0, 1.0);
    s                = std::clamp((ab * t - aw) / aa, 0.0, 1.0);
    return {s, t};
  }

  Eigen::Vector3d
  closest_point_on_triangle(const Eigen::Vector3d &p, const Eigen::Vector3d &a,
                            const Eigen::Vector3d &b, const Eigen::Vector3d &c,
                            Eigen::Vector3d &bary)
  {
    const Eigen::Vector3d ab = b - a, ac = c - a, ap = p - a;
    const double          d1 = ab.dot(ap), d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0)
      {
        bary = {1, 0, 0};
        return a;
      }
    const Eigen::Vector3d bp = p - b;
    const double          d3 = ab.dot(bp), d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3)
      {
        bary = {0, 1, 0};
        return b;
      }
    const double vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
      {
        const double v = d1 / (d1 - d3);
        bary           = {1 - v, v, 0};
        return a + v * ab;
      }
    const Eigen::Vector3d cp = p - c;
    const double          d5 = ab.dot(cp), d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6)
      {
        bary = {0, 0, 1};
        return c;
      }
    const double vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
      {
        const double w = d2 / (d2 - d6);
        bary           = {1 - w, 0, w};
        return a + w * ac;
      }
    const double va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
      {
        const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        bary           = {0, 1 - w, w};
        return b + w * (c - b);
      }
    const double denom = 1 / (va + vb + vc);
    const double v = vb * denom, w = vc * denom;
    bary = {1 - v - w, v, w};
    return a + ab * v + ac * w;
  }

  void
  NearestTriangle::offer(const Eigen::Vector3d &p, const std::uint32_t t, const Eigen::Vector3d &a,
                         const Eigen::Vector3d &b, const Eigen::Vector3d &c, const double scale)
  {
    Eigen::Vector3d       bary;
    const Eigen::Vector3d q = closest_point_on_triangle(p, a, b, c, bary);
    const Eigen::Vector3d n = (b - a).cross(c - a).normalized();
    const double          d = (p - q).dot(n), to = (p - q).norm();
    if (found())
      {
        const double tie = 1e-9 * (to + scale);
        if (to > distance + tie || (to > distance - tie && d <= signed_distance))
          return;
      }
    triangle        = t;
    distance        = to;
    signed_distance = d;
    weights         = bary;
    normal          = n;
  }

  bool
  segment_crosses_triangle(const Eigen::Vector3d &p0, const Eigen::Vector3d &p1, const Eigen::Vector3d &a,
                           const Eigen::Vector3d &b, const Eigen::Vector3d &c, double &s, Eigen::Vector3d &bary)
  {
    // p0 + s d = a + u (b − a) + v (c − a), solved by Cramer's rule with triple products
    const Eigen::Vector3d d = p1 - p0, e1 = b - a, e2 = c - a;
    const Eigen::Vector3d q   = d.cross(e2);
    const double          det = e1.dot(q);
    // parallel (or degenerate): no transversal crossing
    if (std::abs(det) <= 1e-14 * d.norm() * e1.norm() * e2.norm())
      return false;
    const Eigen::Vector3d w = p0 - a;
    const double          u = w.dot(q) / det;
    const Eigen::Vector3d r = w.cross(e1);
    const double          v = d.dot(r) / det;
    s                       = e2.dot(r) / det;
    if (u < 0 || v < 0 || u + v > 1 || s < 0 || s > 1)
      return false;
    bary = {1 - u - v, u, v};
    return true;
  }
} // namespace suturesim::collision
