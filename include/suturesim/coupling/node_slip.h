#pragma once
/**
 * @file
 * Seed 001 §4's hole: a tissue point is joined to one node of the thread and moves with
 * it; "once the suture and tissue have been stretched enough, the required force [...]
 * will be greater than the friction between them": the point is then "detached from
 * node S₀ of the suture, and reattached to S₁", the next node in the direction it is
 * pulled. The thread's slip is quantised to its nodes: one node per step.
 *
 * Multiple slipping (seed 001 §4.2): each node keeps an ordered list of the points
 * joined to it, so points never pass each other. A point can leave its node forward only
 * with every point ahead of it on the same node ("it cannot slip without pulling the
 * left tissue's node with it"), and only when its own pull exceeds its friction and the
 * group's combined pull exceeds the group's combined friction. Backward alike. Two groups
 * that would swap between neighbouring nodes press on each other and neither moves.
 */

#include <vector>

namespace suturesim::coupling
{
  struct NodeSlipPoint
  {
    long   node  = 0; ///< index of the thread node the point is joined to
    /// force with which the tissue pulls the joint along the thread (+: towards higher
    /// node indices), N
    double pull  = 0;
    double limit = 0; ///< friction μ N of the point, N (≥ 0)
    int    moved = 0; ///< output: −1, 0, +1 nodes this step
  };

  /// One step of seed 001's rule. @p points are in thread order (nodes non-decreasing;
  /// points of one node in their list's order); their nodes stay within
  /// [@p first, @p last]. Sets `moved` and `node`; returns the number of points moved.
  std::size_t
  node_slip(std::vector<NodeSlipPoint> &points, long first, long last);
} // namespace suturesim::coupling
