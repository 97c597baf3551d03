#include <suturesim/realtime/node_access.h>

#include <cmath>
#include <stdexcept>
#include <string>

namespace suturesim::realtime
{
  NodeAccess::NodeAccess(const NodeRange suture_nodes, const double rest_length, const double k)
    : suture(suture_nodes)
    , rest(rest_length)
    , stiffness(k)
  {
    if (!(rest_length > 0) || !std::isfinite(rest_length))
      throw std::invalid_argument("node-access: the segment's rest length must be positive and finite (m)");
    if (!(k > 0))
      throw std::invalid_argument("node-access: the stiffness must be positive (N/m)");
    if (suture.size() < 2)
      throw std::invalid_argument("node-access: the suture needs at least two nodes");
  }

  std::size_t
  NodeAccess::add(const Vector3d &b, const std::uint32_t segment)
  {
    if (segment + 1 >= suture.size())
      throw std::invalid_argument("node-access: segment " + std::to_string(segment) + " is not on a suture of " +
                                  std::to_string(suture.size()) + " nodes");
    points.push_back({b, segment, 0});
    return points.size() - 1;
  }

  void
  NodeAccess::detect(const Matrix3Xd &x)
  {
    const std::uint32_t last_segment = suture.size() - 2;
    for (auto &a : points)
      {
        const std::uint32_t before = a.segment;
        // Walk towards b while it lies beyond either end of the segment's chord; a
        // suture can pass at most all its segments, so the walk is bounded.
        for (std::uint32_t walked = 0; walked <= last_segment; ++walked)
          {
            const Vector3d pi = x.col(suture.begin + a.segment);
            const Vector3d d  = x.col(suture.begin + a.segment + 1) - pi;
            const double   L2 = d.squaredNorm();
            if (L2 == 0)
              break;
            const double t = (a.b - pi).dot(d) / L2;
            if (t > 1 && a.segment < last_segment)
              ++a.segment;
            else if (t < 0 && a.segment > 0)
              --a.segment;
            else
              break;
          }
        if (a.segment != before && moved)
          moved(before, a.segment);
      }
  }

  double
  NodeAccess::violation(const std::size_t a, const Matrix3Xd &x) const
  {
    const auto i = first_node(a);
    return (points[a].b - x.col(i)).norm() + (points[a].b - x.col(i + 1)).norm() - rest;
  }

  double
  NodeAccess::gradient(const std::size_t a, const Matrix3Xd &x, Vector3d &gi, Vector3d &gj) const
  {
    const auto     i  = first_node(a);
    const Vector3d di = x.col(i) - points[a].b, dj = x.col(i + 1) - points[a].b;
    const double   ni = di.norm(), nj = dj.norm();
    // A node exactly at b has no direction: its share of C is then stationary (the
    // subgradient's zero element), and the other node alone carries the constraint.
    gi = ni > 0 ? Vector3d(di / ni) : Vector3d::Zero();
    gj = nj > 0 ? Vector3d(dj / nj) : Vector3d::Zero();
    return ni + nj - rest;
  }

  void
  NodeAccess::add_forces(const Matrix3Xd &x, Matrix3Xd &f) const
  {
    if (!std::isfinite(stiffness))
      throw std::logic_error("node-access: a rigid access point (infinite stiffness) has no penalty force");
    Vector3d gi, gj;
    for (std::size_t a = 0; a < points.size(); ++a)
      {
        const double tension = stiffness * gradient(a, x, gi, gj);
        const auto   i       = first_node(a);
        f.col(i) -= tension * gi;
        f.col(i + 1) -= tension * gj;
      }
  }

  std::optional<double>
  NodeAccess::energy(const Matrix3Xd &x) const
  {
    double e = 0;
    for (std::size_t a = 0; a < points.size(); ++a)
      {
        const double c = violation(a, x);
        e += 0.5 * stiffness * c * c;
      }
    return e;
  }

  void
  NodeAccess::add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, const double dt) const
  {
    Vector3d gi, gj;
    for (std::size_t a = 0; a < points.size(); ++a)
      {
        gradient(a, x, gi, gj);
        const auto   i     = first_node(a);
        const double scale = points[a].lambda / (dt * dt);
        f.col(i) += scale * gi;
        f.col(i + 1) += scale * gj;
      }
  }

  void
  NodeAccess::reset_multipliers()
  {
    for (auto &a : points)
      a.lambda = 0;
  }

  void
  NodeAccess::project(Matrix3Xd &x, const VectorXd &w, const double dt)
  {
    const double alpha = 1 / (stiffness * dt * dt); // 0 for a rigid access point
    Vector3d     gi, gj;
    for (std::size_t a = 0; a < points.size(); ++a)
      {
        const auto   i           = first_node(a);
        const double C           = gradient(a, x, gi, gj);
        const double denominator = w[i] * gi.squaredNorm() + w[i + 1] * gj.squaredNorm() + alpha;
        if (denominator == 0)
          continue;
        const double d_lambda = (-C - alpha * points[a].lambda) / denominator;
        points[a].lambda += d_lambda;
        x.col(i) += w[i] * d_lambda * gi;
        x.col(i + 1) += w[i + 1] * d_lambda * gj;
      }
  }
} // namespace suturesim::realtime
