// Suture/Stabilization (rod/viscous_drag.h): a drag c v per unit length of thread,
// v = (x − xₙ)/Δt, lumped to the nodes by half the length of each adjacent element.
// Checked on a polyline of unequal elements against the law itself: a rigid translation
// d meets the total drag c L d/Δt (L the thread's length), each node c ℓ_i d/Δt; the
// Jacobian is the derivative of the residual (central differences); rotations feel
// nothing; the drag vanishes when the nodes are where the step started; the recorded
// total is the sum of the free nodes' drag magnitudes.
#include <suturesim/rod/rod_model.h>
#include <suturesim/rod/viscous_drag.h>

#include <gtest/gtest.h>

#include <random>

using namespace suturesim::rod;

namespace
{
  /// A bent polyline of four elements of 1, 2, 3 and 4 mm (L = 10 mm).
  std::vector<Vec3>
  polyline()
  {
    return {Vec3(0, 0, 0), Vec3(1e-3, 0, 0), Vec3(1e-3, 2e-3, 0), Vec3(1e-3, 2e-3, 3e-3), Vec3(5e-3, 2e-3, 3e-3)};
  }

  RodModel
  rod_through(const std::vector<Vec3> &x)
  {
    return RodModel(x, std::vector<Quat>(x.size(), Quat::Identity()), SectionStiffness{}, 1, Vec3::Ones());
  }

  constexpr double c  = 4.0;  // N s/m²
  constexpr double dt = 0.02; // s
} // namespace

TEST(ViscousDrag, RigidTranslationMeetsCTimesLengthTimesVelocity)
{
  const auto        start = polyline();
  const RodModel    model = rod_through(start);
  ViscousDrag       drag(model, c);
  drag.begin_step(&start, dt);
  const Vec3        d(1e-4, -2e-4, 3e-4);
  const double      half[] = {0.5e-3, 1.5e-3, 2.5e-3, 3.5e-3, 2e-3}; // ℓ_i, m
  Vec3              total  = Vec3::Zero();
  for (std::size_t i = 0; i < start.size(); ++i)
    {
      Vec6 r = Vec6::Zero();
      Mat6 J = Mat6::Zero();
      drag.add(i, start[i] + d, r, J);
      EXPECT_LT((r.head<3>() - c * half[i] * d / dt).norm(), 1e-14 * (c * half[i] * d.norm() / dt)) << i;
      EXPECT_EQ(r.tail<3>().norm(), 0.0) << "the drag acts on rotations";
      total += r.head<3>();
    }
  EXPECT_LT((total - c * 10e-3 * d / dt).norm(), 1e-13 * c * 10e-3 * d.norm() / dt);

  std::vector<Vec3> moved = start;
  for (auto &x : moved)
    x += d;
  const double free_nodes = 1.5e-3 + 2.5e-3 + 3.5e-3; // the ends are excluded
  EXPECT_NEAR(drag.total_force(moved), c * free_nodes * d.norm() / dt, 1e-13);
  EXPECT_EQ(drag.total_force(start), 0.0);
}

TEST(ViscousDrag, JacobianIsTheDerivativeOfTheResidualAndNothingActsAtRest)
{
  const auto     start = polyline();
  const RodModel model = rod_through(start);
  ViscousDrag    drag(model, c);
  drag.begin_step(&start, dt);
  EXPECT_TRUE(drag.active());
  EXPECT_FALSE(ViscousDrag(model, 0.0).active());

  std::mt19937                           random(7);
  std::uniform_real_distribution<double> u(-1e-4, 1e-4);
  const double                           h = 1e-7;
  for (std::size_t i = 0; i < start.size(); ++i)
    {
      Vec6 r0 = Vec6::Zero();
      Mat6 J  = Mat6::Zero();
      drag.add(i, start[i], r0, J);
      EXPECT_EQ(r0.norm(), 0.0) << "drag at the step's start";

      const Vec3 x(start[i] + Vec3(u(random), u(random), u(random)));
      Mat6       numeric = Mat6::Zero();
      for (int k = 0; k < 3; ++k)
        {
          Vec6 plus = Vec6::Zero(), minus = Vec6::Zero();
          Mat6 unused = Mat6::Zero();
          drag.add(i, x + h * Vec3::Unit(k), plus, unused);
          drag.add(i, x - h * Vec3::Unit(k), minus, unused);
          numeric.col(k) = (plus - minus) / (2 * h);
        }
      EXPECT_LT((numeric - J).norm(), 1e-6 * J.norm()) << i;
      const double others = J.bottomRows<3>().norm() + J.topRightCorner<3, 3>().norm();
      EXPECT_EQ(others, 0.0);
    }
}
