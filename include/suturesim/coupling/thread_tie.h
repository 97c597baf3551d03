#pragma once
/**
 * @file
 * The transverse tie of a pierced tissue point to a straight piece of thread, as an
 * energy, so that both sides get its exact derivatives — the thread's included, which
 * sees the tie turn with its element.
 *
 * Thread element with nodes a, b; the tie's point on it c = w_a a + w_b b (w_b = 1 − w_a)
 * and its direction t = u/|u|, u = a − b. The tissue point x is tied across the thread:
 *   E = ½ k |P d|² = ½ k (d·d − (d·t)²),   d = x − c,   P = I − t tᵀ
 * (the node-path constraint of seed 004 as a penalty). Derivatives:
 *   E_d = k P d,  E_t = −k (d·t) d,  E_dd = k P,  E_dt = −k((d·t) I + t dᵀ),
 *   E_tt = −k d dᵀ,  ∂t/∂u = P/|u|,
 * and ∂/∂u of (∂t/∂u)ᵀ a at fixed a = −[(t aᵀ + (a·t) I) P + (P a) tᵀ]/|u|².
 * On the nodes (∂d/∂a = −w_a I, ∂u/∂a = I, ∂u/∂b = −I) these give the thread's gradient
 * (6) and Hessian (6 × 6) with the tissue point held; the tissue side is f = −k P d with
 * ∂f/∂x = −k P (t fixed while the thread is held). The gradient's part beyond w_a k P d
 * is a couple: the tie's moment about the thread.
 */

#include <Eigen/Core>

namespace suturesim::coupling
{
  struct ThreadTie
  {
    double                        energy = 0;                              ///< J
    Eigen::Vector3d               tissue_force = Eigen::Vector3d::Zero();  ///< −E_x, N
    Eigen::Matrix<double, 6, 1>   gradient;  ///< ∂E/∂(a, b), N
    Eigen::Matrix<double, 6, 6>   hessian;   ///< ∂²E/∂(a, b)², N/m
  };

  /// The tie of tissue point @p x to the element (@p a, @p b) at weight @p w_a of a, with
  /// stiffness @p k (N/m).
  ThreadTie
  thread_tie(const Eigen::Vector3d &x, const Eigen::Vector3d &a, const Eigen::Vector3d &b, double w_a, double k);
} // namespace suturesim::coupling
