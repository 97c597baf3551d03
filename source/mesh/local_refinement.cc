#include <suturesim/collision/proximity.h>
#include <suturesim/mesh/local_refinement.h>
#include <suturesim/mesh/mesh_loader.h>

#include <deal.II/base/utilities.h>

#include <algorithm>
#include <array>
#include <limits>

namespace suturesim::mesh
{
  using namespace dealii;

  void
  LocalRefinement::declare(ParameterHandler &prm)
  {
    prm.enter_subsection("Local refinement");
    prm.declare_entry("Levels", "0", Patterns::Integer(0, 6),
                      "Accurate path: rounds of refinement near the features below, each halving "
                      "the cells there (nested meshes: a series with ratio 2). Unit: 1. Range: 0-6.");
    prm.declare_entry("Near boundaries", "", Patterns::List(Patterns::Anything()),
                      "Boundaries (names or ids of the mesh) whose cells are refined, e.g. "
                      "'wound_left, wound_right'. Unit: none.");
    prm.declare_entry("Near needle path", "false", Patterns::Bool(),
                      "Refine along the needle's planned path through the tissue (Needle/Motion = "
                      "pass: the arc its tip follows from entry to exit). Unit: none.");
    prm.declare_entry("Distance", "0", Patterns::Double(0),
                      "A cell is refined when its centre is within this distance plus half its "
                      "diameter of a feature. Unit: m. Range: >= 0.");
    prm.leave_subsection();
  }

  void
  LocalRefinement::parse(ParameterHandler &prm, const ParameterScope &parent)
  {
    prm.enter_subsection("Local refinement");
    levels          = prm.get_integer("Levels");
    near_boundaries = Utilities::split_string_list(prm.get("Near boundaries"));
    near_path       = prm.get_bool("Near needle path");
    distance        = prm.get_double("Distance");
    prm.leave_subsection();
    scope = std::make_shared<ParameterScope>(parent.subsection("Local refinement"));
    scope->require(levels == 0 || near_path || !near_boundaries.empty(), "Levels",
                   "refinement needs Near boundaries or Near needle path");
  }

  namespace
  {
    using Vec = Eigen::Vector3d;

    Vec
    vec(const Point<3> &p)
    {
      return {p[0], p[1], p[2]};
    }

    double
    point_segment_distance(const Vec &p, const Vec &a, const Vec &b)
    {
      const Vec    ab = b - a;
      const double t  = ab.squaredNorm() > 0 ? std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0) : 0.0;
      return (p - (a + t * ab)).norm();
    }
  } // namespace

  void
  LocalRefinement::apply(const MeshInfo &mesh, const std::vector<Point<3>> &path,
                         parallel::distributed::Triangulation<3> &tria) const
  {
    if (levels == 0)
      return;
    scope->require(!near_path || !path.empty(), "Near needle path",
                   "needs a needle pass in the scene (Needle/Motion = pass, accurate path)");
    // the boundaries' faces as triangles, from the coarse mesh (which every process
    // holds whole; finer faces lie on them)
    std::vector<types::boundary_id> ids;
    for (const auto &name : near_boundaries)
      ids.push_back(mesh.boundary_id(name, *scope, "Near boundaries"));
    std::vector<std::array<Vec, 3>> triangles;
    for (const auto &cell : tria.cell_iterators_on_level(0))
      for (const auto f : cell->face_indices())
        if (cell->face(f)->at_boundary() &&
            std::find(ids.begin(), ids.end(), cell->face(f)->boundary_id()) != ids.end())
          {
            const auto face = cell->face(f);
            triangles.push_back({{vec(face->vertex(0)), vec(face->vertex(1)), vec(face->vertex(3))}});
            triangles.push_back({{vec(face->vertex(0)), vec(face->vertex(3)), vec(face->vertex(2))}});
          }
    const auto distance_to_features = [&](const Vec &x) {
      double d = std::numeric_limits<double>::infinity();
      Vec    bary;
      for (const auto &t : triangles)
        d = std::min(d, (x - collision::closest_point_on_triangle(x, t[0], t[1], t[2], bary)).norm());
      if (near_path)
        for (std::size_t k = 0; k + 1 < path.size(); ++k)
          d = std::min(d, point_segment_distance(x, vec(path[k]), vec(path[k + 1])));
      return d;
    };
    for (unsigned level = 0; level < levels; ++level)
      {
        for (const auto &cell : tria.active_cell_iterators())
          if (cell->is_locally_owned() &&
              distance_to_features(vec(cell->center())) <= distance + 0.5 * cell->diameter())
            cell->set_refine_flag();
        tria.execute_coarsening_and_refinement();
      }
  }
} // namespace suturesim::mesh
