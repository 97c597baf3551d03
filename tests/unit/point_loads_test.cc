// Loads at embedded material points (tissue/point_loads.h): a penalty spring pulls a
// material point of the top of a fixed-bottom block towards a target. The tangent of
// the point load keeps Newton quadratic, the fixed bottom carries the spring force,
// and the spring's force equals k times the remaining distance at equilibrium. A
// spread point's weights are a partition of unity that reproduces linear fields across
// hanging nodes, and its displacement has a mesh limit where a point load's has none.
#include "block_model.h"

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q1.h>
#include <deal.II/grid/grid_generator.h>

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <map>
#include <vector>

using namespace suturesim;
using namespace dealii;

namespace
{
  /// f = k (x_target − x): a spring to a fixed target.
  class Spring : public tissue::PointLoads
  {
  public:
    Spring(const Point<3> &X, const Point<3> &target, const double k)
      : X{X}
      , target(target)
      , k(k)
    {}
    const std::vector<Point<3>> &
    points() const override
    {
      return X;
    }
    void
    force(std::size_t, const Point<3> &x, Tensor<1, 3> &f, Tensor<2, 3> &df_dx) const override
    {
      f     = k * (target - x);
      df_dx = -k * unit_symmetric_tensor<3>();
    }
    double
    spread_radius(std::size_t) const override
    {
      return rho;
    }
    bool
    cut_off(std::size_t, const Point<3> &Y) const override
    {
      return Y[0] > cut;
    }
    std::vector<Point<3>> X;
    Point<3>              target;
    double                k;
    double                rho = 0;
    double                cut = std::numeric_limits<double>::infinity(); ///< x beyond which the tissue is cut off
  };

  /// Whether every iterate in the asymptotic range converges at order > 1.8.
  void
  expect_quadratic(const std::vector<double> &r)
  {
    unsigned quadratic = 0;
    for (std::size_t k = 1; k + 1 < r.size(); ++k)
      if (r[k] < 1e-2 * r[0] && r[k + 1] > 1e-12 * r[0])
        {
          EXPECT_GT(std::log(r[k + 1] / r[0]) / std::log(r[k] / r[0]), 1.8) << "iterate " << k;
          ++quadratic;
        }
    EXPECT_GE(quadratic, 1u);
  }
} // namespace

TEST(PointLoads, SpringAtAnEmbeddedPointBalancesAndNewtonStaysQuadratic)
{
  // as a point load and spread over ρ = 3 mm (its weights across a dozen cells of 5 mm:
  // its tangent a rank-3 update added by the solve, EmbeddedPoints::low_rank(), and K's
  // pattern the cells' couplings alone, as the point load's, whose cell holds them)
  std::vector<std::size_t> nonzeros;
  for (const double rho : {0.0, 0.003})
    {
      test_support::BlockModel block(" set Element degree = 2\n"
                                     " subsection Newton\n  set Line search = false\n end\n"
                                     " subsection Material\n  set Model = neo-Hookean\n  set Bulk modulus = 1e6\n"
                                     "  subsection neo-Hookean\n   set Shear modulus = 2e5\n  end\n end\n"
                                     " subsection Boundary conditions\n  set Fixed = bottom\n end\n",
                                     Point<3>(0.02, 0.02, 0.01), {4, 4, 2});
      auto &model = *block.model;

      // a material point off the nodes (inside a cell face of the top), pulled up and
      // sideways (harder when spread: the tissue under it is stiffer)
      const Point<3> X(0.0071, 0.0093, 0.01);
      Spring         spring(X, X + Point<3>(0.0005, 0, 0.002), rho > 0 ? 2000 : 200);
      spring.rho = rho;
      model.set_point_loads(&spring);
      const auto report = model.solve_static(1.0);
      ASSERT_TRUE(report.converged) << report.failure;
      // quadratic: once in the asymptotic range each residual is below C r²
      expect_quadratic(report.residual_norms);
      nonzeros.push_back(model.tangent().n_nonzero_elements());
      ASSERT_EQ(nonzeros.back(), nonzeros.front()) << "a spread point's dense block in K";

      const Point<3>     x = model.point_position(0);
      const Tensor<1, 3> f = spring.k * (spring.target - x);
      EXPECT_GT(f[2], 0.05); // the block resists: a good part of the 0.4 (4) N remains
      EXPECT_GT(x[2], X[2] + 1e-4); // and the point moved towards the target
      const auto reactions = model.reactions(1.0);
      ASSERT_EQ(reactions.size(), 1u);
      for (unsigned d = 0; d < 3; ++d)
        EXPECT_NEAR(reactions[0].force[d] + f[d], 0, 1e-8 * f.norm()) << d << ", ρ = " << rho;
    }
}

TEST(EmbeddedPoints, SpreadWeightsSumToOneAndReproduceLinearFieldsAcrossHangingNodes)
{
  // A 10 mm cube of Q1 cells of 2.5 mm, the eight round its centre refined once: the
  // kernel's ball (ρ = 2 mm about a point off the centre) covers fine cells, hanging
  // nodes and coarse cells. W must sum to one per component, put nothing on a hanging
  // node, and give Σ W_I X_I = the kernel's centroid, X for a ball inside the body (a
  // linear field is reproduced by Q1 and by the hanging-node constraints). That last
  // holds to the iterated Gauss rule's accuracy on the kernel's C¹ edge.
  parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
  GridGenerator::subdivided_hyper_cube(tria, 4, 0, 0.01);
  for (const auto &cell : tria.active_cell_iterators())
    if (cell->center().distance(Point<3>(0.005, 0.005, 0.005)) < 0.003)
      cell->set_refine_flag();
  tria.execute_coarsening_and_refinement();
  const FESystem<3> fe(FE_Q<3>(1), 3);
  DoFHandler<3>     dofs(tria);
  dofs.distribute_dofs(fe);
  IndexSet relevant;
  DoFTools::extract_locally_relevant_dofs(dofs, relevant);
  AffineConstraints<double> hanging(relevant);
  DoFTools::make_hanging_node_constraints(dofs, hanging);
  hanging.close();
  ASSERT_GT(hanging.n_constraints(), 0u);
  const MappingQ1<3>                             mapping;
  std::map<types::global_dof_index, Point<3>> support;
  DoFTools::map_dofs_to_support_points(mapping, dofs, support);

  for (const double rho : {0.0, 0.002})
    {
      Spring spring(Point<3>(0.0053, 0.0046, 0.0051), Point<3>(), 1);
      spring.rho = rho;
      tissue::EmbeddedPoints points(mapping, fe, dofs, MPI_COMM_WORLD);
      points.locate(spring, hanging);
      double   sum[3] = {0, 0, 0};
      Point<3> centroid;
      for (const auto &w : points.weights(0))
        {
          EXPECT_FALSE(hanging.is_constrained(w.dof)) << "weight on hanging DoF " << w.dof;
          sum[w.component] += w.value;
          centroid[w.component] += w.value * support.at(w.dof)[w.component];
        }
      for (unsigned d = 0; d < 3; ++d)
        EXPECT_NEAR(sum[d], 1.0, 1e-12) << "ρ = " << rho;
      // ρ = 0: the shape functions at the point, exact; ρ > 0: the rule's error
      std::cout << "rho = " << rho << " m: centroid " << centroid.distance(spring.X[0]) << " m from the point\n";
      EXPECT_LT(centroid.distance(spring.X[0]), rho > 0 ? 1e-3 * rho : 1e-15) << "ρ = " << rho;
      if (rho > 0)
        EXPECT_GT(points.weights(0).size(), 3 * 27u); // more than one cell's DoFs
      else
        EXPECT_EQ(points.weights(0).size(), 3 * 8u);
    }
}

TEST(EmbeddedPoints, ASpreadPointTakesNothingBeyondACut)
{
  // The visibility criterion (PointLoads::cut_off()): a point spread over ρ = 2 mm inside
  // a 10 mm cube of Q1 cells of 1.25 mm, with everything beyond the plane x = X_x through
  // it cut off, as a pierce point on a wound's face has the other lip beyond it. The
  // plane lies on cell faces, as a wound's faces do (no cell straddles the gap). The
  // weights then lie on the point's side (no DoF further than a cell beyond the plane)
  // and their centroid, Σ W_I X_I (Q1 reproduces linear fields), is the half ball's:
  // X − (∫₀¹ s³φ ds / ∫₀¹ s²φ ds)(ρ/2) e_x = X − (105/192)(ρ/2) e_x = X − 0.2734 ρ e_x
  // for φ = (1 − s²)²; uncut, X itself (the test above). A plane through the cells is
  // resolved to the rule's spacing, about ρ/10 here: measured −0.3035 ρ with the plane at
  // x = 5.3 mm.
  parallel::distributed::Triangulation<3> tria(MPI_COMM_WORLD);
  GridGenerator::subdivided_hyper_cube(tria, 8, 0, 0.01);
  const FESystem<3> fe(FE_Q<3>(1), 3);
  DoFHandler<3>     dofs(tria);
  dofs.distribute_dofs(fe);
  AffineConstraints<double> none;
  none.close();
  const MappingQ1<3>                          mapping;
  std::map<types::global_dof_index, Point<3>> support;
  DoFTools::map_dofs_to_support_points(mapping, dofs, support);

  const double rho = 0.002;
  Spring       spring(Point<3>(0.005, 0.0046, 0.0051), Point<3>(), 1);
  spring.rho = rho;
  spring.cut = spring.X[0][0];
  tissue::EmbeddedPoints points(mapping, fe, dofs, MPI_COMM_WORLD);
  points.locate(spring, none);
  double   sum[3] = {0, 0, 0};
  Point<3> centroid;
  for (const auto &w : points.weights(0))
    {
      EXPECT_LE(support.at(w.dof)[0], spring.cut + 0.00125 + 1e-12) << "weight beyond the cut, DoF " << w.dof;
      sum[w.component] += w.value;
      centroid[w.component] += w.value * support.at(w.dof)[w.component];
    }
  for (unsigned d = 0; d < 3; ++d)
    EXPECT_NEAR(sum[d], 1.0, 1e-12);
  const Tensor<1, 3> offset = centroid - spring.X[0];
  std::cout << "cut at the point: centroid offset (" << offset / rho << ") rho\n";
  EXPECT_NEAR(offset[0], -105.0 / 384.0 * rho, 1e-3 * rho);
  EXPECT_NEAR(offset[1], 0, 1e-3 * rho);
  EXPECT_NEAR(offset[2], 0, 1e-3 * rho);
}

TEST(PointLoads, SpreadLoadHasAMeshLimitAndAPointLoadDoesNot)
{
  // A spring pulls a point of the top of a fixed-bottom 10 × 10 × 5 mm block up by 1 mm
  // (Q2-P1, nearly linear: 0.1 N). Spread over ρ = 2 mm, on cells of 2.5, 1.25 and
  // 0.625 mm, the point's rise converges: each halving of h changes it by much less than
  // the one before (measured 14×; > 3 asserted). As a point load, on cells of 5, 2.5 and
  // 1.25 mm, its rise keeps growing — u ~ F/(8πμr) measured at r ~ h (Kelvin) — and each
  // halving adds about as much as the one before, or more (< 2 asserted). Q1 needs
  // h < ρ/6 before the spread rise converges (measured: 2.41, 2.90, 3.39, 3.57e-5 m on
  // 2.5 to 0.31 mm cells, Q2 3.65e-5 m).
  std::map<double, std::vector<double>> rise;
  for (const double rho : {0.0, 0.002})
    for (const unsigned n : rho > 0 ? std::vector<unsigned>{4, 8, 16} : std::vector<unsigned>{2, 4, 8})
      {
        test_support::BlockModel block(" set Element degree = 2\n set Formulation = mixed\n"
                                       " subsection Material\n  set Model = neo-Hookean\n  set Bulk modulus = 1e6\n"
                                       "  subsection neo-Hookean\n   set Shear modulus = 2e5\n  end\n end\n"
                                       " subsection Boundary conditions\n  set Fixed = bottom\n end\n",
                                       Point<3>(0.01, 0.01, 0.005), {n, n, n / 2});
        auto          &model = *block.model;
        const Point<3> X(0.0051, 0.0048, 0.005);
        Spring         spring(X, X + Point<3>(0, 0, 0.001), 100);
        spring.rho = rho;
        model.set_point_loads(&spring);
        const auto report = model.solve_static(1.0);
        ASSERT_TRUE(report.converged) << report.failure;
        rise[rho].push_back(model.point_position(0)[2] - X[2]);
      }
  for (const auto &[rho, r] : rise)
    {
      const double ratio = (r[1] - r[0]) / (r[2] - r[1]);
      std::cout << "rho = " << rho << " m: rise " << r[0] << ", " << r[1] << ", " << r[2]
                << " m; change ratio " << ratio << "\n";
      ASSERT_GT(r[2] - r[1], 0.0);
      if (rho > 0)
        EXPECT_GT(ratio, 3.0);
      else
        EXPECT_LT(ratio, 2.0);
    }
}
