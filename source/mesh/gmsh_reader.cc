#include <suturesim/core/error.h>
#include <suturesim/mesh/gmsh_reader.h>

#include <gmsh.h>

#include <filesystem>
#include <stdexcept>
#include <unordered_map>

namespace suturesim::mesh
{
  namespace
  {
    /// gmsh's API is one global session; this scopes it to one read, also on errors.
    struct GmshSession
    {
      GmshSession()
      {
        gmsh::initialize(0, nullptr, false);
        gmsh::option::setNumber("General.Terminal", 0);
      }
      ~GmshSession()
      {
        gmsh::finalize();
      }
    };

    constexpr int gmsh_triangle = 2, gmsh_tetrahedron = 4, gmsh_hexahedron = 5;

    /// Elements of @p type on the entities of every physical group of dimension @p dim,
    /// as (physical tag, node tags) pairs; elements of no group are skipped (msh 2.2
    /// files written by gmsh hold only grouped elements).
    template <std::size_t n>
    void
    read_grouped(const int dim, const int type,
                 const std::unordered_map<std::size_t, std::uint32_t> &index,
                 std::vector<std::array<std::uint32_t, n>> &elements, std::vector<int> &tags,
                 std::map<int, std::string> &names)
    {
      gmsh::vectorpair groups;
      gmsh::model::getPhysicalGroups(groups, dim);
      for (const auto &[d, physical] : groups)
        {
          std::string name;
          gmsh::model::getPhysicalName(d, physical, name);
          names[physical] = name.empty() ? std::to_string(physical) : name;
          std::vector<int> entities;
          gmsh::model::getEntitiesForPhysicalGroup(d, physical, entities);
          for (const int entity : entities)
            {
              std::vector<std::size_t> element_tags, node_tags;
              gmsh::model::mesh::getElementsByType(type, element_tags, node_tags, entity);
              for (std::size_t e = 0; e < element_tags.size(); ++e)
                {
                  std::array<std::uint32_t, n> element;
                  for (std::size_t k = 0; k < n; ++k)
                    element[k] = index.at(node_tags[n * e + k]);
                  elements.push_back(element);
                  tags.push_back(physical);
                }
            }
        }
    }
  } // namespace

  SimplexMesh
  read_simplex_mesh(const MeshParameters &p, const std::string &work_directory)
  {
    if (p.source != "gmsh")
      throw InputError("Mesh/Source = " + p.source +
                       ": the realtime path reads gmsh meshes only (tetrahedra)");
    const std::string file = mesh_file(p, work_directory);
    SimplexMesh       mesh;
    std::size_t       n_hexahedra = 0;
    try
      {
        GmshSession session;
        gmsh::open(file);

        std::vector<std::size_t> node_tags;
        std::vector<double>      coordinates, parametric;
        gmsh::model::mesh::getNodes(node_tags, coordinates, parametric, -1, -1, false, false);
        std::unordered_map<std::size_t, std::uint32_t> index;
        mesh.vertices.resize(3, node_tags.size());
        for (std::size_t i = 0; i < node_tags.size(); ++i)
          {
            index[node_tags[i]] = i;
            for (int d = 0; d < 3; ++d)
              mesh.vertices(d, i) = p.scale * coordinates[3 * i + d];
          }
        read_grouped<4>(3, gmsh_tetrahedron, index, mesh.tetrahedra, mesh.tetrahedron_tags,
                        mesh.material_names);
        read_grouped<3>(2, gmsh_triangle, index, mesh.triangles, mesh.triangle_tags,
                        mesh.boundary_names);
        std::vector<std::size_t> hexahedra, hexahedron_nodes;
        gmsh::model::mesh::getElementsByType(gmsh_hexahedron, hexahedra, hexahedron_nodes);
        n_hexahedra = hexahedra.size();
      }
    catch (const std::exception &e)
      {
        throw InputError(p.file + ": cannot read the mesh through gmsh: " + e.what());
      }
    catch (...)
      {
        // gmsh's API reports errors by throwing its last message as a plain string.
        throw InputError(p.file + ": cannot read the mesh through gmsh");
      }
    if (mesh.tetrahedra.empty())
      throw InputError(p.file + ": the realtime path needs tetrahedra; the mesh has " +
                       std::to_string(n_hexahedra) +
                       " hexahedra and none (set Mesh/Geo parameters = hexahedra: 0 where "
                       "the .geo offers that switch)");
    for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
      if (!(mesh.volume(t) > 0))
        throw InputError(p.file + ": tetrahedron " + std::to_string(t) +
                         " is inverted or degenerate (volume " + std::to_string(mesh.volume(t)) +
                         " m^3)");
    mesh.description = "gmsh: " + std::filesystem::path(p.file).filename().string() + ", " +
                       std::to_string(mesh.vertices.cols()) + " vertices, " +
                       std::to_string(mesh.tetrahedra.size()) + " tetrahedra";
    return mesh;
  }
} // namespace suturesim::mesh
