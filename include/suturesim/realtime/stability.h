#pragma once
/**
 * @file
 * Stability limits of the force-based integrators from the spring network itself (the
 * rigorous form of seed 003's "dt inversely proportional to the square root of the
 * stiffness"). Linearised about a state x, the free nodes obey M ẍ = −K u (explicit
 * integration) or B ẋ = −K u (quasi-static V = F/B). Their fastest mode has
 * ω²_max = λ_max(M^{-1/2} K M^{-1/2}) resp. rate λ_max(B^{-1/2} K B^{-1/2}), estimated
 * here by Lanczos with full reorthogonalisation on the matrix-free product K u
 * (System::stiffness_product). The largest Ritz value converges from below; iterations
 * stop when its residual bound |β_j y_j| falls below the tolerance times the value.
 *
 * The limits themselves (integrator.h):
 *  - symplectic Euler v' = v + dt (F/m − c v), x' = x + dt v' on a mode of frequency ω is
 *    stable for c dt < 2 and dt²ω² < 4 − 2c dt, i.e. dt < (√(c² + 4ω²) − c)/ω², which is
 *    2/ω for c = 0 (the step's amplification matrix has determinant 1 − c dt and trace
 *    2 − c dt − dt²ω²; Jury's conditions);
 *  - quasi-static x' = x + dt B⁻¹F is explicit Euler on a gradient flow: dt < 2/λ_max.
 */

#include <suturesim/realtime/system.h>

namespace suturesim::realtime
{
  struct EigenvalueEstimate
  {
    double   value      = 0; ///< λ_max
    double   residual   = 0; ///< Lanczos residual bound of the Ritz value
    unsigned iterations = 0;
  };

  /// λ_max of D^{-1/2} K(x) D^{-1/2} over the nodes that are not held and have
  /// D_i > 0; @p diagonal holds D per node (mass, kg, or damping, N s/m).
  EigenvalueEstimate
  largest_eigenvalue(const System &system, const Matrix3Xd &x, const VectorXd &diagonal,
                     double tolerance = 1e-6, unsigned max_iterations = 300);

  /// Largest stable step of symplectic Euler with mass-proportional damping @p c (1/s)
  /// for a highest frequency @p omega (rad/s).
  double
  symplectic_euler_limit(double omega, double c);
} // namespace suturesim::realtime
