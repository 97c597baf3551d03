// The cell tangent of both formulations against central finite differences of the cell
// residual (conventions.md §6; FEBio's FETangentDiagnostic): relative error ≤ 1e-6.
#include "distorted_cell.h"

#include <suturesim/tissue/cell_assembler.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_handler.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_generator.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/grid/tria.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <memory>

using namespace suturesim::tissue;
using namespace dealii;

namespace
{
  using suturesim::testing::mooney_rivlin;

  struct Case
  {
    unsigned degree;
    bool     mixed;
    unsigned pressure_degree;
  };

  /// One general (non-affine) hexahedron of about 10 mm, each vertex of a cube moved by a
  /// fixed pattern, with the element and the assembler of @p c.
  struct OneCell
  {
    explicit OneCell(const Case &c)
      : fe(FE_Q<3>(c.degree), 3)
      , dofs(tria)
    {
      suturesim::testing::distorted_cube(tria);
      dofs.distribute_dofs(fe);
      assembler = std::make_unique<CellAssembler>(mapping, fe, QGauss<3>(c.degree + 1), c.mixed,
                                                  c.pressure_degree);
    }
    Triangulation<3>               tria;
    FESystem<3>                    fe;
    DoFHandler<3>                  dofs;
    MappingQ1<3>                   mapping;
    std::unique_ptr<CellAssembler> assembler;
  };
  /// The largest difference between the cell tangent at @p u and central differences
  /// (step 1e-9 m) of the residual, relative to the tangent's largest entry; ∞ when an
  /// assembly fails.
  double
  tangent_error(CellAssembler &assembler, const DoFHandler<3>::active_cell_iterator &cell, const Vector<double> &u,
                const Material &m, const Tensor<1, 3> &gravity, const std::vector<double> *degradation = nullptr)
  {
    const unsigned     n = u.size();
    Vector<double>     r(n), rp(n), rm(n);
    FullMatrix<double> K(n, n);
    const auto assemble = [&](const Vector<double> &at, Vector<double> &out, FullMatrix<double> *tangent) {
      return assembler.assemble(cell, at, m, gravity, out, tangent, nullptr, MixedUpdate::exact, nullptr, degradation);
    };
    if (!assemble(u, r, &K))
      return std::numeric_limits<double>::infinity();
    const double h         = 1e-9;
    double       max_error = 0, max_entry = 0;
    for (unsigned j = 0; j < n; ++j)
      {
        Vector<double> up = u, um = u;
        up[j] += h;
        um[j] -= h;
        if (!assemble(up, rp, nullptr) || !assemble(um, rm, nullptr))
          return std::numeric_limits<double>::infinity();
        for (unsigned i = 0; i < n; ++i)
          {
            max_error = std::max(max_error, std::abs((rp[i] - rm[i]) / (2 * h) - K(i, j)));
            max_entry = std::max(max_entry, std::abs(K(i, j)));
          }
      }
    return max_error / max_entry;
  }
} // namespace

class CellTangent : public ::testing::TestWithParam<Case>
{};

TEST_P(CellTangent, MatchesCentralDifferences)
{
  const Case     c = GetParam();
  OneCell        one(c);
  const auto    &fe        = one.fe;
  CellAssembler &assembler = *one.assembler;
  const Material m         = mooney_rivlin(0.45);

  const unsigned n = fe.n_dofs_per_cell();
  Vector<double> u(n);
  for (unsigned i = 0; i < n; ++i)
    u[i] = 6e-4 * std::sin(0.9 * i + 0.3); // displacement gradients of order 0.1
  const Tensor<1, 3> gravity({0, 0, -9.81});

  EXPECT_LE(tangent_error(assembler, one.dofs.begin_active(), u, m, gravity), 1e-6)
    << "Q" << c.degree << (c.mixed ? " mixed P" + std::to_string(c.pressure_degree) : "");
}

// Phase-field tearing degrades the energy to g Ψ_iso + g_v Ψ_vol at each quadrature point,
// g_v = g in expansion and 1 in compression (cell_assembler.h). On a compressed and on a
// dilated cell: the tangent stays consistent with g varying over the cell, g = 1 is the
// undamaged cell to the bit, and the residual is affine in a uniform g; compressed, the
// volumetric part stays at g = 0; dilated, nothing does.
TEST_P(CellTangent, DegradedEnergyKeepsTheTangentAndTheCompressedVolumetricPart)
{
  const Case     c = GetParam();
  OneCell        one(c);
  CellAssembler &assembler = *one.assembler;
  const Material m         = mooney_rivlin(0.45);
  const unsigned n         = one.fe.n_dofs_per_cell();
  const unsigned n_q       = static_cast<unsigned>(std::pow(c.degree + 1, 3));
  const auto     cell      = one.dofs.begin_active();
  const Tensor<1, 3> none;
  std::vector<double> g(n_q);
  for (unsigned q = 0; q < n_q; ++q)
    g[q] = 0.3 + 0.25 * std::sin(1.7 * q + 0.2); // 0.05-0.55, a different value at each point
  const std::vector<double> one_everywhere(n_q, 1.0), zero(n_q, 0.0), forty(n_q, 0.4);

  // u = ε X + a wavy part of gradients about 1e-3, ε = −1 % (J < 1) or +1 % (J > 1)
  std::map<types::global_dof_index, Point<3>> X;
  DoFTools::map_dofs_to_support_points(one.mapping, one.dofs, X);
  for (const double strain : {-0.01, 0.01})
    {
      SCOPED_TRACE(strain);
      Vector<double> u(n);
      for (unsigned i = 0; i < n; ++i)
        u[i] = strain * X[i][one.fe.system_to_component_index(i).first] + 1e-5 * std::sin(0.9 * i + 0.3);

      EXPECT_LE(tangent_error(assembler, cell, u, m, none, &g), 1e-6);

      const auto residual = [&](const std::vector<double> *degradation) {
        Vector<double> out(n);
        EXPECT_TRUE(
          assembler.assemble(cell, u, m, none, out, nullptr, nullptr, MixedUpdate::exact, nullptr, degradation));
        return out;
      };
      const Vector<double> whole = residual(nullptr), r1 = residual(&one_everywhere), r0 = residual(&zero),
                           r04 = residual(&forty);
      for (unsigned i = 0; i < n; ++i)
        {
          EXPECT_EQ(r1[i], whole[i]) << i;
          EXPECT_NEAR(r04[i], r0[i] + 0.4 * (whole[i] - r0[i]), 1e-12 * whole.linfty_norm()) << i;
        }
      if (strain < 0)
        {
          // the compressed volumetric part is there (r0) and is a share of the whole
          EXPECT_GT(r0.linfty_norm(), 1e-2 * whole.linfty_norm());
          Vector<double> isochoric = whole;
          isochoric -= r0;
          EXPECT_GT(isochoric.linfty_norm(), 1e-2 * whole.linfty_norm());
        }
      else
        EXPECT_LE(r0.linfty_norm(), 1e-14 * whole.linfty_norm());
    }
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
  EXPECT_FALSE(assembler.assemble(dofs.begin_active(), u, mooney_rivlin(0.3), {}, r, nullptr));
}

// The three-field Newton update (MixedUpdate::newton, cell_assembler.h) against central
// differences along the update it predicts. From a state whose p̃ and J̃ violate both
// constraints, the step (Δu, Δp̃, ΔJ̃) with Δp̃, ΔJ̃ recovered by MixedCell::begin_update()
// must be Newton's step for the uncondensed system: along it the constraint residuals
// fall as (1 − ε) R_p, (1 − ε) R_J, and the equilibrium part r_u = r − r_c moves as
// K Δu + r_c (the condensed tangent times Δu plus the constraint force). Each line is
// one row block of the 3 × 3 system, so a wrong K_pu, K_JJ, M or recovery fails one.
// With the phase field's degradation too, dilated (the volumetric share g in R_J and
// K_JJ) and compressed.
class MixedNewtonUpdate : public ::testing::TestWithParam<Case>
{};

TEST_P(MixedNewtonUpdate, IsNewtonsStepOfTheThreeFieldSystem)
{
  const Case     c = GetParam();
  ASSERT_TRUE(c.mixed);
  OneCell        one(c);
  const auto    &fe        = one.fe;
  CellAssembler &assembler = *one.assembler;
  const Material m         = mooney_rivlin(0.49);
  const auto     cell      = one.dofs.begin_active();
  const unsigned n    = fe.n_dofs_per_cell();
  const unsigned n_p  = assembler.n_pressure();

  // as assembled, and degraded by the phase field (g varying over the cell) on a cell
  // dilated and on one compressed by 1 % (g_v = g and 1: cell_assembler.h)
  std::vector<double> g(static_cast<unsigned>(std::pow(c.degree + 1, 3)));
  for (unsigned q = 0; q < g.size(); ++q)
    g[q] = 0.3 + 0.25 * std::sin(1.7 * q + 0.2);
  std::map<types::global_dof_index, Point<3>> X;
  DoFTools::map_dofs_to_support_points(one.mapping, one.dofs, X);
  for (const auto &[strain, degradation] : {std::pair<double, const std::vector<double> *>{0.0, nullptr},
                                            std::pair<double, const std::vector<double> *>{0.01, &g},
                                            std::pair<double, const std::vector<double> *>{-0.01, &g}})
  {
    SCOPED_TRACE(degradation ? "degraded, strain " + std::to_string(strain) : "as assembled");
    Vector<double> u(n), du(n);
    for (unsigned i = 0; i < n; ++i)
      {
        u[i]  = strain * X[i][fe.system_to_component_index(i).first] + 6e-4 * std::sin(0.9 * i + 0.3);
        du[i] = 2e-4 * std::cos(1.7 * i + 0.2);
      }
    // consistent fields at u, then both constraints broken
    MixedCell fields;
    Vector<double> r(n), r_c(n), r_exact(n);
    ASSERT_TRUE(
      assembler.assemble(cell, u, m, {}, r_exact, nullptr, &fields, MixedUpdate::exact, nullptr, degradation));
    MixedCell consistent = fields;
    ASSERT_TRUE(assembler.assemble(cell, u, m, {}, r, nullptr, &consistent, MixedUpdate::newton, &r_c, degradation));
    EXPECT_LE(r_c.linfty_norm(), 1e-10 * r_exact.linfty_norm()) << "a consistent state has no constraint force";
    Vector<double> diff = r;
    diff -= r_exact;
    EXPECT_LE(diff.linfty_norm(), 1e-10 * r_exact.linfty_norm()) << "both updates agree where the constraints hold";

    for (unsigned a = 0; a < n_p; ++a)
      {
        fields.J[a] += (a == 0 ? 3e-3 : 1e-3);
        fields.p[a] += (a == 0 ? 0.02 : 0.01) * m.bulk_modulus();
      }
    FullMatrix<double> K(n, n);
    ASSERT_TRUE(assembler.assemble(cell, u, m, {}, r, &K, &fields, MixedUpdate::newton, &r_c, degradation));
    const auto R_p0 = fields.dilatation_residual();
    const auto R_J0 = fields.pressure_residual();
    Vector<double> expected_dr(n);
    K.vmult(expected_dr, du);
    expected_dr += r_c;
    fields.begin_update(du);

    // r_u and the constraint residuals at ε along the step
    const auto at = [&](const double eps, Vector<double> &r_u, PressureCoefficients &R_p, PressureCoefficients &R_J) {
      MixedCell f = fields;
      f.step(eps);
      Vector<double> ue = u, re(n), rce(n);
      ue.add(eps, du);
      ASSERT_TRUE(assembler.assemble(cell, ue, m, {}, re, nullptr, &f, MixedUpdate::newton, &rce, degradation));
      r_u = re;
      r_u -= rce;
      R_p = f.dilatation_residual();
      R_J = f.pressure_residual();
    };
    const double         h = 1e-4;
    Vector<double>       rp(n), rm(n);
    PressureCoefficients Pp, Pm, Jp, Jm;
    at(h, rp, Pp, Jp);
    at(-h, rm, Pm, Jm);
    double err = 0;
    for (unsigned i = 0; i < n; ++i)
      err = std::max(err, std::abs((rp[i] - rm[i]) / (2 * h) - expected_dr[i]));
    EXPECT_LE(err, 1e-6 * expected_dr.linfty_norm()) << "equilibrium row";
    double P_scale = 0, J_scale = 0;
    for (unsigned a = 0; a < n_p; ++a)
      {
        P_scale = std::max(P_scale, std::abs(R_p0[a]));
        J_scale = std::max(J_scale, std::abs(R_J0[a]));
      }
    ASSERT_GT(P_scale, 0);
    ASSERT_GT(J_scale, 0);
    for (unsigned a = 0; a < n_p; ++a)
      {
        EXPECT_NEAR((Pp[a] - Pm[a]) / (2 * h), -R_p0[a], 1e-6 * P_scale) << "dilatation row, a = " << a;
        EXPECT_NEAR((Jp[a] - Jm[a]) / (2 * h), -R_J0[a], 1e-6 * J_scale) << "pressure row, a = " << a;
      }

  }
}

INSTANTIATE_TEST_SUITE_P(Elements, MixedNewtonUpdate,
                         ::testing::Values(Case{2, true, 1}, Case{1, true, 0}, Case{2, true, 0},
                                           Case{1, true, 1}),
                         [](const auto &info) {
                           return "Q" + std::to_string(info.param.degree) + "_P" +
                                  std::to_string(info.param.pressure_degree);
                         });
