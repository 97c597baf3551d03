#pragma once
/**
 * @file
 * The tissue's surface displacement at the end of a run, `surface_displacement.json`:
 * the surface triangles with their vertices' material (reference) positions X and
 * displacements u = x − X, in m. The realtime path writes it at its surface nodes, the
 * accurate tissue scenes (scene/tissue_recorder.h) at the FE mesh's boundary vertices,
 * where the nodal values are the FE solution's, so that a study compares the realtime
 * surface with the FE displacement at the same material points (study/surface_error.h).
 * The accurate stitch does not write it yet: a study of the stitch cannot ask for
 * Metrics/Surface.
 *
 *   {"time": t, "reference": [[X, Y, Z], …], "displacement": [[ux, uy, uz], …],
 *    "triangles": [[i, j, k], …]}
 */

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace suturesim::io
{
  struct SurfaceField
  {
    double                                    time = 0; ///< s
    Eigen::Matrix3Xd                          reference;    ///< X, m
    Eigen::Matrix3Xd                          displacement; ///< u, m
    std::vector<std::array<std::uint32_t, 3>> triangles;

    /// The field on the vertices @p triangles use (indices into @p X and @p u), renumbered.
    static SurfaceField
    of(double time, const Eigen::Ref<const Eigen::Matrix3Xd> &X, const Eigen::Ref<const Eigen::Matrix3Xd> &u,
       const std::vector<std::array<std::uint32_t, 3>> &triangles);

    /// Writes @p file; throws std::runtime_error when it cannot be written.
    void
    write(const std::string &file) const;

    /// Reads @p file; throws std::runtime_error naming it when it is missing or malformed
    /// (sizes that disagree, an index out of range).
    static SurfaceField
    read(const std::string &file);
  };
} // namespace suturesim::io
