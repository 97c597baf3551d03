#pragma once
/**
 * @file
 * A polyline (a rod's centreline) as a .vtu file, through deal.II's DataOutBase: every
 * segment is one patch, so per-segment values (forces, strains) show as constant along
 * the segment and per-node values (radius, contact force) are continuous. ParaView's
 * Tube filter with "Vary radius by scalar = radius" draws the suture at its true
 * thickness.
 */

#include <Eigen/Core>

#include <string>
#include <vector>

namespace suturesim::io
{
  struct PolylineData
  {
    std::vector<Eigen::Vector3d>                                  points;
    std::vector<std::pair<std::string, std::vector<double>>>      point_fields;   ///< per point
    std::vector<std::pair<std::string, std::vector<double>>>      segment_fields; ///< per segment
  };

  /// Writes @p data to @p file_name; throws std::runtime_error when the file cannot be
  /// written.
  void
  write_polyline_vtu(const std::string &file_name, const PolylineData &data, double time);
} // namespace suturesim::io
