#pragma once
/**
 * @file
 * Pierce points along the thread (needle, then suture) never pass each other or a hard
 * constraint (seed 001 §4.2: "an ordered list of tissue nodes" per suture node; seed
 * 002 §4: "soft constraints cannot slip through each other, or past a hard
 * constraint"). Proposed thread coordinates ζ₁ ≤ ζ₂ ≤ … (the order in which they lie
 * on the thread) are projected onto the ordered set ζ_{k+1} − ζ_k ≥ g, lower ≤ ζ ≤
 * upper, in the least-squares sense: points that would cross merge into a block that
 * moves together at the mean of their proposals (pool-adjacent-violators, Ayer et al.
 * 1955, on ζ_k − k g). This is seed 001's "multiple slipping": a point that cannot slip
 * without pushing its neighbour moves only with it.
 */

#include <vector>

namespace suturesim::coupling
{
  /// Projects @p zeta (in thread order) in place; returns true when it changed anything.
  /// Throws std::invalid_argument when the points cannot fit (upper − lower < (n − 1) g).
  bool
  keep_order(std::vector<double> &zeta, double gap, double lower, double upper);
} // namespace suturesim::coupling
