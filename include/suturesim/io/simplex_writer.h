#pragma once
/**
 * @file
 * Tetrahedra or triangles with point data as a .vtu file (VTK XML UnstructuredGrid): the
 * realtime path's tissue output. One point per mesh node, shared by the cells around it
 * (deal.II's DataOutBase writes one patch of own vertices per cell, four times the
 * points, and cannot share them), Float32 coordinates and fields, each array deflated by
 * zlib at its fastest level (1) in blocks of 1 MiB, inline base64 with a UInt32 header
 * (VTK file formats, "XML File Formats", Kitware: compressed binary data). Vector fields
 * are marked as vectors, so ParaView's "Warp By Vector" applies to displacement.
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

  /// Writes tetrahedra (n_vertices = 4) or triangles (3) to @p file_name, with the time
  /// @p time (s) as FieldData TIME; throws WriteError when the file cannot be written and
  /// std::invalid_argument when a cell names a point that is not there or a field has
  /// another number of points.
  template <std::size_t n_vertices>
  void
  write_simplex_vtu(const std::string &file_name, const SimplexData<n_vertices> &data, double time);
} // namespace suturesim::io
