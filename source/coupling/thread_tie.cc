#include <suturesim/coupling/thread_tie.h>

namespace suturesim::coupling
{
  ThreadTie
  thread_tie(const Eigen::Vector3d &x, const Eigen::Vector3d &a, const Eigen::Vector3d &b, const double w_a,
             const double k)
  {
    using Mat3             = Eigen::Matrix3d;
    const double          w[2]  = {w_a, 1 - w_a};
    const double          s[2]  = {1, -1}; // ∂u/∂(a, b)
    const Eigen::Vector3d u     = a - b;
    const double          L     = u.norm();
    const Eigen::Vector3d t     = u / L;
    const Eigen::Vector3d d     = x - (w[0] * a + w[1] * b);
    const double          dt    = d.dot(t);
    const Mat3            P     = Mat3::Identity() - t * t.transpose();
    const Eigen::Vector3d E_d   = k * (P * d);
    const Eigen::Vector3d E_t   = -k * dt * d;
    const Mat3            E_dd  = k * P;
    const Mat3            E_dt  = -k * (dt * Mat3::Identity() + t * d.transpose());
    const Mat3            E_tt  = -k * d * d.transpose();
    const Mat3            t_u   = P / L;
    // E as a function of (d, u): its gradient and Hessian
    const Eigen::Vector3d E_u   = t_u * E_t;
    const Mat3            E_du  = E_dt * t_u;
    const Mat3            E_uu  = t_u * E_tt * t_u -
                           ((t * E_t.transpose() + E_t.dot(t) * Mat3::Identity()) * P + (P * E_t) * t.transpose()) /
                             (L * L);
    ThreadTie r;
    r.energy       = 0.5 * k * (d.squaredNorm() - dt * dt);
    r.tissue_force = -E_d;
    for (int i = 0; i < 2; ++i)
      {
        r.gradient.segment<3>(3 * i) = -w[i] * E_d + s[i] * E_u;
        for (int j = 0; j < 2; ++j)
          r.hessian.block<3, 3>(3 * i, 3 * j) = w[i] * w[j] * E_dd - w[i] * s[j] * E_du -
                                                s[i] * w[j] * E_du.transpose() + s[i] * s[j] * E_uu;
      }
    return r;
  }
} // namespace suturesim::coupling
