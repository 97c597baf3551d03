#include <suturesim/realtime/node_triangle_contacts.h>

#include <algorithm>

namespace suturesim::realtime
{
  double
  NodeTriangleContacts::gap(const Contact &c, const Matrix3Xd &x) const
  {
    const Vector3d q = c.bary[0] * x.col(c.triangle[0]) + c.bary[1] * x.col(c.triangle[1]) +
                       c.bary[2] * x.col(c.triangle[2]);
    return (x.col(c.node) - q).dot(c.normal) - offset;
  }

  void
  NodeTriangleContacts::add_forces(const Matrix3Xd &x, Matrix3Xd &f) const
  {
    for (const auto &c : contacts)
      {
        const double g = gap(c, x);
        if (g >= 0)
          continue;
        const Vector3d force = -penalty * g * c.normal;
        f.col(c.node) += force;
        for (unsigned k = 0; k < 3; ++k)
          f.col(c.triangle[k]) -= c.bary[k] * force;
      }
  }

  std::optional<double>
  NodeTriangleContacts::energy(const Matrix3Xd &x) const
  {
    double e = 0;
    for (const auto &c : contacts)
      {
        const double g = std::min(gap(c, x), 0.0);
        e += 0.5 * penalty * g * g;
      }
    return e;
  }

  void
  NodeTriangleContacts::add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, const double dt) const
  {
    if (!projected)
      {
        add_forces(x, f);
        return;
      }
    // C = g ≥ 0 with ∇_node C = n: the node is pushed by λ n/dt², the triangle back
    for (const auto &c : contacts)
      {
        const Vector3d force = c.lambda / (dt * dt) * c.normal;
        f.col(c.node) += force;
        for (unsigned k = 0; k < 3; ++k)
          f.col(c.triangle[k]) -= c.bary[k] * force;
      }
  }

  void
  NodeTriangleContacts::reset_multipliers()
  {
    for (auto &c : contacts)
      c.lambda = 0;
  }

  void
  NodeTriangleContacts::project(Matrix3Xd &x, const VectorXd &w, const double dt)
  {
    const double alpha = 1 / (penalty * dt * dt);
    for (auto &c : contacts)
      {
        const double g = gap(c, x);
        if (g >= 0)
          continue;
        double denominator = w[c.node] + alpha;
        for (unsigned k = 0; k < 3; ++k)
          denominator += c.bary[k] * c.bary[k] * w[c.triangle[k]];
        if (denominator == 0)
          continue;
        const double d_lambda = std::max((-g - alpha * c.lambda) / denominator, -c.lambda);
        c.lambda += d_lambda;
        x.col(c.node) += w[c.node] * d_lambda * c.normal;
        for (unsigned k = 0; k < 3; ++k)
          x.col(c.triangle[k]) -= w[c.triangle[k]] * c.bary[k] * d_lambda * c.normal;
      }
  }
} // namespace suturesim::realtime
