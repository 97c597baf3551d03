#pragma once
/**
 * @file
 * Tetrahedra or triangles with point data as a .vtu file, through deal.II's DataOutBase
 * (one simplex patch per cell, deal.II ≥ 9.3): the realtime path's tissue output. Vector
 * fields are marked as vectors, so ParaView's "Warp By Vector" applies to displacement.
 */

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace suturesim::io
{
  template <std::size_t n_vertices>
  struct SimplexData
  {
    Eigen::Matrix3Xd                                        points;
    std::vector<std::array<std::uint32_t, n_vertices>>      cells;
    std::vector<std::pair<std::string, Eigen::Matrix3Xd>>   vector_fields; ///< per point
    std::vector<std::pair<std::string, Eigen::VectorXd>>    scalar_fields; ///< per point
  };

  /// Writes tetrahedra (n_vertices = 4) or triangles (3) to @p file_name; throws
  /// std::runtime_error when the file cannot be written.
  template <std::size_t n_vertices>
  void
  write_simplex_vtu(const std::string &file_name, const SimplexData<n_vertices> &data, double time);
} // namespace suturesim::io
