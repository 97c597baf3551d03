#pragma once
/**
 * @file
 * Reads a gmsh mesh into the realtime path's SimplexMesh through the gmsh API: the
 * tetrahedra of every physical volume (with its tag), the triangles of every physical
 * surface (with its tag) and the physical names. The accurate path reads the same
 * files through deal.II's GridIn; a .geo offers both element types through its own
 * switch (meshes/block.geo: `hexahedra`; meshes/skin_pad_incision.geo: `hexahedra`).
 */

#include <suturesim/mesh/mesh_loader.h>
#include <suturesim/mesh/simplex_mesh.h>

#include <string>

namespace suturesim::mesh
{
  /// The tetrahedral mesh of @p parameters (gmsh source only; meshed into
  /// @p work_directory when a .geo). InputError naming the file when gmsh fails, when the
  /// mesh has no tetrahedra (e.g. hexahedra: the message names the .geo switch), or when
  /// a tetrahedron is inverted.
  SimplexMesh
  read_simplex_mesh(const MeshParameters &parameters, const std::string &work_directory);
} // namespace suturesim::mesh
