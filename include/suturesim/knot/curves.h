#pragma once
/**
 * @file
 * Closed knots as parametric curves, t ∈ [0, 2π), each read along z into its standard
 * diagram (knot/diagram.h): the trefoil, three alternating crossings, the
 * figure-eight, four, and the cinquefoil, five. The tests draw ropes from them; rod/knot_tightening.h cuts one
 * open and lays it in a Cosserat rod.
 */

#include <Eigen/Core>

#include <cmath>

namespace suturesim::knot
{
  /// The least distance between the strands of trefoil(), figure_eight() and
  /// cinquefoil(), to four digits rounded down
  /// (KnotDiagram.TheClosedKnotsStrandsPassAtTheirClearance).
  constexpr double trefoil_clearance = 1.2143, figure_eight_clearance = 1.1408, cinquefoil_clearance = 1.1287;

  /// The trefoil (sin t + 2 sin 2t, cos t − 2 cos 2t, −sin 3t): its lobes reach 3 from
  /// the centre, its strands pass trefoil_clearance apart at their closest.
  inline Eigen::Vector3d
  trefoil(const double t)
  {
    return {std::sin(t) + 2 * std::sin(2 * t), std::cos(t) - 2 * std::cos(2 * t), -std::sin(3 * t)};
  }

  /// The figure-eight ((2 + cos 2t) cos 3t, (2 + cos 2t) sin 3t, sin 4t): it reaches 3
  /// from the axis at t = 0 and π, its strands pass figure_eight_clearance apart at
  /// their closest.
  inline Eigen::Vector3d
  figure_eight(const double t)
  {
    return {(2 + std::cos(2 * t)) * std::cos(3 * t), (2 + std::cos(2 * t)) * std::sin(3 * t), std::sin(4 * t)};
  }

  /// The cinquefoil, the (2, 5) torus knot 5₁ ((2 + cos 5t) cos 2t, (2 + cos 5t) sin 2t,
  /// −sin 5t): the overhand knot whose end goes round once more (seed 002's planner ties
  /// it so, knot::instructions()), Audoly, Clauvelin & Neukirch's (PRL 99, 164301,
  /// 2007) second knot beside the trefoil. It reaches 3 from the axis at t = 0, its
  /// strands pass cinquefoil_clearance apart at their closest.
  inline Eigen::Vector3d
  cinquefoil(const double t)
  {
    return {(2 + std::cos(5 * t)) * std::cos(2 * t), (2 + std::cos(5 * t)) * std::sin(2 * t), -std::sin(5 * t)};
  }
} // namespace suturesim::knot
