#pragma once
/**
 * @file
 * Event location by linear interpolation within a step (Shampine & Thompson 2000, Appl.
 * Numer. Math. 32, 477–486): a quantity sampled at the ends of an accepted step, q₀ then
 * q₁, reaches a level q_c at the fraction
 *   s = (q₀ − q_c) / (q₀ − q₁)  ∈ [0, 1]
 * of the step, when q₀ and q₁ lie on either side of it (q₁ on or past it). Everything
 * read at the event (its time, the suture's tension then) is then interpolated with the
 * same s: for quantities smooth over the step the reading's error is O(Δt²) instead of
 * the O(Δt) of reading at the step's end. The wound's closure (scene/wound_closure.h)
 * and a tear criterion's onset (scene/tear_monitor.h) are read this way.
 */

namespace suturesim
{
  /// s above for a crossing of @p level from @p before to @p after, in either direction
  /// (falling: before ≥ level > after; rising: before < level ≤ after); 1, the step's
  /// end, when @p before is not on the other side (a NaN before: no sample there).
  inline double
  level_crossing(const double before, const double after, const double level)
  {
    const bool falling = before >= level && after < level;
    const bool rising  = before < level && after >= level;
    return falling || rising ? (before - level) / (before - after) : 1.0;
  }

  /// A quantity read at the fraction @p s of the step, linear between its values
  /// @p before and @p after at the step's ends.
  inline double
  at_fraction(const double before, const double after, const double s)
  {
    return before + s * (after - before);
  }
} // namespace suturesim
