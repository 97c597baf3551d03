#pragma once
/**
 * @file
 * Refinement that stays on the drawn geometry. A refined cell's new vertices lie on the
 * straight chords between its parent's, so every level of a nested series keeps the
 * coarsest mesh's polygon of a curved face: the incision's cosine edges of
 * meshes/skin_pad_incision.geo are 13 % narrower at mid-length on a mesh refined from
 * 6 mm cells than drawn (docs/interrupted_stitch.md). GmshSurfaceManifold moves each new
 * vertex of a boundary face or edge to the point of the .geo's surfaces closest to
 * that chord's point (gmsh::model::getClosestPoint), as deal.II's OpenCASCADE
 * projection manifolds do for CAD shapes (deal.II tutorial step-54).
 */

#include <deal.II/base/point.h>
#include <deal.II/grid/manifold.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

namespace suturesim::mesh
{
  /// gmsh's command-line arguments "-setnumber NAME VALUE" for each geo parameter, the
  /// values to 17 digits: the same for the gmsh executable that meshes a .geo and for
  /// the API session that reads its geometry.
  std::vector<std::string>
  setnumber_arguments(const std::map<std::string, double> &parameters);

  /// A .geo's geometry loaded into gmsh (its API is one global session per process; no
  /// mesh is generated), with the geo parameters given as gmsh's -setnumber.
  class GmshGeometry
  {
  public:
    /// Throws InputError naming @p geo when gmsh cannot read it.
    GmshGeometry(const std::string &geo, const std::map<std::string, double> &parameters);
    ~GmshGeometry();
    GmshGeometry(const GmshGeometry &) = delete;
    GmshGeometry &
    operator=(const GmshGeometry &) = delete;

    /// The surfaces of the physical group @p name (dimension 2); empty if none.
    std::vector<int>
    surfaces(const std::string &name) const;

    /// The curves that bound @p surfaces.
    std::vector<int>
    boundary_curves(const std::vector<int> &surfaces) const;

    /// The point of the entities @p tags of dimension @p dim (1: curves, 2: surfaces)
    /// closest to @p p (the .geo's coordinates).
    dealii::Point<3>
    closest_point(int dim, const std::vector<int> &tags, const dealii::Point<3> &p) const;

  private:
    std::string file;
  };

  /// New points of the faces and edges that carry its manifold id: the chord's point
  /// (the weighted mean of the parents, as a flat manifold has it), moved to the closest
  /// point of the entities @p tags of dimension @p dim: a face's surfaces, or for an edge
  /// where the face meets another boundary (the incision's top edge, its floor) the
  /// curves that bound them, so that the edge stays on both. @p scale: the mesh's
  /// coordinates over the .geo's (Mesh/Scale).
  class GmshSurfaceManifold : public dealii::Manifold<3>
  {
  public:
    GmshSurfaceManifold(std::shared_ptr<const GmshGeometry> geometry, int dim, std::vector<int> tags,
                        double scale);

    std::unique_ptr<dealii::Manifold<3>>
    clone() const override;

    dealii::Point<3>
    get_new_point(const dealii::ArrayView<const dealii::Point<3>> &points,
                  const dealii::ArrayView<const double>           &weights) const override;

  private:
    std::shared_ptr<const GmshGeometry> geometry;
    int                                 dim;
    std::vector<int>                    tags;
    double                              scale;
  };
} // namespace suturesim::mesh
