#include <suturesim/core/error.h>
#include <suturesim/core/interruption.h>
#include <suturesim/core/process.h>
#include <suturesim/mesh/gmsh_geometry.h>
#include <suturesim/mesh/mesh_loader.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/tensor.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_in.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <regex>
#include <set>
#include <sstream>
#include <thread>
#include <vector>

#include <sys/wait.h>

#ifndef SUTURESIM_GMSH
#  define SUTURESIM_GMSH "gmsh"
#endif

namespace suturesim::mesh
{
  using namespace dealii;
  namespace fs = std::filesystem;

  void
  MeshParameters::declare(ParameterHandler &prm)
  {
    prm.declare_entry("Source",
                      "gmsh",
                      Patterns::Selection("gmsh|cook membrane|deal.II"),
                      "Where the tissue mesh comes from: 'gmsh' (a .geo meshed by the gmsh "
                      "CLI, or a .msh), 'cook membrane' (the benchmark geometry of "
                      "references.md), or 'deal.II' (a GridGenerator function by name).");
    prm.declare_entry("File",
                      "meshes/skin_pad_incision.geo",
                      Patterns::FileName(),
                      "gmsh .geo or .msh file, relative to the scene file or to the "
                      "suturesim source tree. Hexahedral meshes only. Unit: none.");
    prm.declare_entry("Geo parameters",
                      "",
                      Patterns::Map(Patterns::Anything(), Patterns::Double(), 0,
                                    Patterns::Map::max_int_value, ",", ":"),
                      "Values passed to gmsh as -setnumber NAME VALUE, e.g. 'h: 0.0015'. "
                      "Unit: as the .geo file defines (SI for meshes/).");
    prm.declare_entry("Generator",
                      "hyper_rectangle",
                      Patterns::Anything(),
                      "deal.II GridGenerator function name (Source = deal.II), e.g. "
                      "'subdivided_hyper_rectangle'. Unit: none.");
    prm.declare_entry("Generator arguments",
                      "0, 0, 0 : 0.01, 0.01, 0.01 : true",
                      Patterns::Anything(),
                      "Arguments of the GridGenerator function as deal.II's "
                      "generate_from_name_and_arguments() reads them. Unit: m for lengths.");
    prm.declare_entry("Elements per edge",
                      "16",
                      Patterns::Integer(1, 1024),
                      "Cook's membrane: elements along each in-plane edge. Unit: 1. "
                      "Range: 1-1024.");
    prm.declare_entry("Thickness",
                      "0.001",
                      Patterns::Double(0),
                      "Cook's membrane: extrusion thickness (one element). Unit: m. "
                      "Range: > 0.");
    prm.declare_entry("Scale",
                      "1",
                      Patterns::Double(0),
                      "Factor applied to the mesh coordinates (e.g. 0.001 for a mesh in "
                      "mm). Unit: 1. Range: > 0.");
    prm.declare_entry("Global refinements",
                      "0",
                      Patterns::Integer(0, 10),
                      "Uniform refinements of the coarse mesh. Unit: 1. Range: 0-10.");
    prm.declare_entry("Maximum cells",
                      "1e6",
                      Patterns::Double(1),
                      "A guard against a mesh that would exhaust the memory: a coarse mesh whose "
                      "Global refinements would give more active cells than this (each refinement "
                      "multiplies them by 8) is refused before refining, and so is a mesh that "
                      "has more after its local refinement. Raise it for a larger mesh. Unit: 1. "
                      "Range: >= 1.");
    prm.declare_entry("Gmsh time limit",
                      "600",
                      Patterns::Double(0),
                      "A guard against a .geo meshed far finer than meant (e.g. Geo parameters "
                      "h: 1e-5): gmsh is stopped after this much wall time and the run refused. "
                      "Raise it for a larger mesh. Unit: s. Range: > 0.");
    prm.declare_entry("Gmsh memory limit",
                      "8e9",
                      Patterns::Double(0),
                      "A guard against a .geo meshed far finer than meant: gmsh's address "
                      "space is limited to this, so that it fails instead of exhausting the "
                      "machine's memory. Raise it for a larger mesh. Unit: B. Range: > 0.");
    prm.declare_entry("Snap to geometry",
                      "",
                      Patterns::List(Patterns::Anything()),
                      "Boundaries (names or ids) of a .geo mesh whose faces refinement "
                      "(global or local) puts on the .geo's surfaces, e.g. 'wound_left, "
                      "wound_right': without it a refined face's new vertices lie on its "
                      "parent's chords, and a curved face keeps the coarse mesh's polygon "
                      "at every level. Unit: none.");
    LocalRefinement::declare(prm);
  }

  void
  MeshParameters::parse(ParameterHandler &prm, const ParameterScope &scope)
  {
    source              = prm.get("Source");
    generator_name      = prm.get("Generator");
    generator_arguments = prm.get("Generator arguments");
    elements_per_edge   = prm.get_integer("Elements per edge");
    thickness           = prm.get_double("Thickness");
    scale               = prm.get_double("Scale");
    global_refinements  = prm.get_integer("Global refinements");
    maximum_cells       = prm.get_double("Maximum cells");
    gmsh_time_limit     = prm.get_double("Gmsh time limit");
    gmsh_memory_limit   = prm.get_double("Gmsh memory limit");
    scope.require(gmsh_time_limit > 0, "Gmsh time limit", "must be > 0 s");
    scope.require(gmsh_memory_limit > 0, "Gmsh memory limit", "must be > 0 B");
    scope.require(scale > 0, "Scale", "must be > 0");
    scope.require(thickness > 0, "Thickness", "must be > 0 m");
    local.parse(prm, scope);
    snap_to_geometry = Utilities::split_string_list(prm.get("Snap to geometry"));
    this->scope      = std::make_shared<const ParameterScope>(scope);

    geo_parameters.clear();
    const auto map = Patterns::Tools::Convert<std::map<std::string, double>>::to_value(
      prm.get("Geo parameters"),
      Patterns::Map(Patterns::Anything(), Patterns::Double(), 0,
                    Patterns::Map::max_int_value, ",", ":"));
    for (const auto &[k, v] : map)
      geo_parameters[k] = v;

    if (source == "gmsh")
      {
        const std::string given = prm.get("File");
        file                    = scope.parameter_file().resolve(given);
        scope.require(fs::exists(file), "File", "mesh file '" + given + "' not found");
        const std::string ext = fs::path(file).extension().string();
        scope.require(ext == ".geo" || ext == ".msh",
                      "File",
                      "mesh file '" + given + "' must end in .geo or .msh");
      }
    scope.require(snap_to_geometry.empty() || (source == "gmsh" && fs::path(file).extension() == ".geo"),
                  "Snap to geometry", "needs the geometry: a .geo mesh file (Source = gmsh)");
  }

  types::boundary_id
  MeshInfo::boundary_id(const std::string          &name_or_id,
                        const ParameterScope &scope,
                        const std::string          &key) const
  {
    for (const auto &[id, name] : boundary_names)
      if (name == name_or_id || std::to_string(id) == name_or_id)
        return id;
    std::string known;
    for (const auto &[id, name] : boundary_names)
      known += (known.empty() ? "" : ", ") + name + " (" + std::to_string(id) + ")";
    scope.fail(key, "no boundary '" + name_or_id + "' in the mesh; it has: " + known);
  }

  std::string
  MeshInfo::boundary_name(const types::boundary_id id) const
  {
    const auto it = boundary_names.find(id);
    return it == boundary_names.end() ? "boundary_" + std::to_string(id) : it->second;
  }

  namespace
  {
    /// $PhysicalNames of a .msh file: dimension → (tag → name).
    std::map<int, std::map<int, std::string>>
    read_physical_names(const std::string &file)
    {
      std::map<int, std::map<int, std::string>> names;
      std::ifstream                             in(file);
      std::string                               line;
      while (std::getline(in, line))
        if (line.rfind("$PhysicalNames", 0) == 0)
          {
            int n = 0;
            in >> n;
            for (int i = 0; i < n; ++i)
              {
                int         dim, tag;
                std::string name;
                in >> dim >> tag;
                std::getline(in, name);
                const auto b = name.find('"'), e = name.rfind('"');
                if (b != std::string::npos && e > b)
                  name = name.substr(b + 1, e - b - 1);
                names[dim][tag] = name;
              }
            break;
          }
      return names;
    }

    /// Cook's membrane (references.md): the trapezoid (0,0)–(48,44)–(48,60)–(0,44) mm
    /// extruded by the thickness, n × n × 1 cells. Boundary ids: 0 left (x = 0),
    /// 1 right (x = 48 mm), 2 bottom, 3 top, 4 back (z = −t/2), 5 front (z = +t/2).
    void
    make_cook_membrane(const MeshParameters &p, Triangulation<3> &tria)
    {
      const double t = p.thickness;
      GridGenerator::subdivided_hyper_rectangle(
        tria,
        {p.elements_per_edge, p.elements_per_edge, 1},
        Point<3>(0, 0, -0.5 * t),
        Point<3>(1, 1, 0.5 * t),
        true);
      GridTools::transform(
        [](const Point<3> &x) {
          const double s = x[0], r = x[1];
          return Point<3>(48e-3 * s, 44e-3 * s + r * (44e-3 - 28e-3 * s), x[2]);
        },
        tria);
    }

    void
    check_cells(const Triangulation<3> &tria, const std::string &what)
    {
      // det J of the trilinear map at the 2x2x2 Gauss points, from the vertices
      // (lexicographic: v = i + 2j + 4k). FEValues would assert on such a cell in a
      // Debug build before this message could be given.
      const double g[2] = {0.5 - 0.5 / std::sqrt(3.0), 0.5 + 0.5 / std::sqrt(3.0)};
      for (const auto &cell : tria.active_cell_iterators())
        for (const double x : g)
          for (const double y : g)
            for (const double z : g)
              {
                Tensor<2, 3> J;
                for (unsigned v = 0; v < 8; ++v)
                  {
                    const unsigned i = v & 1, j = (v >> 1) & 1, k = (v >> 2) & 1;
                    const double   a = i ? x : 1 - x, b = j ? y : 1 - y, c = k ? z : 1 - z;
                    const Tensor<1, 3> grad({(i ? 1. : -1.) * b * c, a * (j ? 1. : -1.) * c,
                                             a * b * (k ? 1. : -1.)});
                    J += outer_product(cell->vertex(v), grad);
                  }
                if (!(determinant(J) > 0))
                  {
                    std::ostringstream s;
                    s << what << ": cell " << cell->index() << " (centre " << cell->center()
                      << " m) is inverted or degenerate (Jacobian determinant <= 0 inside "
                         "the cell)";
                    throw InputError(s.str());
                  }
              }
    }
  } // namespace

  namespace
  {
    /// gmsh did not finish within Mesh/Gmsh time limit (run_gmsh()).
    constexpr int gmsh_timed_out = -2;
    /// gmsh stopped because this process received a stop signal: this minus the signal.
    constexpr int gmsh_stopped = -1000;

    /// Runs gmsh on the scene's .geo with an argument vector (no shell: a file name or a
    /// geo-parameter key is never read as a command), its output into @p log, stopped
    /// after Mesh/Gmsh time limit or a stop signal to this process. Returns gmsh's exit
    /// status, -1 if it could not be started or did not exit normally, gmsh_timed_out or
    /// gmsh_stopped minus the signal when it was stopped.
    int
    run_gmsh(const MeshParameters &p, const std::string &msh, const std::string &log)
    {
      // gmsh's address space limited before it starts: util-linux's prlimit sets the
      // soft limit and executes gmsh in its place (posix_spawn sets no limits, and one
      // set from here after the start would race gmsh's own start-up)
      std::ostringstream limit;
      if (p.gmsh_memory_limit >= 0x1p63)
        limit << "--as=unlimited:";
      else
        limit << "--as=" << static_cast<unsigned long long>(p.gmsh_memory_limit) << ":";
      std::vector<std::string> args{"prlimit", limit.str(), SUTURESIM_GMSH, "-3", "-format", "msh22", "-nt", "1"};
      const auto               setnumber = setnumber_arguments(p.geo_parameters);
      args.insert(args.end(), setnumber.begin(), setnumber.end());
      args.insert(args.end(), {"-o", msh, p.file});
      pid_t pid = 0;
      try
        {
          pid = start_process(args, log);
        }
      catch (const std::runtime_error &)
        {
          return -1;
        }
      const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(p.gmsh_time_limit);
      for (int status = 0;;)
        {
          const pid_t done = waitpid(pid, &status, WNOHANG);
          // Ctrl-C (which a terminal sends gmsh too) or SIGTERM: the run stops here
          const int stop = stop_received();
          if (done == pid)
            return stop != 0 ? gmsh_stopped - stop : WIFEXITED(status) ? WEXITSTATUS(status) : -1;
          const bool lost = done < 0 && errno != EINTR;
          if (lost || stop != 0 || std::chrono::steady_clock::now() > deadline)
            {
              kill(pid, SIGKILL);
              while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
                ;
              return lost ? -1 : stop != 0 ? gmsh_stopped - stop : gmsh_timed_out;
            }
          std::this_thread::sleep_for(std::chrono::milliseconds(20));
        }
    }
  } // namespace

  namespace
  {
    /// The first error gmsh's @p log reports (gmsh's "Error   : ..." or the loader's
    /// "... error ..."), at most 300 characters; "" when none.
    std::string
    gmsh_error(const std::string &log)
    {
      std::ifstream in(log);
      for (std::string line; std::getline(in, line);)
        if (line.rfind("Info", 0) != 0 && line.rfind("Warning", 0) != 0 &&
            (line.rfind("Error", 0) == 0 || line.find("error") != std::string::npos ||
             line.find("bad_alloc") != std::string::npos))
          return one_line(line.substr(0, 300));
      return "";
    }

    /// @p p's .geo meshed by gmsh (run_gmsh()) into @p work_directory/mesh.msh.
    std::string
    meshed_geo(const MeshParameters &p, const std::string &work_directory)
    {
      const std::string msh = (fs::path(work_directory) / "mesh.msh").string();
      const std::string log = (fs::path(work_directory) / "gmsh.log").string();
      int               status = 0;
      if (Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
        {
          fs::remove(msh);
          status = run_gmsh(p, msh, log);
          if (status == 0 && !fs::exists(msh))
            status = -1;
        }
      // Every rank learns the outcome, so that all throw together (no rank left waiting).
      MPI_Bcast(&status, 1, MPI_INT, 0, MPI_COMM_WORLD);
      if (status <= gmsh_stopped)
        throw Interrupted(gmsh_stopped - status, 0, "");
      if (status == gmsh_timed_out)
        {
          std::ostringstream why;
          why << "gmsh did not mesh " << p.file << " within " << p.gmsh_time_limit
              << " s (a mesh finer than meant? see Mesh/Geo parameters); raise it for a larger mesh";
          if (p.scope)
            p.scope->fail("Gmsh time limit", why.str());
          throw InputError("Mesh/Gmsh time limit: " + why.str());
        }
      if (status != 0)
        {
          const std::string said = gmsh_error(log);
          std::ostringstream why;
          why << p.file << ": gmsh failed (exit " << status << ")" << (said.empty() ? "" : ": " + said) << "; see "
              << log;
          // out of memory, or not even loaded: its address space was too small
          const bool memory = said.find("alloc") != std::string::npos || said.find("memory") != std::string::npos ||
                              said.find("map segment") != std::string::npos;
          if (!memory)
            throw InputError(why.str());
          why << "; its address space is limited to Mesh/Gmsh memory limit = " << p.gmsh_memory_limit
              << " B (raise it for a larger mesh)";
          if (p.scope)
            p.scope->fail("Gmsh memory limit", why.str());
          throw InputError("Mesh/Gmsh memory limit: " + why.str());
        }
      return msh;
    }
  } // namespace

  namespace
  {
    /// Gives the faces of each boundary of Snap to geometry a GmshSurfaceManifold on its
    /// surfaces (manifold ids 1, 3, …) and their edges where another boundary meets them
    /// one on those surfaces' bounding curves (2, 4, …), from the coarse mesh.
    void
    attach_geometry(const MeshParameters &p, const MeshInfo &info, parallel::distributed::Triangulation<3> &tria)
    {
      const auto geometry = std::make_shared<const GmshGeometry>(p.file, p.geo_parameters);
      // the boundary ids that meet at each coarse edge
      std::map<unsigned, std::set<types::boundary_id>> meeting;
      for (const auto &cell : tria.cell_iterators_on_level(0))
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary())
            for (const auto l : cell->face(f)->line_indices())
              meeting[cell->face(f)->line(l)->index()].insert(cell->face(f)->boundary_id());
      types::manifold_id id = 0;
      for (const auto &name : p.snap_to_geometry)
        {
          const types::boundary_id b        = info.boundary_id(name, *p.scope, "Snap to geometry");
          const std::vector<int>   surfaces = geometry->surfaces(info.boundary_name(b));
          if (surfaces.empty())
            p.scope->fail("Snap to geometry", "boundary '" + name + "' is no physical surface of " + p.file);
          const types::manifold_id on_surface = ++id, on_edge = ++id;
          for (const auto &cell : tria.cell_iterators_on_level(0))
            for (const auto f : cell->face_indices())
              if (cell->face(f)->at_boundary() && cell->face(f)->boundary_id() == b)
                {
                  cell->face(f)->set_manifold_id(on_surface);
                  for (const auto l : cell->face(f)->line_indices())
                    cell->face(f)->line(l)->set_manifold_id(
                      meeting[cell->face(f)->line(l)->index()].size() > 1 ? on_edge : on_surface);
                }
          tria.set_manifold(on_surface, GmshSurfaceManifold(geometry, 2, surfaces, p.scale));
          tria.set_manifold(on_edge, GmshSurfaceManifold(geometry, 1, geometry->boundary_curves(surfaces), p.scale));
        }
    }

    /// Refuses @p cells above Mesh/Maximum cells, naming @p key (of Mesh) and @p what
    /// gives them. Checked before a mesh is built where its size is known beforehand.
    void
    check_cell_count(const MeshParameters &p, const double cells, const std::string &key, const std::string &what)
    {
      if (cells <= p.maximum_cells)
        return;
      std::ostringstream why;
      why << what << " gives " << cells << " cells, above Mesh/Maximum cells = " << p.maximum_cells
          << " (raise it for a larger mesh)";
      if (p.scope)
        p.scope->fail(key, why.str());
      throw InputError("Mesh/" + key + ": " + why.str());
    }

    /// The cells of deal.II generator @p name with @p arguments before refinement where
    /// they are its first argument (the subdivided_* generators' repetitions), else 0.
    double
    generator_cells(const std::string &name, const std::string &arguments)
    {
      if (name.rfind("subdivided_", 0) != 0)
        return 0;
      double             cells = 1;
      std::istringstream repetitions(arguments.substr(0, arguments.find(':')));
      for (std::string n; std::getline(repetitions, n, ',');)
        {
          char        *end   = nullptr;
          const double value = std::strtod(n.c_str(), &end);
          if (end == n.c_str() || !std::isfinite(value))
            return 0; // not a list of repetitions: deal.II names what is wrong
          cells *= std::max(1.0, value);
        }
      return cells;
    }

    /// The volume elements of the gmsh ASCII mesh @p file (format 2 or 4), counted from
    /// its $Elements section element by element; 0 when it has no such section or is
    /// binary (the reader then says what is wrong, or reads it uncounted). Counted before
    /// the file is read, so that a mesh far larger than meant is refused before it fills
    /// the memory; lines are skipped, never held (a file of one huge line allocates
    /// nothing).
    double
    msh_volume_elements(const std::string &file)
    {
      constexpr auto rest = std::numeric_limits<std::streamsize>::max();
      std::ifstream  in(file);
      std::string    word;
      double         version = 0;
      int            binary  = 0;
      for (; in; in.ignore(rest, '\n'))
        if (in.peek() == '$' && in >> std::setw(64) >> word)
          {
            if (word == "$Elements")
              break;
            if (word == "$MeshFormat")
              in >> version >> binary;
          }
      if (!in || binary != 0)
        return 0;
      double cells = 0, count = 0;
      if (version >= 4)
        {
          // blocks "entityDim entityTag elementType count" (4.0: "entityTag entityDim
          // ..."), each followed by its elements, one per line
          double blocks = 0, total = 0, first = 0, second = 0, type = 0;
          in >> blocks >> total >> first >> second;
          for (double b = 0; b < blocks && in >> first >> second >> type >> count; ++b)
            {
              if ((version < 4.1 ? second : first) == 3)
                cells += count;
              in.ignore(rest, '\n');
              for (double e = 0; e < count && in; ++e)
                in.ignore(rest, '\n');
            }
          return cells;
        }
      // format 2: "number type tags ...", the types of gmsh's volume elements (linear and
      // higher-order tetrahedra, hexahedra, prisms, pyramids)
      static const std::set<int> volume_types{4, 5, 6, 7, 11, 12, 13, 14, 17, 18, 19, 29, 30, 31, 92, 93};
      long                       number = 0;
      int                        type   = 0;
      in >> count;
      for (double e = 0; e < count && in >> number >> type; ++e, in.ignore(rest, '\n'))
        cells += volume_types.count(type);
      return cells;
    }
  } // namespace

  std::string
  mesh_file(const MeshParameters &p, const std::string &work_directory)
  {
    const bool        geo = fs::path(p.file).extension() == ".geo";
    const std::string msh = geo ? meshed_geo(p, work_directory) : p.file;
    const double      cells = msh_volume_elements(msh);
    const bool        from_parameters = geo && p.scope && p.scope->parameter_file().given("Mesh/Geo parameters");
    check_cell_count(p, cells, from_parameters ? "Geo parameters" : "File",
                     fs::path(p.file).filename().string() + (geo ? " meshed by gmsh" : ""));
    return msh;
  }

  MeshInfo
  create_mesh(const MeshParameters                            &p,
              const std::string                               &work_directory,
              parallel::distributed::Triangulation<3>          &tria,
              const std::vector<Point<3>>                      &needle_path)
  {
    MeshInfo info;
    // The coarse mesh is built serially (identical on every rank) and handed to p4est,
    // which partitions it; a bad cell is reported before p4est sees it.
    Triangulation<3> coarse;
    std::string      what;
    if (p.source == "gmsh")
      {
        const std::string msh = mesh_file(p, work_directory);
        what                  = p.file;
        std::ifstream in(msh);
        GridIn<3>     grid_in;
        grid_in.attach_triangulation(coarse);
        try
          {
            grid_in.read_msh(in);
          }
        catch (const ExceptionBase &e)
          {
            std::ostringstream info_text;
            e.print_info(info_text);
            throw InputError(p.file + ": cannot read the mesh: " + one_line(info_text.str()));
          }
        const auto names = read_physical_names(msh);
        if (names.count(2))
          for (const auto &[tag, name] : names.at(2))
            info.boundary_names[tag] = name;
        if (names.count(3))
          for (const auto &[tag, name] : names.at(3))
            info.material_names[tag] = name;
        info.description = "gmsh: " + fs::path(p.file).filename().string();
      }
    else if (p.source == "cook membrane")
      {
        const double n = p.elements_per_edge;
        // the coarse mesh alone here; its refinements below
        check_cell_count(p, n * n, "Elements per edge",
                         "Cook's membrane of " + std::to_string(p.elements_per_edge) + " x " +
                           std::to_string(p.elements_per_edge) + " elements");
        make_cook_membrane(p, coarse);
        what                = "Cook's membrane";
        info.boundary_names = {{0, "left"}, {1, "right"}, {2, "bottom"},
                               {3, "top"},  {4, "back"},  {5, "front"}};
        info.description    = "Cook's membrane, " + std::to_string(p.elements_per_edge) +
                           " elements per edge";
      }
    else
      {
        what = "GridGenerator::" + p.generator_name;
        check_cell_count(p, generator_cells(p.generator_name, p.generator_arguments), "Generator arguments", what);
        const auto refuse = [&](const std::string &problem) {
          const std::string why = what + "(" + p.generator_arguments + "): " + problem;
          // the name when the scene gives it, else its arguments (the default name's)
          if (p.scope)
            p.scope->fail(p.scope->parameter_file().given("Mesh/Generator") ? "Generator" : "Generator arguments",
                          why);
          throw InputError(why);
        };
        try
          {
            GridGenerator::generate_from_name_and_arguments(coarse,
                                                            p.generator_name,
                                                            p.generator_arguments);
          }
        catch (const ExceptionBase &e)
          {
            std::ostringstream info_text;
            e.print_info(info_text);
            refuse(one_line(info_text.str()));
          }
        catch (const std::bad_alloc &)
          {
            refuse("the mesh does not fit in memory");
          }
        info.description = what;
      }

    if (!coarse.all_reference_cells_are_hyper_cube())
      throw InputError(what + ": the mesh has non-hexahedral cells; suturesim's tissue "
                              "model needs hexahedra (gmsh: Transfinite + Recombine)");
    if (p.scale != 1.0)
      GridTools::scale(p.scale, coarse);
    try
      {
        check_cells(coarse, what);
      }
    catch (const InputError &e)
      {
        // a scale that overflows the coordinates inverts every cell: name it, not the mesh
        if (p.scale == 1.0 || !p.scope)
          throw;
        std::ostringstream why;
        why << e.what() << " after scaling by " << p.scale;
        p.scope->fail("Scale", why.str());
      }

    for (const auto &face : coarse.active_face_iterators())
      if (face->at_boundary() && !info.boundary_names.count(face->boundary_id()))
        info.boundary_names[face->boundary_id()] = "boundary_" + std::to_string(face->boundary_id());

    tria.copy_triangulation(coarse);
    if (!p.snap_to_geometry.empty())
      attach_geometry(p, info, tria);
    // checked before refining: 10 refinements of a small mesh are 1e9 cells, which
    // exhausted the memory instead of being refused
    const double cells = coarse.n_active_cells() * std::pow(8.0, p.global_refinements);
    check_cell_count(p, cells, "Global refinements",
                     std::to_string(coarse.n_active_cells()) + " coarse cells refined " +
                       std::to_string(p.global_refinements) + " times");
    tria.refine_global(p.global_refinements);
    p.local.apply(info, needle_path, tria);
    check_cell_count(p, tria.n_global_active_cells(), "Local refinement/Levels", "the local refinement");
    if (!p.snap_to_geometry.empty())
      {
        // flat again: the manifolds, and with them the gmsh session, go with the refinement
        for (const auto &cell : tria.cell_iterators())
          cell->set_all_manifold_ids(numbers::flat_manifold_id);
        tria.reset_all_manifolds();
      }
    return info;
  }
} // namespace suturesim::mesh
