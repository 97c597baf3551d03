#include <suturesim/realtime/angle_springs.h>

#include <Eigen/Geometry>

#include <cmath>
#include <stdexcept>

namespace suturesim::realtime
{
  namespace
  {
    double
    angle_between(const Vector3d &e1, const Vector3d &e2)
    {
      return std::atan2(e1.cross(e2).norm(), e1.dot(e2));
    }
  } // namespace

  void
  AngleSprings::add(const std::uint32_t v, const std::uint32_t a, const std::uint32_t b,
                    const Matrix3Xd &x, const double k)
  {
    if (!(k > 0))
      throw std::invalid_argument("bending spring with stiffness <= 0");
    vertex.push_back(v);
    end_a.push_back(a);
    end_b.push_back(b);
    rest.push_back(angle_between(x.col(a) - x.col(v), x.col(b) - x.col(v)));
    stiffness.push_back(k);
    lambda.push_back(0);
  }

  bool
  AngleSprings::angle(const Matrix3Xd &x, const std::size_t s, double &theta, Vector3d &ga,
                      Vector3d &gb) const
  {
    const Vector3d e1 = x.col(end_a[s]) - x.col(vertex[s]);
    const Vector3d e2 = x.col(end_b[s]) - x.col(vertex[s]);
    const double   l1 = e1.norm(), l2 = e2.norm();
    if (!(l1 > 0) || !(l2 > 0))
      return false;
    const Vector3d u1 = e1 / l1, u2 = e2 / l2;
    const double   c = u1.dot(u2), sn = u1.cross(u2).norm();
    theta            = std::atan2(sn, c);
    if (sn < 1e-9)
      return false;
    ga = -(u2 - c * u1) / (l1 * sn);
    gb = -(u1 - c * u2) / (l2 * sn);
    return true;
  }

  double
  AngleSprings::energy(const Matrix3Xd &x) const
  {
    double e = 0;
    for (std::size_t s = 0; s < vertex.size(); ++s)
      {
        const double theta =
          angle_between(x.col(end_a[s]) - x.col(vertex[s]), x.col(end_b[s]) - x.col(vertex[s]));
        e += 0.5 * stiffness[s] * (theta - rest[s]) * (theta - rest[s]);
      }
    return e;
  }

  void
  AngleSprings::add_forces(const Matrix3Xd &x, Matrix3Xd &f) const
  {
    double   theta;
    Vector3d ga, gb;
    for (std::size_t s = 0; s < vertex.size(); ++s)
      if (angle(x, s, theta, ga, gb))
        {
          const double m = -stiffness[s] * (theta - rest[s]);
          f.col(end_a[s]) += m * ga;
          f.col(end_b[s]) += m * gb;
          f.col(vertex[s]) -= m * (ga + gb);
        }
  }

  void
  AngleSprings::add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, const double dt) const
  {
    double   theta;
    Vector3d ga, gb;
    for (std::size_t s = 0; s < vertex.size(); ++s)
      if (angle(x, s, theta, ga, gb))
        {
          const double m = lambda[s] / (dt * dt);
          f.col(end_a[s]) += m * ga;
          f.col(end_b[s]) += m * gb;
          f.col(vertex[s]) -= m * (ga + gb);
        }
  }

  void
  AngleSprings::reset_multipliers()
  {
    std::fill(lambda.begin(), lambda.end(), 0.0);
  }

  void
  AngleSprings::warm_multipliers(const VectorXd &, const double scale)
  {
    for (auto &l : lambda)
      l *= scale;
  }

  void
  AngleSprings::project(Matrix3Xd &x, const VectorXd &w, const double dt)
  {
    double   theta;
    Vector3d ga, gb;
    for (std::size_t s = 0; s < vertex.size(); ++s)
      if (angle(x, s, theta, ga, gb))
        {
          const double   wa = w[end_a[s]], wb = w[end_b[s]], wv = w[vertex[s]];
          const Vector3d gv = -(ga + gb);
          const double   alpha = 1 / (stiffness[s] * dt * dt);
          const double   denominator =
            wa * ga.squaredNorm() + wb * gb.squaredNorm() + wv * gv.squaredNorm() + alpha;
          const double d_lambda = (-(theta - rest[s]) - alpha * lambda[s]) / denominator;
          lambda[s] += d_lambda;
          x.col(end_a[s]) += wa * d_lambda * ga;
          x.col(end_b[s]) += wb * d_lambda * gb;
          x.col(vertex[s]) += wv * d_lambda * gv;
        }
  }

  double
  AngleSprings::max_violation(const Matrix3Xd &x) const
  {
    double m = 0;
    for (std::size_t s = 0; s < vertex.size(); ++s)
      m = std::max(m, std::abs(angle_between(x.col(end_a[s]) - x.col(vertex[s]),
                                             x.col(end_b[s]) - x.col(vertex[s])) -
                               rest[s]));
    return m;
  }
} // namespace suturesim::realtime
