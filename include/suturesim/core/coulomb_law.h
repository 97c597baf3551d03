#pragma once
/**
 * @file
 * Coulomb's law regularised by an elastic stick (the penalty regularisation of FE
 * contact: Wriggers 2006, "Computational Contact Mechanics", §5.2; Laursen 2002, §4), the
 * one statement of its stick test and slip return that every frictional contact of both
 * model paths uses: a pierce point on its thread (coupling/coulomb_friction.h, one
 * dimension) and the accurate suture against itself (rod/contact_friction.h, the
 * isotropic law in the contact's tangent plane, applied to the magnitude of the slip).
 *
 * With g the elastic slip (the distance between where the contact is and its anchor, m),
 * k_t the stick stiffness (N/m) and c = μ N the capacity (N): the trial force k_t |g|
 * sticks when k_t |g| ≤ c; otherwise the contact slips, carries c, and its anchor returns
 * to the distance c / k_t behind it, so that k_t |g| = c after the step.
 */

#include <cmath>

namespace suturesim
{
  /// true when the trial force @p stiffness |@p slip| stays within @p capacity (N).
  inline bool
  coulomb_sticks(const double stiffness, const double capacity, const double slip)
  {
    return std::abs(stiffness * slip) <= capacity;
  }

  /// The elastic slip left after a slipping step, c / k_t (m); 0 for a rigid stick.
  inline double
  coulomb_slip_gap(const double stiffness, const double capacity)
  {
    return stiffness > 0 ? capacity / stiffness : 0.0;
  }
} // namespace suturesim
