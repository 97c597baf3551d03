// The explicit integrator's stability limit, computed from the network, against a dense
// eigenvalue solve and against what actually happens on either side of it; the
// divergence guard's diagnostic.
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/stability.h>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

#include "realtime/test_worlds.h"

using namespace suturesim;
using namespace suturesim::realtime;

namespace
{
  constexpr unsigned n_links = 40;

  /// A 1-D chain of masses and springs along x, node 0 held by a tool, under symplectic
  /// Euler at 1/rate per step; the free end pulled out by 1 % and released.
  std::unique_ptr<World>
  chain(const double rate, const double damping = 0)
  {
    WorldSetup w;
    w.suture          = test_support::make_model<SutureModel::Registry>("mass-spring");
    w.suture_geometry = test_support::straight_suture(n_links, 0.04, Vector3d::Zero(), Vector3d::UnitX());
    w.integrator      = test_support::make_model<Integrator::Registry>(
      "symplectic-euler", {{"Damping rate", std::to_string(damping)}});
    w.rate     = rate;
    w.substeps = 1;
    auto world = std::make_unique<World>(std::move(w));
    world->add_tool("grasp", {world->system().suture.begin}, ToolPose());
    world->initialize();
    auto &x = world->system().nodes.x;
    for (auto i = world->system().suture.begin; i < world->system().suture.end; ++i)
      x(0, i) *= 1.01;
    return world;
  }

  /// Largest eigenvalue of M^{-1/2} K M^{-1/2} of the free nodes, assembled densely.
  double
  dense_omega_squared(const System &s)
  {
    const Eigen::Index n = s.nodes.size();
    Eigen::MatrixXd    K = Eigen::MatrixXd::Zero(3 * n, 3 * n);
    const auto        *springs = dynamic_cast<const SpringSet *>(s.interactions.front().get());
    for (std::size_t e = 0; e < springs->size(); ++e)
      {
        const auto     a = springs->first_ends()[e], b = springs->second_ends()[e];
        const Vector3d d = s.nodes.x.col(b) - s.nodes.x.col(a);
        const double   L = d.norm(), k = springs->stiffnesses()[e], L0 = springs->rest_lengths()[e];
        const Eigen::Matrix3d nn = d * d.transpose() / (L * L);
        const Eigen::Matrix3d block = k * nn + k * (1 - L0 / L) * (Eigen::Matrix3d::Identity() - nn);
        K.block<3, 3>(3 * a, 3 * a) += block;
        K.block<3, 3>(3 * b, 3 * b) += block;
        K.block<3, 3>(3 * a, 3 * b) -= block;
        K.block<3, 3>(3 * b, 3 * a) -= block;
      }
    Eigen::VectorXd scale(3 * n);
    for (Eigen::Index i = 0; i < n; ++i)
      scale.segment<3>(3 * i).setConstant(s.nodes.held[i] ? 0.0 : 1 / std::sqrt(s.nodes.mass[i]));
    const Eigen::MatrixXd A = scale.asDiagonal() * K * scale.asDiagonal();
    return Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvalues().maxCoeff();
  }
} // namespace

TEST(RealtimeStability, LanczosLimitMatchesTheDenseEigenvalue)
{
  const auto   world  = chain(1000);
  const double omega  = std::sqrt(dense_omega_squared(world->system()));
  const double limit  = symplectic_euler_limit(omega, 0);
  EXPECT_NEAR(world->stability_limit(), limit, 1e-6 * limit);
  EXPECT_NEAR(limit, 2 / omega, 1e-15);
  // damping lowers the limit as (sqrt(c^2 + 4 w^2) - c)/w^2
  EXPECT_NEAR(symplectic_euler_limit(omega, 0.1 * omega), (std::sqrt(0.01 + 4) - 0.1) / omega, 1e-12 / omega);
}

TEST(RealtimeStability, ExplicitEulerChainIsStableBelowAndDivergesAboveTheLimit)
{
  const double dt_crit = chain(1000)->stability_limit();
  std::printf("[ chain ] %u links, dt_crit = %.6e s\n", n_links, dt_crit);

  // 0.95 dt_crit: bounded energy for 20 000 steps
  {
    auto       world = chain(1 / (0.95 * dt_crit));
    const auto &s    = world->system();
    const double e0  = s.elastic_energy(s.nodes.x);
    double       e_max = 0;
    for (int step = 0; step < 20000; ++step)
      {
        ASSERT_NO_THROW(world->step({ToolPose()})) << "step " << step;
        e_max = std::max(e_max, s.elastic_energy(s.nodes.x) + s.kinetic_energy());
      }
    std::printf("[ 0.95 dt_crit ] max energy %.3e J vs initial %.3e J\n", e_max, e0);
    EXPECT_LT(e_max, 2 * e0); // symplectic Euler's energy oscillates about its shadow value
    EXPECT_TRUE(world->warning().empty());
  }

  // 1.05 dt_crit: the guard fires, names step, node and cause, and keeps the last good state
  {
    auto world = chain(1 / (1.05 * dt_crit));
    EXPECT_NE(world->warning().find("above the stability limit"), std::string::npos);
    std::size_t completed = 0;
    try
      {
        for (; completed < 20000; ++completed)
          world->step({ToolPose()});
        FAIL() << "no divergence in 20000 steps at 1.05 dt_crit";
      }
    catch (const DivergenceError &e)
      {
        const std::string what = e.what();
        std::printf("[ 1.05 dt_crit ] %s\n", what.c_str());
        EXPECT_EQ(e.step, completed + 1);
        EXPECT_NE(what.find("step " + std::to_string(completed + 1)), std::string::npos);
        EXPECT_NE(what.find("suture node"), std::string::npos);
        EXPECT_NE(what.find("dt_crit"), std::string::npos);
        EXPECT_EQ(what.find('\n'), std::string::npos);
        EXPECT_TRUE(world->system().nodes.x.allFinite());
        EXPECT_EQ(world->steps(), completed);
      }
  }
}

TEST(RealtimeStability, RefusesAStepAboveTheLimitWhenAsked)
{
  WorldSetup w;
  w.suture          = test_support::make_model<SutureModel::Registry>("mass-spring");
  w.suture_geometry = test_support::straight_suture(10, 0.01, Vector3d::Zero(), Vector3d::UnitX());
  w.integrator      = test_support::make_model<Integrator::Registry>("symplectic-euler");
  w.rate            = 10; // 0.1 s steps, far above the limit
  w.refuse_above_limit = true;
  World world(std::move(w));
  try
    {
      world.initialize();
      FAIL() << "accepted dt above dt_crit";
    }
  catch (const ParameterError &e)
    {
      EXPECT_EQ(e.key, "Substeps");
      EXPECT_NE(e.problem.find("dt_crit"), std::string::npos);
    }
}
