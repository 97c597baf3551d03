// The cell tangent of both formulations against central finite differences of the cell
// residual (conventions.md §6; FEBio's FETangentDiagnostic): relative error ≤ 1e-6.
#include <suturesim/tissue/cell_assembler.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <gtest/gtest.h>

#include <cmath>

using namespace suturesim::tissue;
using namespace dealii;

namespace
{
  Material
  material(const double nu)
  {
    dealii::ParameterHandler prm;
    Material::declare_parameters(prm);
    suturesim::ParameterFile file(
      prm,
      "set Model = Mooney-Rivlin\nset Poisson ratio = " + std::to_string(nu) +
        "\nsubsection Mooney-Rivlin\n set C10 = 0.8e6\n set C01 = 0.2e6\nend\n",
      "test.prm",
      ".");
    return Material::parse_parameters(prm, suturesim::ParameterScope(file, ""));
  }

  struct Case
  {
    unsigned degree;
    bool     mixed;
    unsigned pressure_degree;
  };
} // namespace

class CellTangent : public ::testing::TestWithParam<Case>
{};

TEST_P(CellTangent, MatchesCentralDifferences)
{
  const Case c = GetParam();
  Triangulation<3> tria;
  GridGenerator::hyper_cube(tria, 0.0, 0.01);
  // A general (non-affine) cell: move each vertex by a fixed pattern.
  GridTools::transform(
    [](const Point<3> &p) {
      return p + 0.001 * Point<3>(std::sin(300 * p[1] + 200 * p[2]),
                                std::cos(250 * p[0] + 100 * p[2]),
                                std::sin(150 * p[0] + 280 * p[1] + 1));
    },
    tria);
  FESystem<3>  fe(FE_Q<3>(c.degree), 3);
  DoFHandler<3> dofs(tria);
  dofs.distribute_dofs(fe);
  MappingQ1<3>  mapping;
  CellAssembler assembler(mapping, fe, QGauss<3>(c.degree + 1), c.mixed, c.pressure_degree);
  const Material m = material(0.45);

  const unsigned n = fe.n_dofs_per_cell();
  Vector<double> u(n);
  for (unsigned i = 0; i < n; ++i)
    u[i] = 6e-4 * std::sin(0.9 * i + 0.3); // displacement gradients of order 0.1
  const Tensor<1, 3> gravity({0, 0, -9.81});

  const auto         cell = dofs.begin_active();
  Vector<double>     r(n), rp(n), rm(n);
  FullMatrix<double> K(n, n);
  ASSERT_TRUE(assembler.assemble(cell, u, m, gravity, r, &K));

  const double h         = 1e-9;
  double       max_error = 0, max_entry = 0;
  for (unsigned j = 0; j < n; ++j)
    {
      Vector<double> up = u, um = u;
      up[j] += h;
      um[j] -= h;
      ASSERT_TRUE(assembler.assemble(cell, up, m, gravity, rp, nullptr));
      ASSERT_TRUE(assembler.assemble(cell, um, m, gravity, rm, nullptr));
      for (unsigned i = 0; i < n; ++i)
        {
          const double fd = (rp[i] - rm[i]) / (2 * h);
          max_error       = std::max(max_error, std::abs(fd - K(i, j)));
          max_entry       = std::max(max_entry, std::abs(K(i, j)));
        }
    }
  EXPECT_LE(max_error, 1e-6 * max_entry)
    << "Q" << c.degree << (c.mixed ? " mixed P" + std::to_string(c.pressure_degree) : "");
}

INSTANTIATE_TEST_SUITE_P(Formulations, CellTangent,
                         ::testing::Values(Case{1, false, 0}, Case{2, false, 0},
                                           Case{1, true, 0}, Case{2, true, 0},
                                           Case{2, true, 1}, Case{1, true, 1}),
                         [](const auto &info) {
                           return "Q" + std::to_string(info.param.degree) +
                                  (info.param.mixed ? "_mixed_P" +
                                                        std::to_string(info.param.pressure_degree)
                                                    : "_displacement");
                         });

TEST(CellAssembler, RejectsInvertedIterate)
{
  Triangulation<3> tria;
  GridGenerator::hyper_cube(tria, 0.0, 0.01);
  FESystem<3>   fe(FE_Q<3>(1), 3);
  DoFHandler<3> dofs(tria);
  dofs.distribute_dofs(fe);
  MappingQ1<3>  mapping;
  CellAssembler assembler(mapping, fe, QGauss<3>(2), false, 0);
  Vector<double> u(fe.n_dofs_per_cell()), r(fe.n_dofs_per_cell());
  // push the top face through the bottom one
  for (unsigned i = 0; i < fe.n_dofs_per_cell(); ++i)
    if (fe.system_to_component_index(i).first == 2 && fe.system_to_component_index(i).second >= 4)
      u[i] = -0.02;
  EXPECT_FALSE(assembler.assemble(dofs.begin_active(), u, material(0.3), {}, r, nullptr));
}
