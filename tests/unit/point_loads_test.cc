// Loads at embedded material points (tissue/point_loads.h): a penalty spring pulls a
// material point of the top of a fixed-bottom block towards a target. The tangent of
// the point load keeps Newton quadratic, the fixed bottom carries the spring force,
// and the spring's force equals k times the remaining distance at equilibrium.
#include "block_model.h"

#include <gtest/gtest.h>

#include <cmath>

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
    std::vector<Point<3>> X;
    Point<3>              target;
    double                k;
  };
} // namespace

TEST(PointLoads, SpringAtAnEmbeddedPointBalancesAndNewtonStaysQuadratic)
{
  test_support::BlockModel block(" set Element degree = 2\n"
                                 " subsection Newton\n  set Line search = false\n end\n"
                                 " subsection Material\n  set Model = neo-Hookean\n  set Bulk modulus = 1e6\n"
                                 "  subsection neo-Hookean\n   set Shear modulus = 2e5\n  end\n end\n"
                                 " subsection Boundary conditions\n  set Fixed = bottom\n end\n",
                                 Point<3>(0.02, 0.02, 0.01), {4, 4, 2});
  auto &model = *block.model;

  // a material point off the nodes (inside a cell face of the top), pulled up and sideways
  const Point<3> X(0.0071, 0.0093, 0.01);
  const Spring   spring(X, X + Point<3>(0.0005, 0, 0.002), 200);
  model.set_point_loads(&spring);
  const auto report = model.solve_static(1.0);
  ASSERT_TRUE(report.converged) << report.failure;
  // quadratic: once in the asymptotic range each residual is below C r²
  const auto &r = report.residual_norms;
  unsigned    quadratic = 0;
  for (std::size_t k = 1; k + 1 < r.size(); ++k)
    if (r[k] < 1e-2 * r[0] && r[k + 1] > 1e-12 * r[0])
      {
        EXPECT_GT(std::log(r[k + 1] / r[0]) / std::log(r[k] / r[0]), 1.8) << "iterate " << k;
        ++quadratic;
      }
  EXPECT_GE(quadratic, 1u);

  const Point<3>     x = model.point_position(0);
  const Tensor<1, 3> f = spring.k * (spring.target - x);
  EXPECT_GT(f[2], 0.05); // the block resists: a good part of the 0.4 N remains
  EXPECT_GT(x[2], X[2] + 1e-4); // and the point moved towards the target
  const auto reactions = model.reactions(1.0);
  ASSERT_EQ(reactions.size(), 1u);
  for (unsigned d = 0; d < 3; ++d)
    EXPECT_NEAR(reactions[0].force[d] + f[d], 0, 1e-8 * f.norm()) << d;
}
