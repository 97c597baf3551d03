#pragma once
/**
 * @file
 * The tissue mesh of a scene: a gmsh .geo (meshed by the gmsh CLI at run time, so a
 * scene chooses its own resolution through `-setnumber`), a gmsh .msh, Cook's membrane,
 * or any deal.II GridGenerator shape by name. Physical groups of gmsh become boundary
 * and material ids, and their names are kept so that scene files and outputs can say
 * "bottom" rather than "1".
 */

#include <suturesim/core/parameter_file.h>
#include <suturesim/mesh/local_refinement.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/distributed/tria.h>

#include <map>
#include <memory>
#include <vector>
#include <string>

namespace suturesim::mesh
{
  struct MeshParameters
  {
    std::string                   source = "gmsh";
    std::string                   file;
    std::map<std::string, double> geo_parameters;
    std::string                   generator_name;
    std::string                   generator_arguments;
    unsigned                      elements_per_edge = 16;
    double                        thickness         = 1e-3;
    double                        scale             = 1.0;
    unsigned                      global_refinements = 0;
    /// the most active cells the refined mesh may have (Mesh/Maximum cells)
    double                        maximum_cells = 1e6;
    double                        gmsh_time_limit = 600; ///< s, meshing a .geo
    /// gmsh's address space, B (Mesh/Gmsh memory limit): a .geo meshed far finer than
    /// meant then fails in gmsh instead of exhausting the machine
    double                        gmsh_memory_limit = 8e9;
    LocalRefinement               local;
    /// Boundaries whose refined faces are put on the .geo's surfaces (gmsh_geometry.h).
    std::vector<std::string>      snap_to_geometry;
    /// Where these were read, for errors that name their entry.
    std::shared_ptr<const ParameterScope> scope;

    static void
    declare(dealii::ParameterHandler &prm);
    /// Resolves the mesh file against the scene file; a missing file is an InputError.
    void
    parse(dealii::ParameterHandler &prm, const ParameterScope &scope);
  };

  struct MeshInfo
  {
    std::map<dealii::types::boundary_id, std::string> boundary_names;
    std::map<dealii::types::material_id, std::string> material_names;
    std::string                                       description;

    /// The id of a boundary given by name or number; InputError through @p scope if
    /// unknown.
    dealii::types::boundary_id
    boundary_id(const std::string          &name_or_id,
                const ParameterScope &scope,
                const std::string          &key) const;

    std::string
    boundary_name(dealii::types::boundary_id id) const;
  };

  /// The gmsh mesh file of @p parameters: a .msh as given, a .geo meshed by the gmsh CLI
  /// (with its Geo parameters, under Mesh/Gmsh time limit and Gmsh memory limit) into
  /// @p work_directory/mesh.msh. InputError naming the file and gmsh's log when gmsh
  /// fails, and naming Mesh/Maximum cells when the file holds more volume elements
  /// (counted before it is read).
  std::string
  mesh_file(const MeshParameters &parameters, const std::string &work_directory);

  /// Builds the coarse mesh into @p tria (refined globally, then locally near the
  /// features of Local refinement, @p needle_path among them; the new vertices of the
  /// boundaries of Snap to geometry on the .geo's surfaces), running gmsh into
  /// @p work_directory when the source is a .geo. Checks every cell for a positive
  /// Jacobian determinant; an inverted or degenerate cell is an InputError naming the
  /// file and the cell.
  MeshInfo
  create_mesh(const MeshParameters                         &parameters,
              const std::string                            &work_directory,
              dealii::parallel::distributed::Triangulation<3> &tria,
              const std::vector<dealii::Point<3>>             &needle_path = {});
} // namespace suturesim::mesh
