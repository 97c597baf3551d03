#include <suturesim/rod/generalized_alpha.h>

#include <cmath>

namespace suturesim::rod
{
  namespace
  {
    /// J_r(ψ)⁻¹ = I + ½ψ̂ + (1/φ² − (1 + cos φ)/(2φ sin φ)) ψ̂², φ = |ψ|.
    Mat3
    right_jacobian_inverse(const Vec3 &psi)
    {
      const double phi = psi.norm();
      const Mat3   P   = skew(psi);
      const double b   = phi < 1e-4 ? 1.0 / 12 + phi * phi / 720
                                    : 1 / (phi * phi) - (1 + std::cos(phi)) / (2 * phi * std::sin(phi));
      return Mat3::Identity() + 0.5 * P + b * P * P;
    }
  } // namespace

  GeneralizedAlpha::GeneralizedAlpha(RodModel &model, const double rho, const double damping)
    : model(model)
    , c(damping)
  {
    alpha_m = (2 * rho - 1) / (rho + 1);
    alpha_f = rho / (rho + 1);
    gamma   = 0.5 + alpha_f - alpha_m;
    beta    = 0.25 * (gamma + 0.5) * (gamma + 0.5);
    const std::size_t n = model.n_nodes();
    v.assign(n, Vec3::Zero());
    W   = a_x = a_w = acc_x = acc_w = v;
    x0  = model.positions();
    q0  = model.rotations();
  }

  void
  GeneralizedAlpha::initialize(const std::vector<Vec3> &velocity, const std::vector<Vec3> &omega)
  {
    v  = velocity;
    W  = omega;
    x0 = model.positions();
    q0 = model.rotations();
    // M v̇₀ = −r(q₀) − gyroscopic and damping terms
    const Eigen::VectorXd r = model.residual();
    for (std::size_t i = 0; i < model.n_nodes(); ++i)
      {
        const NodeInertia &in = model.inertia(i);
        const Vec3 Rt_r = model.rotations()[i].conjugate() * Vec3(r.segment<3>(6 * i + 3));
        const Vec3 JW   = in.rotational.cwiseProduct(W[i]);
        for (unsigned d = 0; d < 3; ++d)
          {
            acc_x[i][d] = model.is_constrained(i, d) ? 0 : (-r[6 * i + d] - c * in.mass * v[i][d]) / in.mass;
            acc_w[i][d] = model.is_constrained(i, 3 + d)
                            ? 0
                            : (-Rt_r[d] - W[i].cross(JW)[d] - c * JW[d]) / in.rotational[d];
          }
      }
    a_x = acc_x;
    a_w = acc_w;
  }

  GeneralizedAlpha::NodeKinematics
  GeneralizedAlpha::kinematics(const std::size_t i, const Vec3 &x, const Quat &q, const double h) const
  {
    NodeKinematics k;
    const auto     advance = [&](const Vec3 &psi, const Vec3 &v0, const Vec3 &a0, const Vec3 &acc0,
                             Vec3 &a, Vec3 &vel, Vec3 &acc) {
      a   = (psi - h * v0 - h * h * (0.5 - beta) * a0) / (h * h * beta);
      vel = v0 + h * (1 - gamma) * a0 + h * gamma * a;
      acc = ((1 - alpha_m) * a + alpha_m * a0 - alpha_f * acc0) / (1 - alpha_f);
    };
    advance(x - x0[i], v[i], a_x[i], acc_x[i], k.a_x, k.v, k.acc_x);
    k.psi = quaternion_log(q0[i].conjugate() * q);
    advance(k.psi, W[i], a_w[i], acc_w[i], k.a_w, k.W, k.acc_w);
    return k;
  }

  NodalTerms
  GeneralizedAlpha::inertia_terms(const double h)
  {
    const double bp = (1 - alpha_m) / ((1 - alpha_f) * h * h * beta); // ∂v̇/∂Ψ
    const double gp = gamma / (h * beta);                             // ∂v/∂Ψ
    return [this, h, bp, gp](const std::size_t i, const Vec3 &x, const Quat &q, Vec6 &r, Mat6 &J) {
      const NodeInertia   &in = model.inertia(i);
      const NodeKinematics k  = kinematics(i, x, q, h);
      r.head<3>()             = in.mass * (k.acc_x + c * k.v);
      J.topLeftCorner<3, 3>() = in.mass * (bp + c * gp) * Mat3::Identity();
      const Vec3 &Jd    = in.rotational;
      const Vec3  JW    = Jd.cwiseProduct(k.W);
      const Vec3  m_mat = Jd.cwiseProduct(k.acc_w) + k.W.cross(JW) + c * JW;
      const Mat3  R     = q.toRotationMatrix();
      const Vec3  m_sp  = R * m_mat;
      r.tail<3>()       = m_sp;
      const Mat3 dm     = (bp + c * gp) * Mat3(Jd.asDiagonal()) + gp * (skew(k.W) * Jd.asDiagonal() - skew(JW));
      J.bottomRightCorner<3, 3>() = -skew(m_sp) + R * dm * right_jacobian_inverse(k.psi) * R.transpose();
    };
  }

  NewtonResult
  GeneralizedAlpha::step(const double h, const NewtonParameters &newton,
                         const std::vector<std::size_t> &prescribed)
  {
    const std::size_t n = model.n_nodes();
    // the prescribed nodes were set by the caller; save their targets
    std::vector<std::pair<Vec3, Quat>> target;
    for (const std::size_t i : prescribed)
      target.emplace_back(model.positions()[i], model.rotations()[i]);
    // predictor: constant pseudo-acceleration
    for (std::size_t i = 0; i < n; ++i)
      {
        const Vec3 dx  = h * v[i] + 0.5 * h * h * a_x[i];
        const Vec3 dth = h * W[i] + 0.5 * h * h * a_w[i];
        Vec3       ux  = dx;
        Vec3       uw  = dth;
        for (unsigned d = 0; d < 3; ++d)
          {
            if (model.is_constrained(i, d))
              ux[d] = 0;
            if (model.is_constrained(i, 3 + d))
              uw[d] = 0;
          }
        model.set_node(i, x0[i] + ux, q0[i] * quaternion_exp(uw));
      }
    for (std::size_t k = 0; k < prescribed.size(); ++k)
      model.set_node(prescribed[k], target[k].first, target[k].second);

    // round-off of the inertia terms: ε |x| m v̇'(Ψ), with v̇' = ∂v̇/∂Ψ ~ 1/(βh²)
    double extent = 0, mass = 0;
    for (std::size_t i = 0; i < n; ++i)
      {
        extent = std::max(extent, x0[i].cwiseAbs().maxCoeff());
        mass   = std::max(mass, model.inertia(i).mass);
      }
    NewtonParameters prm = newton;
    prm.absolute_floor   = std::max(prm.absolute_floor,
                                    1e-14 * extent * mass * (1 - alpha_m) / ((1 - alpha_f) * h * h * beta));
    const NodalTerms   terms  = inertia_terms(h);
    const NewtonResult result = model.solve(prm, &terms);
    if (!result.converged)
      {
        for (std::size_t i = 0; i < n; ++i)
          model.set_node(i, x0[i], q0[i]);
        return result;
      }
    residual = model.residual(&terms);
    // update the kinematic state to tₙ₊₁
    for (std::size_t i = 0; i < n; ++i)
      {
        const NodeKinematics k = kinematics(i, model.positions()[i], model.rotations()[i], h);
        a_x[i]                 = k.a_x;
        v[i]                   = k.v;
        acc_x[i]               = k.acc_x;
        a_w[i]                 = k.a_w;
        W[i]                   = k.W;
        acc_w[i]               = k.acc_w;
      }
    x0 = model.positions();
    q0 = model.rotations();
    return result;
  }
} // namespace suturesim::rod
