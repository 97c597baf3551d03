#include <suturesim/realtime/curvature_springs.h>

#include <stdexcept>

namespace suturesim::realtime
{
  void
  CurvatureSprings::add(const std::uint32_t p, const std::uint32_t i, const std::uint32_t n,
                        const double c)
  {
    if (!(c > 0))
      throw std::invalid_argument("rod bending with stiffness <= 0");
    before.push_back(p);
    centre.push_back(i);
    after.push_back(n);
    stiffness.push_back(c);
    const Eigen::Index k = lambda.cols();
    lambda.conservativeResize(3, k + 1);
    lambda.col(k).setZero();
  }

  double
  CurvatureSprings::energy(const Matrix3Xd &x) const
  {
    double e = 0;
    for (std::size_t s = 0; s < centre.size(); ++s)
      e += 0.5 * stiffness[s] *
           (x.col(before[s]) - 2 * x.col(centre[s]) + x.col(after[s])).squaredNorm();
    return e;
  }

  void
  CurvatureSprings::add_forces(const Matrix3Xd &x, Matrix3Xd &f) const
  {
    for (std::size_t s = 0; s < centre.size(); ++s)
      {
        const Vector3d cb = stiffness[s] * (x.col(before[s]) - 2 * x.col(centre[s]) + x.col(after[s]));
        f.col(before[s]) -= cb;
        f.col(centre[s]) += 2 * cb;
        f.col(after[s]) -= cb;
      }
  }

  void
  CurvatureSprings::add_constraint_forces(const Matrix3Xd &, Matrix3Xd &f, const double dt) const
  {
    // C = x₋ − 2x + x₊ (vector): ∇Cᵀλ/dt² in place of −k C
    for (std::size_t s = 0; s < centre.size(); ++s)
      {
        const Vector3d cb = -lambda.col(s) / (dt * dt);
        f.col(before[s]) -= cb;
        f.col(centre[s]) += 2 * cb;
        f.col(after[s]) -= cb;
      }
  }

  void
  CurvatureSprings::reset_multipliers()
  {
    lambda.setZero();
  }

  void
  CurvatureSprings::project(Matrix3Xd &x, const VectorXd &w, const double dt)
  {
    for (std::size_t s = 0; s < centre.size(); ++s)
      {
        const double wp = w[before[s]], wi = w[centre[s]], wn = w[after[s]];
        const double alpha       = 1 / (stiffness[s] * dt * dt);
        const double denominator = wp + 4 * wi + wn + alpha;
        const Vector3d b = x.col(before[s]) - 2 * x.col(centre[s]) + x.col(after[s]);
        const Vector3d d_lambda = (-b - alpha * lambda.col(s)) / denominator;
        lambda.col(s) += d_lambda;
        x.col(before[s]) += wp * d_lambda;
        x.col(centre[s]) -= 2 * wi * d_lambda;
        x.col(after[s]) += wn * d_lambda;
      }
  }

  double
  CurvatureSprings::max_violation(const Matrix3Xd &x) const
  {
    double m = 0;
    for (std::size_t s = 0; s < centre.size(); ++s)
      {
        const double span = (x.col(after[s]) - x.col(before[s])).norm();
        if (span > 0)
          m = std::max(m, (x.col(before[s]) - 2 * x.col(centre[s]) + x.col(after[s])).norm() / span);
      }
    return m;
  }
} // namespace suturesim::realtime
