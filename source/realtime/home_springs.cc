#include <suturesim/realtime/home_springs.h>

#include <algorithm>
#include <stdexcept>

namespace suturesim::realtime
{
  void
  HomeSprings::add(const std::uint32_t i, const Vector3d &h, const double k)
  {
    if (!(k > 0))
      throw std::invalid_argument("home spring with stiffness <= 0");
    nodes.push_back(i);
    stiffness.push_back(k);
    const Eigen::Index n = home.cols();
    home.conservativeResize(3, n + 1);
    home.col(n) = h;
    lambda.conservativeResize(3, n + 1);
    lambda.col(n).setZero();
  }

  std::size_t
  HomeSprings::find(const std::uint32_t i) const
  {
    return static_cast<std::size_t>(std::find(nodes.begin(), nodes.end(), i) - nodes.begin());
  }

  void
  HomeSprings::set(const std::size_t s, const Vector3d &h, const double k)
  {
    if (s >= nodes.size() || !(k > 0))
      throw std::invalid_argument("home spring that does not exist, or with stiffness <= 0");
    home.col(s)   = h;
    stiffness[s]  = k;
    lambda.col(s).setZero();
  }

  double
  HomeSprings::energy(const Matrix3Xd &x) const
  {
    double e = 0;
    for (std::size_t s = 0; s < nodes.size(); ++s)
      e += 0.5 * stiffness[s] * (x.col(nodes[s]) - home.col(s)).squaredNorm();
    return e;
  }

  void
  HomeSprings::add_forces(const Matrix3Xd &x, Matrix3Xd &f) const
  {
    for (std::size_t s = 0; s < nodes.size(); ++s)
      f.col(nodes[s]) += stiffness[s] * (home.col(s) - x.col(nodes[s]));
  }

  bool
  HomeSprings::element_nodes(std::vector<std::uint32_t> &list, unsigned &per_element) const
  {
    per_element = 1;
    list        = nodes;
    return true;
  }

  void
  HomeSprings::add_vertex_block(const Matrix3Xd &x, const std::uint32_t i, const std::uint32_t *springs,
                                const std::size_t n, Vector3d &f, Eigen::Matrix3d &H) const
  {
    for (std::size_t k = 0; k < n; ++k)
      {
        const auto s = springs[k];
        f += stiffness[s] * (home.col(s) - x.col(i));
        H.diagonal().array() += stiffness[s];
      }
  }

  void
  HomeSprings::add_constraint_forces(const Matrix3Xd &, Matrix3Xd &f, const double dt) const
  {
    for (std::size_t s = 0; s < nodes.size(); ++s)
      f.col(nodes[s]) += lambda.col(s) / (dt * dt);
  }

  void
  HomeSprings::reset_multipliers()
  {
    lambda.setZero();
  }

  void
  HomeSprings::warm_multipliers(const VectorXd &w, const double scale)
  {
    // a held node's spring is not projected (project() skips w = 0), so its multiplier
    // would stay frozen: it starts at zero, as in a cold step
    lambda *= scale;
    for (std::size_t s = 0; s < nodes.size(); ++s)
      if (w[nodes[s]] == 0)
        lambda.col(s).setZero();
  }

  void
  HomeSprings::project(Matrix3Xd &x, const VectorXd &w, const double dt)
  {
    for (std::size_t s = 0; s < nodes.size(); ++s)
      {
        const double wi = w[nodes[s]];
        if (wi == 0)
          continue;
        const double   alpha = 1 / (stiffness[s] * dt * dt);
        const Vector3d d_lambda =
          (-(x.col(nodes[s]) - home.col(s)) - alpha * lambda.col(s)) / (wi + alpha);
        lambda.col(s) += d_lambda;
        x.col(nodes[s]) += wi * d_lambda;
      }
  }

  double
  HomeSprings::max_violation(const Matrix3Xd &x) const
  {
    double m = 0;
    for (std::size_t s = 0; s < nodes.size(); ++s)
      m = std::max(m, (x.col(nodes[s]) - home.col(s)).norm());
    return m;
  }
} // namespace suturesim::realtime
