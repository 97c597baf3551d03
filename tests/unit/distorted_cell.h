#pragma once
// One general (non-affine) hexahedron and a Mooney–Rivlin material, shared by the cell
// tests (cell_assembler_test.cc) and the cell benchmark (tissue_benchmark.cc).
#include <suturesim/core/parameter_file.h>
#include <suturesim/tissue/material.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <cmath>
#include <string>

namespace suturesim::testing
{
  /// A cube of 10 mm with each vertex moved by a fixed pattern of up to 1 mm.
  inline void
  distorted_cube(dealii::Triangulation<3> &tria)
  {
    dealii::GridGenerator::hyper_cube(tria, 0.0, 0.01);
    dealii::GridTools::transform(
      [](const dealii::Point<3> &p) {
        return p + 0.001 * dealii::Point<3>(std::sin(300 * p[1] + 200 * p[2]),
                                            std::cos(250 * p[0] + 100 * p[2]),
                                            std::sin(150 * p[0] + 280 * p[1] + 1));
      },
      tria);
  }

  /// Mooney–Rivlin, C10 = 0.8 MPa, C01 = 0.2 MPa, Poisson ratio @p nu.
  inline tissue::Material
  mooney_rivlin(const double nu)
  {
    dealii::ParameterHandler prm;
    tissue::Material::declare_parameters(prm);
    ParameterFile file(prm,
                       "set Model = Mooney-Rivlin\nset Poisson ratio = " + std::to_string(nu) +
                         "\nsubsection Mooney-Rivlin\n set C10 = 0.8e6\n set C01 = 0.2e6\nend\n",
                       "test.prm",
                       ".");
    return tissue::Material::parse_parameters(prm, ParameterScope(file, ""));
  }
} // namespace suturesim::testing
