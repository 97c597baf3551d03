// The gmsh readers on their own: mesh/gmsh_reader.h (the realtime path's tetrahedra,
// through the gmsh API) and mesh/mesh_loader.h (the accurate path's hexahedra, through
// deal.II's GridIn; a .geo meshed by the gmsh CLI first): node and element counts,
// physical groups as tags, names and boundary ids, and a one-line InputError naming the
// file for what they cannot read. And the accurate path's local refinement from the
// scene (mesh/local_refinement.h): on meshes/block.geo (hexahedra of 5 mm) the cells near
// the named faces and near a needle path are refined Levels times and the far ones not
// at all; bad settings are a one-line error naming the parameter. That the tissue stays
// correct on such a mesh (hanging nodes, embedded points) is tested where it is solved:
// Condensation.*LocallyRefined* and AccurateNeedle.*Refined*.
#include "run_scene.h"

#include <suturesim/core/error.h>
#include <suturesim/mesh/gmsh_reader.h>
#include <suturesim/mesh/mesh_loader.h>
#include <suturesim/scene/simulation.h>

#include <deal.II/distributed/tria.h>

#include <Eigen/Geometry>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>

using namespace suturesim;
namespace fs = std::filesystem;

namespace
{
  /// A fresh folder for one test's files.
  std::string
  work_folder(const std::string &name)
  {
    const auto dir = test_support::scratch_path() / ("mesh_" + name);
    fs::remove_all(dir);
    fs::create_directories(dir);
    return dir.string();
  }

  std::string
  write(const std::string &dir, const std::string &name, const std::string &text)
  {
    const std::string file = dir + "/" + name;
    std::ofstream(file) << text;
    return file;
  }

  mesh::MeshParameters
  gmsh_source(const std::string &file, std::map<std::string, double> geo = {})
  {
    mesh::MeshParameters p;
    p.source         = "gmsh";
    p.file           = file;
    p.geo_parameters = std::move(geo);
    return p;
  }

  struct RefinedBlock
  {
    /// meshes/block.geo (40 x 40 x 10 mm, hexahedra of 5 mm) with @p local as the body of
    /// Mesh/Local refinement, created along @p path.
    RefinedBlock(const std::string &local, const std::vector<dealii::Point<3>> &path = {})
      : tria(MPI_COMM_WORLD)
    {
      dealii::ParameterHandler prm;
      scene::Simulation::declare_parameters(prm);
      const std::string text = "subsection Mesh\n set Source = gmsh\n set File = " +
                               test_support::source_path("meshes/block.geo") +
                               "\n set Geo parameters = h: 0.005, hexahedra: 1\n subsection Local refinement\n" + local +
                               " end\nend\n";
      file.emplace(prm, text, "refined.prm", ".");
      prm.enter_subsection("Mesh");
      parameters.parse(prm, ParameterScope(*file, "Mesh"));
      prm.leave_subsection();
      const auto dir = test_support::test_scratch("local_refinement");
      info = mesh::create_mesh(parameters, dir.string(), tria, path);
    }

    std::optional<ParameterFile>                    file;
    mesh::MeshParameters                            parameters;
    dealii::parallel::distributed::Triangulation<3>         tria;
    mesh::MeshInfo                                  info;
  };

  /// The message of the InputError @p f throws ("" if it throws none).
  template <typename F>
  std::string
  input_error(F &&f)
  {
    try
      {
        f();
      }
    catch (const InputError &e)
      {
        return e.what();
      }
    return "";
  }

  // The pyramid over the unit square with its apex above the origin, cut along the
  // square's diagonal into two tetrahedra: physical volume "dermis" (7), the two
  // triangles of the base as "bottom" (3); msh 2.2 as gmsh writes it.
  const std::string two_tetrahedra = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
2
2 3 "bottom"
3 7 "dermis"
$EndPhysicalNames
$Nodes
5
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
5 0 0 1
$EndNodes
$Elements
4
1 2 2 3 1 1 3 2
2 2 2 3 1 1 4 3
3 4 2 7 1 1 2 3 5
4 4 2 7 1 1 3 4 5
$EndElements
)";

  // Two hexahedra side by side along x, physical volume "dermis" (7), the face x = 0
  // as "left" (1) and both bottom quadrangles as "bottom" (2).
  const std::string two_hexahedra = R"($MeshFormat
2.2 0 8
$EndMeshFormat
$PhysicalNames
3
2 1 "left"
2 2 "bottom"
3 7 "dermis"
$EndPhysicalNames
$Nodes
12
1 0 0 0
2 1 0 0
3 1 1 0
4 0 1 0
5 0 0 1
6 1 0 1
7 1 1 1
8 0 1 1
9 2 0 0
10 2 1 0
11 2 0 1
12 2 1 1
$EndNodes
$Elements
5
1 3 2 1 1 1 4 8 5
2 3 2 2 2 1 2 3 4
3 3 2 2 2 2 9 10 3
4 5 2 7 1 1 2 3 4 5 6 7 8
5 5 2 7 1 2 9 10 3 6 11 12 7
$EndElements
)";
} // namespace

TEST(GmshReader, ReadsTetrahedraWithTheirPhysicalGroupsAndNames)
{
  const std::string dir  = work_folder("tetrahedra");
  const auto        mesh = mesh::read_simplex_mesh(gmsh_source(write(dir, "two.msh", two_tetrahedra)), dir);
  EXPECT_EQ(mesh.vertices.cols(), 5);
  ASSERT_EQ(mesh.tetrahedra.size(), 2u);
  EXPECT_EQ(mesh.tetrahedron_tags, (std::vector<int>{7, 7}));
  EXPECT_NEAR(mesh.volume(0) + mesh.volume(1), 1.0 / 3.0, 1e-15); // the pyramid over the unit square
  EXPECT_EQ(mesh.triangles.size(), 2u);
  EXPECT_EQ(mesh.triangle_tags, (std::vector<int>{3, 3}));
  EXPECT_EQ(mesh.boundary_names.at(3), "bottom");
  EXPECT_EQ(mesh.material_names.at(7), "dermis");
  EXPECT_EQ(mesh.boundary_id("bottom"), 3);
  EXPECT_EQ(mesh.boundary_id("3"), 3);
  EXPECT_EQ(mesh.boundary_id("side"), -1);
  EXPECT_NE(mesh.description.find("5 vertices, 2 tetrahedra"), std::string::npos) << mesh.description;

  // tests/data/tetrahedron.msh: one group, no names: the tag is the name
  const auto one = mesh::read_simplex_mesh(gmsh_source(test_support::source_path("tests/data/tetrahedron.msh")), dir);
  ASSERT_EQ(one.tetrahedra.size(), 1u);
  EXPECT_NEAR(one.volume(0), 1.0 / 6.0, 1e-15);
  EXPECT_EQ(one.material_names.at(1), "1");
  EXPECT_TRUE(one.triangles.empty());
}

TEST(GmshReader, ReadsTheBlockGeoThroughGmshIntoAClosedMeshOfItsVolume)
{
  // meshes/block.geo (40 x 40 x 10 mm) at h = 5 mm: the tetrahedra fill the block, the
  // "bottom" triangles tile z = 0
  const std::string dir  = work_folder("block_geo");
  const auto        mesh = mesh::read_simplex_mesh(
    gmsh_source(test_support::source_path("meshes/block.geo"), {{"h", 0.005}, {"hexahedra", 0}}), dir);
  ASSERT_GT(mesh.tetrahedra.size(), 100u);
  double volume = 0;
  for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
    volume += mesh.volume(t);
  EXPECT_NEAR(volume, 0.04 * 0.04 * 0.01, 1e-12 * 0.04 * 0.04 * 0.01);
  const int bottom = mesh.boundary_id("bottom"), top = mesh.boundary_id("top");
  ASSERT_GE(bottom, 0);
  ASSERT_GE(top, 0);
  double   area = 0;
  unsigned on_bottom = 0;
  for (std::size_t k = 0; k < mesh.triangles.size(); ++k)
    if (mesh.triangle_tags[k] == bottom)
      {
        const auto    &t = mesh.triangles[k];
        const Eigen::Vector3d a = mesh.vertices.col(t[0]), b = mesh.vertices.col(t[1]), c = mesh.vertices.col(t[2]);
        for (const auto &v : {a, b, c})
          EXPECT_EQ(v[2], 0.0);
        area += 0.5 * (b - a).cross(c - a).norm();
        ++on_bottom;
      }
  EXPECT_GT(on_bottom, 10u);
  EXPECT_NEAR(area, 0.04 * 0.04, 1e-12);
  // the boundary extracted from the tetrahedra carries those tags
  const auto surface = mesh::extract_boundary(mesh);
  EXPECT_FALSE(mesh::vertices_with_tag(surface, bottom).empty());
}

// No shell between suturesim and gmsh (issue 26): a .geo named with a quote and a space,
// as a patient's file may be, meshes, and neither a file name nor a Geo parameters key
// written as a shell command runs anything. Through a shell (std::system, as before)
// the quoted name failed with "Unterminated quoted string" and the other two created
// the marker file in the working folder.
TEST(GmshReader, AFileNameOrGeoParameterIsAnArgumentNeverACommand)
{
  const std::string dir    = work_folder("file_names");
  const fs::path    marker = fs::current_path() / "INJECTED_marker";
  fs::remove(marker);
  const std::map<std::string, double> tetrahedra{{"h", 0.01}, {"hexahedra", 0}};
  for (const std::string name : {"patient's block.geo", "x';touch INJECTED_marker;'.geo"})
    {
      const fs::path geo = fs::path(dir) / name;
      fs::copy_file(test_support::source_path("meshes/block.geo"), geo);
      const auto mesh = mesh::read_simplex_mesh(gmsh_source(geo.string(), tetrahedra), dir);
      EXPECT_GT(mesh.tetrahedra.size(), 10u) << name;
    }
  auto with_key                                     = tetrahedra;
  with_key["zz;touch INJECTED_marker;true"]         = 1;
  const auto mesh = mesh::read_simplex_mesh(gmsh_source(test_support::source_path("meshes/block.geo"), with_key), dir);
  EXPECT_GT(mesh.tetrahedra.size(), 10u);
  EXPECT_FALSE(fs::exists(marker)) << "a name or key ran as a command";
}

TEST(GmshReader, TheAccuratePathReadsHexahedraWithBoundaryIdsAndNames)
{
  const std::string                               dir = work_folder("hexahedra");
  dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
  const auto info = mesh::create_mesh(gmsh_source(write(dir, "two.msh", two_hexahedra)), dir, tria);
  EXPECT_EQ(tria.n_global_active_cells(), 2u);
  EXPECT_EQ(tria.n_vertices(), 12u);
  EXPECT_EQ(info.boundary_names.at(1), "left");
  EXPECT_EQ(info.boundary_names.at(2), "bottom");
  EXPECT_EQ(info.material_names.at(7), "dermis");
  std::map<dealii::types::boundary_id, unsigned> faces;
  for (const auto &cell : tria.active_cell_iterators())
    {
      EXPECT_EQ(cell->material_id(), 7u);
      for (const auto f : cell->face_indices())
        if (cell->face(f)->at_boundary())
          {
            const auto id = cell->face(f)->boundary_id();
            ++faces[id];
            // counted in faces[] below
            if (id == 1)
              {
                EXPECT_NEAR(cell->face(f)->center()[0], 0.0, 1e-15);
              }
            if (id == 2)
              {
                EXPECT_NEAR(cell->face(f)->center()[2], 0.0, 1e-15);
              }
          }
    }
  EXPECT_EQ(faces[1], 1u);
  EXPECT_EQ(faces[2], 2u);
  EXPECT_EQ(faces[0], 7u); // the other faces: deal.II's default id, named for outputs
  EXPECT_EQ(info.boundary_names.at(0), "boundary_0");

  // meshes/block.geo with hexahedra at h = 5 mm: 8 x 8 x 2 cells, its named faces
  dealii::parallel::distributed::Triangulation<3> block(MPI_COMM_WORLD);
  const auto geo = mesh::create_mesh(
    gmsh_source(test_support::source_path("meshes/block.geo"), {{"h", 0.005}, {"hexahedra", 1}}), dir, block);
  EXPECT_EQ(block.n_global_active_cells(), 128u);
  for (const char *name : {"bottom", "top"})
    {
      unsigned found = 0;
      for (const auto &[id, n] : geo.boundary_names)
        found += n == name;
      EXPECT_EQ(found, 1u) << name;
    }
}

TEST(GmshReader, MalformedInputIsOneLineNamingTheFile)
{
  const std::string dir = work_folder("malformed");
  // a file cut short inside its nodes
  const std::string cut = write(dir, "cut.msh", two_hexahedra.substr(0, two_hexahedra.find("7 1 1 1")));
  // an inverted tetrahedron (two vertices swapped)
  std::string inverted = two_tetrahedra;
  inverted.replace(inverted.find("3 4 2 7 1 1 2 3 5"), 17, "3 4 2 7 1 2 1 3 5");
  const std::string flipped = write(dir, "flipped.msh", inverted);
  unsigned          checked = 0;
  const auto        expect_one_line = [&](const std::string &message, const std::string &file, const char *fragment) {
    EXPECT_FALSE(message.empty()) << "no InputError for " << file;
    EXPECT_EQ(message.find('\n'), std::string::npos) << message;
    EXPECT_EQ(message.rfind(file, 0), 0u) << message;
    EXPECT_NE(message.find(fragment), std::string::npos) << message;
    ++checked;
  };
  dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
  expect_one_line(input_error([&] { mesh::create_mesh(gmsh_source(cut), dir, tria); }), cut, "cannot read");
  expect_one_line(input_error([&] { mesh::read_simplex_mesh(gmsh_source(cut), dir); }), cut, "cannot read");
  expect_one_line(input_error([&] { mesh::read_simplex_mesh(gmsh_source(flipped), dir); }), flipped,
                  "tetrahedron 0 is inverted");
  const std::string hex = test_support::source_path("tests/data/inverted_hex.msh");
  dealii::parallel::distributed::Triangulation<3> again(MPI_COMM_WORLD);
  expect_one_line(input_error([&] { mesh::create_mesh(gmsh_source(hex), dir, again); }), hex, "is inverted");
  // the realtime path's reader refuses hexahedra, naming the .geo switch
  expect_one_line(input_error([&] { mesh::read_simplex_mesh(gmsh_source(hex), dir); }), hex, "needs tetrahedra");
  EXPECT_EQ(checked, 5u);
}

TEST(LocalRefinement, RefinesTheCellsNearANamedFaceLevelsTimesAndNoOthers)
{
  // the top face (z = 10 mm), two levels within 1 mm: the top layer of 5 mm cells is
  // halved, then the upper half of that again; the bottom layer is left alone
  const RefinedBlock block(" set Levels = 2\n set Near boundaries = top\n set Distance = 0.001\n");
  unsigned           top = 0, bottom = 0;
  for (const auto &cell : block.tria.active_cell_iterators())
    {
      const double z = cell->center()[2];
      if (z > 0.0075)
        {
          EXPECT_EQ(cell->level(), 2) << cell->center();
          ++top;
        }
      if (z < 0.005)
        {
          EXPECT_EQ(cell->level(), 0) << cell->center();
          ++bottom;
        }
    }
  // 8 x 8 coarse columns: 64 bottom cells, 32 cells of 1.25 mm in the upper 2.5 mm of
  // each column, 4 of 2.5 mm below them
  EXPECT_EQ(bottom, 64u);
  EXPECT_EQ(top, 64u * 32u);
  EXPECT_EQ(block.tria.n_global_active_cells(), 64u + 64u * 4u + 64u * 32u);
}

TEST(LocalRefinement, RefinesAlongTheNeedlePathOnly)
{
  // a path along x at y = 0 on the plane between the two layers (z = 5 mm), from −12 to
  // 12 mm: the cells within half their diameter (4.33 mm) of it are the two layers of
  // the six columns either side of y = 0 it spans (centres 3.5 mm away); the next cells
  // out (centres 7.9 mm away, or 6.5 mm past the path's ends) are left alone
  const std::vector<dealii::Point<3>> path{dealii::Point<3>(-0.012, 0, 0.005), dealii::Point<3>(0.012, 0, 0.005)};
  const RefinedBlock          block(" set Levels = 1\n set Near needle path = true\n set Distance = 0\n", path);
  for (const auto &cell : block.tria.active_cell_iterators())
    {
      const dealii::Point<3> &c = cell->center();
      EXPECT_EQ(cell->level(), std::abs(c[1]) < 0.005 && std::abs(c[0]) < 0.015 ? 1 : 0) << c;
    }
  EXPECT_EQ(block.tria.n_global_active_cells(), 128u - 24u + 24u * 8u);
}

TEST(LocalRefinement, BadSettingsNameTheParameter)
{
  // an unknown face, refinement with nothing to refine near, a needle path in a scene
  // without a pass
  EXPECT_NE(input_error([] { RefinedBlock(" set Levels = 1\n set Near boundaries = wound\n"); })
              .find("Mesh/Local refinement/Near boundaries"),
            std::string::npos);
  EXPECT_NE(input_error([] { RefinedBlock(" set Levels = 1\n"); }).find("Mesh/Local refinement/Levels"),
            std::string::npos);
  EXPECT_NE(input_error([] { RefinedBlock(" set Levels = 1\n set Near needle path = true\n"); })
              .find("Mesh/Local refinement/Near needle path"),
            std::string::npos);
  // no refinement asked: the coarse mesh as it is
  EXPECT_EQ(RefinedBlock(" set Near boundaries = top\n").tria.n_global_active_cells(), 128u);
}

namespace
{
  /// meshes/skin_pad_incision.geo at h = 6 mm with its wound open (W_g = 0.4 mm), the
  /// mesh section's further settings @p mesh; the largest distance of a vertex on the
  /// incision's top edges (z = H) from the drawn cosine x = ±(W_g/2) cos(π y/L_i), and
  /// the count of such vertices.
  std::pair<double, unsigned>
  wound_edge_error(const std::string &mesh, dealii::parallel::distributed::Triangulation<3> &tria)
  {
    dealii::ParameterHandler prm;
    scene::Simulation::declare_parameters(prm);
    const std::string text = "subsection Mesh\n set Source = gmsh\n set File = " +
                             test_support::source_path("meshes/skin_pad_incision.geo") +
                             "\n set Geo parameters = h: 0.006, hexahedra: 1, Wg: 0.0004\n" + mesh + "end\n";
    ParameterFile file(prm, text, "pad.prm", ".");
    prm.enter_subsection("Mesh");
    mesh::MeshParameters parameters;
    parameters.parse(prm, ParameterScope(file, "Mesh"));
    prm.leave_subsection();
    const auto dir = test_support::test_scratch("snapped_pad");
    const mesh::MeshInfo info = mesh::create_mesh(parameters, dir.string(), tria);
    const double         Wg = 0.0004, Li = 0.020, H = 0.006;
    double               worst = 0;
    unsigned             count = 0;
    for (const auto &cell : tria.active_cell_iterators())
      {
        EXPECT_GT(cell->measure(), 0) << cell->center(); // snapping inverts no cell
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary() && info.boundary_name(cell->face(f)->boundary_id()).rfind("wound_", 0) == 0)
            for (const auto v : cell->face(f)->vertex_indices())
              {
                const dealii::Point<3> &x = cell->face(f)->vertex(v);
                if (std::abs(x[2] - H) > 1e-12)
                  continue;
                worst = std::max(worst, std::abs(std::abs(x[0]) - Wg / 2 * std::cos(M_PI * x[1] / Li)));
                ++count;
              }
      }
    return {worst, count};
  }
} // namespace

TEST(SnapToGeometry, RefinedWoundEdgesStayOnTheDrawnCosine)
{
  // Two global refinements of 6.67 mm cells along the incision: without snapping the new
  // vertices lie on the coarse chords, whose midpoint at y = 0 is (W_g/2) cos(π/6), 27 µm
  // inside the drawn edge; snapped, they lie on the drawn edge, gmsh's Spline through 17
  // points of the cosine, and on the top (z = H: the edge follows the surface's bounding
  // curve, not the surface, which would take it below the top). The drawn spline is
  // itself the cosine only to about 2e-8 m (measured: 1.4e-8 m at gmsh's own nodes of the
  // coarse mesh, 2.0e-8 m at the snapped vertices, 2026-11-27)
  dealii::parallel::distributed::Triangulation<3> chords(MPI_COMM_WORLD), snapped(MPI_COMM_WORLD);
  const auto [chord_error, chord_count] = wound_edge_error(" set Global refinements = 2\n", chords);
  const auto [snap_error, snap_count] =
    wound_edge_error(" set Global refinements = 2\n set Snap to geometry = wound_left, wound_right\n", snapped);
  std::printf("[ snap ] wound top-edge vertices off the cosine: %.3e m on the chords, %.3e m snapped (%u, %u "
              "face vertices)\n",
              chord_error, snap_error, chord_count, snap_count);
  EXPECT_GT(chord_count, 0u);
  EXPECT_EQ(snap_count, chord_count);
  EXPECT_GT(chord_error, 2e-5);
  EXPECT_LT(snap_error, 5e-8);
}

TEST(SnapToGeometry, BadSettingsNameTheParameter)
{
  // a boundary the mesh does not have
  EXPECT_NE(input_error([] {
              dealii::parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
              wound_edge_error(" set Global refinements = 1\n set Snap to geometry = incision\n", tria);
            }).find("Mesh/Snap to geometry"),
            std::string::npos);
}
