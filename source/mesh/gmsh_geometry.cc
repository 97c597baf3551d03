#include <suturesim/core/error.h>
#include <suturesim/mesh/gmsh_geometry.h>

#include <gmsh.h>

#include <iomanip>
#include <limits>
#include <sstream>

namespace suturesim::mesh
{
  std::vector<std::string>
  setnumber_arguments(const std::map<std::string, double> &parameters)
  {
    std::vector<std::string> args;
    for (const auto &[k, v] : parameters)
      {
        std::ostringstream value;
        value << std::setprecision(17) << v;
        args.insert(args.end(), {"-setnumber", k, value.str()});
      }
    return args;
  }

  GmshGeometry::GmshGeometry(const std::string &geo, const std::map<std::string, double> &parameters)
    : file(geo)
  {
    // the geo parameters as on gmsh's command line, which initialize() reads
    std::vector<std::string> args{"gmsh"};
    const auto               setnumber = setnumber_arguments(parameters);
    args.insert(args.end(), setnumber.begin(), setnumber.end());
    std::vector<char *> argv;
    for (auto &a : args)
      argv.push_back(a.data());
    try
      {
        gmsh::initialize(static_cast<int>(argv.size()), argv.data(), false);
        gmsh::option::setNumber("General.Terminal", 0);
        gmsh::open(geo);
      }
    catch (...)
      {
        // gmsh's API reports errors by throwing its last message as a plain string
        gmsh::finalize();
        throw InputError(geo + ": gmsh cannot read its geometry");
      }
  }

  GmshGeometry::~GmshGeometry()
  {
    gmsh::finalize();
  }

  std::vector<int>
  GmshGeometry::surfaces(const std::string &name) const
  {
    gmsh::vectorpair groups;
    gmsh::model::getPhysicalGroups(groups, 2);
    std::vector<int> tags;
    for (const auto &[dim, physical] : groups)
      {
        std::string group;
        gmsh::model::getPhysicalName(dim, physical, group);
        if (group == name || std::to_string(physical) == name)
          {
            std::vector<int> entities;
            gmsh::model::getEntitiesForPhysicalGroup(dim, physical, entities);
            tags.insert(tags.end(), entities.begin(), entities.end());
          }
      }
    return tags;
  }

  std::vector<int>
  GmshGeometry::boundary_curves(const std::vector<int> &surfaces) const
  {
    gmsh::vectorpair in, out;
    for (const int tag : surfaces)
      in.emplace_back(2, tag);
    gmsh::model::getBoundary(in, out, false, false, false);
    std::vector<int> curves;
    for (const auto &[dim, tag] : out)
      if (dim == 1)
        curves.push_back(tag);
    return curves;
  }

  dealii::Point<3>
  GmshGeometry::closest_point(const int dim, const std::vector<int> &tags, const dealii::Point<3> &p) const
  {
    dealii::Point<3> best = p;
    double           d    = std::numeric_limits<double>::infinity();
    for (const int tag : tags)
      {
        std::vector<double> closest, parametric;
        gmsh::model::getClosestPoint(dim, tag, {p[0], p[1], p[2]}, closest, parametric);
        if (closest.size() != 3)
          throw SolverError(file + ": gmsh found no closest point on entity (" + std::to_string(dim) + ", " +
                            std::to_string(tag) + ")");
        const dealii::Point<3> q(closest[0], closest[1], closest[2]);
        if (const double dq = q.distance(p); dq < d)
          {
            d    = dq;
            best = q;
          }
      }
    return best;
  }

  GmshSurfaceManifold::GmshSurfaceManifold(std::shared_ptr<const GmshGeometry> geometry, const int dim,
                                           std::vector<int> tags, const double scale)
    : geometry(std::move(geometry))
    , dim(dim)
    , tags(std::move(tags))
    , scale(scale)
  {}

  std::unique_ptr<dealii::Manifold<3>>
  GmshSurfaceManifold::clone() const
  {
    return std::make_unique<GmshSurfaceManifold>(geometry, dim, tags, scale);
  }

  dealii::Point<3>
  GmshSurfaceManifold::get_new_point(const dealii::ArrayView<const dealii::Point<3>> &points,
                                     const dealii::ArrayView<const double>           &weights) const
  {
    dealii::Point<3> chord;
    for (unsigned i = 0; i < points.size(); ++i)
      chord += weights[i] * points[i];
    return scale * geometry->closest_point(dim, tags, chord / scale);
  }
} // namespace suturesim::mesh
