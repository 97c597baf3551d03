#pragma once
// What the rod tests share: random perturbations, a section with all six stiffnesses
// distinct, and the assembled Jacobian's finite-difference check.
#include <suturesim/rod/rod_model.h>

#include <random>

namespace suturesim::rod::test_support
{
  /// A vector with components uniform in [−scale, scale].
  inline Vec3
  random_vector(std::mt19937 &rng, const double scale)
  {
    std::uniform_real_distribution<double> u(-1, 1);
    return scale * Vec3(u(rng), u(rng), u(rng));
  }

  /// EA, GA₂, GA₃ = 3, 1.2, 0.7 N; GJ, EI₂, EI₃ = 0.4, 1.1, 0.9 N m².
  inline SectionStiffness
  anisotropic_section()
  {
    SectionStiffness s;
    s.force << 3.0, 1.2, 0.7;
    s.moment << 0.4, 1.1, 0.9;
    return s;
  }

  /// ‖J − J_fd‖/‖J‖ of @p model's assembled Jacobian (with @p extra terms) in its current
  /// state. J_fd: central differences D(s) of the residual along x + s e_k and
  /// exp(s ê_k)R, extrapolated as (4 D(h) − D(2h))/3, whose truncation error is O(h⁴)
  /// instead of O(h²). The state is restored after each difference.
  inline double
  jacobian_fd_error(RodModel &model, const double h, const NodalTerms *extra = nullptr)
  {
    const Eigen::MatrixXd J = model.dense_jacobian(extra);
    const auto            x = model.positions();
    const auto            q = model.rotations();
    const auto            restore = [&] {
      for (std::size_t i = 0; i < x.size(); ++i)
        model.set_node(i, x[i], q[i]);
    };
    const auto difference = [&](const Eigen::Index k, const double s) {
      Eigen::VectorXd d = Eigen::VectorXd::Zero(J.cols());
      d[k]              = s;
      model.update(d);
      const Eigen::VectorXd rp = model.residual(extra);
      restore();
      model.update(-d);
      const Eigen::VectorXd rm = model.residual(extra);
      restore();
      return Eigen::VectorXd((rp - rm) / (2 * s));
    };
    Eigen::MatrixXd J_fd(J.rows(), J.cols());
    for (Eigen::Index k = 0; k < J.cols(); ++k)
      J_fd.col(k) = (4 * difference(k, h) - difference(k, 2 * h)) / 3;
    return (J - J_fd).norm() / J.norm();
  }
} // namespace suturesim::rod::test_support
