#pragma once
/**
 * @file
 * Boundary conditions of the tissue, by gmsh physical-group name or boundary id:
 * fixed (u = 0), prescribed displacement u = g(X, t) (muParser expression), reference
 * traction t₀(X, t) (force per reference area, so total force is independent of the
 * deformation), and a body force from gravity. Dirichlet entries may restrict the
 * constrained components, e.g. "back:z" for plane strain.
 */

#include <suturesim/mesh/mesh_loader.h>
#include <suturesim/core/parameter_file.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/parsed_function.h>
#include <deal.II/fe/component_mask.h>

#include <memory>
#include <set>
#include <string>
#include <vector>

namespace suturesim::tissue
{
  struct DirichletBoundary
  {
    dealii::types::boundary_id id;
    std::string                name;
    std::array<bool, 3>        components;
    /// false: fixed (u = 0); true: u = g(X, t) of the prescribed-displacement function.
    bool prescribed;
  };

  class BoundaryConditions
  {
  public:
    static void
    declare(dealii::ParameterHandler &prm);

    /// Reads the subsection; boundary names are resolved against the mesh by resolve().
    void
    parse(dealii::ParameterHandler &prm, const ParameterScope &scope);

    /// Turns names into boundary ids; an unknown name is an InputError.
    void
    resolve(const mesh::MeshInfo &mesh);

    /// Prescribed displacement g(X, t) (m) at time t.
    dealii::Function<3> &
    displacement(double t) const;

    /// Reference traction t₀(X, t) (Pa) at time t.
    dealii::Function<3> &
    traction(double t) const;

    std::vector<DirichletBoundary>      dirichlet;
    std::set<dealii::types::boundary_id> traction_boundaries;
    dealii::Tensor<1, 3>                gravity;

  private:
    std::vector<std::pair<std::string, bool>>     dirichlet_specs;
    std::vector<std::string>                      traction_specs;
    std::unique_ptr<dealii::Functions::ParsedFunction<3>> displacement_function;
    std::unique_ptr<dealii::Functions::ParsedFunction<3>> traction_function;
    std::unique_ptr<ParameterScope>         scope;
  };
} // namespace suturesim::tissue
