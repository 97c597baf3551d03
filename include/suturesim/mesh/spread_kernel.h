#pragma once
/**
 * @file
 * The kernel that spreads a pierce point's load over the tissue within a radius ρ of
 * it, in both paths (`Pierce points/Load radius`):
 *
 *     φ(s) = (1 − s²)²  for s = |X' − X|/ρ < 1,  0 beyond,
 *
 * C¹ at s = 1 and positive inside: the smoothed delta of immersed-boundary methods,
 * which interpolate the point's motion and spread its force with the same weights
 * (Peskin 2002, Acta Numerica 11:479–517, §6). The accurate path integrates it against
 * the shape functions, W_I = ∫ φ N_I dV / ∫ φ dV (tissue/point_loads.h); the realtime
 * path samples it at the nodes, W_I = φ(s_I) m_I / Σ_J φ(s_J) m_J with the lumped masses
 * m_I = ρ_t ∫ N_I dV (realtime/needle_coupling.h): the same integral by the nodal
 * (lumping) rule.
 */

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace suturesim::mesh
{
  /// φ(s) of the spread kernel; @p s = distance / radius ≥ 0.
  inline double
  spread_kernel(const double s)
  {
    return s < 1 ? (1 - s * s) * (1 - s * s) : 0.0;
  }

  /// The nodal weights of a point at @p origin spread over @p radius (> 0) across the
  /// nodes [@p begin, @p end) at rest positions @p X (columns) with lumped masses
  /// @p mass: W_I = φ(|X_I − origin|/radius) m_I / Σ_J φ m_J, the nodes with W_I > 0
  /// and their weights appended to @p nodes and @p weights. Returns false, appending
  /// nothing, when no node with mass lies within the radius.
  inline bool
  spread_weights(const Eigen::Matrix3Xd &X, const Eigen::VectorXd &mass, const std::uint32_t begin,
                 const std::uint32_t end, const Eigen::Vector3d &origin, const double radius,
                 std::vector<std::uint32_t> &nodes, std::vector<double> &weights)
  {
    const std::size_t first = nodes.size();
    double            total = 0;
    for (std::uint32_t i = begin; i < end; ++i)
      if (const double w = spread_kernel((X.col(i) - origin).norm() / radius) * mass[i]; w > 0)
        {
          nodes.push_back(i);
          weights.push_back(w);
          total += w;
        }
    if (!(total > 0))
      return false;
    for (std::size_t j = first; j < weights.size(); ++j)
      weights[j] /= total;
    return true;
  }
} // namespace suturesim::mesh
