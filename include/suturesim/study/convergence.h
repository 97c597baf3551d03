#pragma once
/**
 * @file
 * Grid convergence of a scalar f under refinement (issue 24), after Celik et al.,
 * "Procedure for estimation and reporting of uncertainty due to discretization in CFD
 * applications", J. Fluids Eng. 130 (2008) 078001, on three sizes h₁ < h₂ < h₃ with
 * ratios r₂₁ = h₂/h₁, r₃₂ = h₃/h₂ and differences ε₂₁ = f₂ − f₁, ε₃₂ = f₃ − f₂:
 *
 *   observed order   p = | ln|ε₃₂/ε₂₁| + q(p) | / ln r₂₁,
 *                    q(p) = ln( (r₂₁ᵖ − s)/(r₃₂ᵖ − s) ),  s = sign(ε₃₂/ε₂₁)
 *                    (fixed-point iteration; q = 0 for a constant ratio);
 *   Richardson       f_ext = (r₂₁ᵖ f₁ − f₂)/(r₂₁ᵖ − 1);
 *   fine-grid GCI    GCI₂₁ = 1.25 |(f₁ − f₂)/f₁| / (r₂₁ᵖ − 1)    (Roache, 1994:
 *                    safety factor 1.25 for three grids).
 *
 * Oscillatory convergence (s < 0) is reported as such: the order is still computed from
 * |ε₃₂/ε₂₁| as Celik et al. do, and flagged. So is divergence: the absolute value in p
 * hides differences that grow under refinement (|ε₂₁| > |ε₃₂| at equal ratios, an order
 * below zero), which give a large positive p; the sign of ln|ε₃₂/ε₂₁| + q(p) tells them
 * apart, and such a series has no asymptotic range either.
 */

#include <vector>

namespace suturesim::study
{
  struct ConvergenceEstimate
  {
    double order         = 0; ///< p, 1
    double extrapolated  = 0; ///< f_ext, unit of f
    double gci_fine      = 0; ///< GCI₂₁, 1 (relative)
    bool   oscillatory   = false;
    bool   diverging     = false; ///< the differences grow under refinement (signed order < 0)
    bool   converged     = true; ///< false when ε₂₁ = 0 or the iteration did not settle
  };

  /// The estimate from the three finest of (h, f) pairs @p h (m), @p f; throws
  /// std::invalid_argument unless h has ≥ 3 distinct sizes of the same sign.
  ConvergenceEstimate
  estimate_convergence(std::vector<double> h, std::vector<double> f);
} // namespace suturesim::study
