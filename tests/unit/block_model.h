// A fixed-bottom block of FE tissue for tests that load embedded material points: the
// scene's own parameter parsing (Simulation's declarations) on a short parameter text,
// a subdivided box with named faces, and the TissueModel on it, set up.
#pragma once

#include <suturesim/mesh/mesh_loader.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/scene/simulation.h>
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>
#include <deal.II/grid/grid_generator.h>

#include <functional>
#include <iostream>
#include <memory>
#include <optional>
#include <string>

namespace suturesim::test_support
{
  struct BlockModel
  {
    /// @p tissue: the body of the Tissue subsection (Element degree, Newton, Material,
    /// Boundary conditions); the box from the origin to @p upper with @p cells, then
    /// @p refine (a locally refined mesh: hanging nodes) before the model is set up.
    BlockModel(const std::string &tissue, const dealii::Point<3> &upper, const std::vector<unsigned> &cells,
               const std::function<void(dealii::parallel::distributed::Triangulation<3> &)> &refine = {})
      : tria(MPI_COMM_WORLD)
      , timer(MPI_COMM_WORLD, std::cout, dealii::TimerOutput::never, dealii::TimerOutput::wall_times)
    {
      scene::Simulation::declare_parameters(prm);
      // kept: the parameters' scopes name their entries from it in later errors
      file.emplace(prm, "subsection Tissue\n" + tissue + "end\n", "block.prm", ".");
      const ParameterScope root(*file, "");
      prm.enter_subsection("Tissue");
      parameters.parse(prm, root.subsection("Tissue"));
      prm.enter_subsection("Material");
      material.emplace(tissue::Material::parse_parameters(prm, root.subsection("Tissue/Material")));
      prm.leave_subsection();
      prm.enter_subsection("Boundary conditions");
      bc.parse(prm, root.subsection("Tissue/Boundary conditions"));
      prm.leave_subsection();
      prm.leave_subsection();

      dealii::GridGenerator::subdivided_hyper_rectangle(tria, cells, dealii::Point<3>(), upper, true);
      if (refine)
        refine(tria);
      mesh::MeshInfo info;
      info.boundary_names = {{0, "x0"}, {1, "x1"}, {2, "y0"}, {3, "y1"}, {4, "bottom"}, {5, "top"}};
      bc.resolve(info);
      model = std::make_unique<tissue::TissueModel>(MPI_COMM_WORLD, parameters, *material, bc, tria, timer);
      model->setup();
    }

    dealii::ParameterHandler                  prm;
    std::optional<ParameterFile>              file;
    tissue::TissueParameters                  parameters;
    std::optional<tissue::Material>           material;
    tissue::BoundaryConditions                bc;
    dealii::parallel::distributed::Triangulation<3> tria;
    dealii::TimerOutput                       timer;
    std::unique_ptr<tissue::TissueModel>      model;
  };
} // namespace suturesim::test_support
