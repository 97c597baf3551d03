#pragma once
/**
 * @file
 * Local refinement of the tissue mesh from the scene: fine cells where the stitch
 * happens (the wound's faces, the needle's planned path through the tissue), the coarse
 * mesh elsewhere. Each of Levels rounds refines every active cell that comes within
 * Distance of those features,
 *
 *     d(x_c, F) ≤ Distance + r_c,
 *
 * x_c the cell's centre, r_c half its diameter and F the features (the faces as two
 * triangles each, the path as a polyline). Refinement is nested (the same coarse mesh,
 * halved near F at each level), so successive levels form a series with refinement
 * ratio 2 for Richardson extrapolation. p4est keeps neighbouring cells within one level
 * of each other (2:1 balance) and the tissue model constrains the hanging nodes
 * (tissue/tissue_model.h). The refinement is done before anything is located in the
 * mesh, so the needle's points and contacts are found in the refined cells.
 */

#include <suturesim/core/parameter_file.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>
#include <deal.II/distributed/tria.h>

#include <memory>
#include <string>
#include <vector>

namespace suturesim::mesh
{
  struct MeshInfo;

  struct LocalRefinement
  {
    unsigned                 levels = 0;
    std::vector<std::string> near_boundaries; ///< names or ids of boundaries
    bool                     near_path = false;
    double                   distance  = 0; ///< m

    /// Declares the subsection "Local refinement" into the current one ("Mesh").
    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm, const ParameterScope &scope);

    /// Refines @p tria near the boundaries (resolved through @p mesh) and near @p path
    /// (the scene's needle path; used with Near needle path); unknown boundary names are
    /// an InputError naming the parameter.
    void
    apply(const MeshInfo &mesh, const std::vector<dealii::Point<3>> &path,
          dealii::parallel::distributed::Triangulation<3> &tria) const;

  private:
    std::shared_ptr<ParameterScope> scope;
  };
} // namespace suturesim::mesh
