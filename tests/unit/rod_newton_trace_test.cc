// The suture's Newton diagnostics (Suture/Newton/Trace failures) and its stall fallback
// (Suture/Newton/Stall window): RodModel's residual split by contribution adds up to its
// residual; the Newton observer sees every iterate with the step it takes and the state
// the solve stops in; SutureNewtonTrace writes a failed solve's iterations with each
// part's norm (scene/suture_newton_trace.h); full steps that cycle between the slip
// branches of a friction law are handed to the energy line search, which converges, also
// when an active set changes between the steps; a
// correction longer than the caps is replaced by the trust-region step, which lays a
// slack thread where the scaled-down Newton correction crawls.
#include "run_scene.h"

#include <suturesim/rod/cross_section.h>
#include <suturesim/rod/rod_model.h>
#include <suturesim/scene/suture_newton_trace.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace suturesim::rod;

namespace
{
  /// A bent rod of four elements (1, 2, 3, 4 mm), clamped at its first node, with a
  /// force and a moment at its last and an element term (a spring pulling element 1's
  /// nodes apart along x).
  struct LoadedRod
  {
    std::vector<Vec3> x{Vec3(0, 0, 0), Vec3(1e-3, 0, 0), Vec3(1e-3, 2e-3, 0), Vec3(1e-3, 2e-3, 3e-3),
                        Vec3(5e-3, 2e-3, 3e-3)};
    RodModel          rod{x, std::vector<Quat>(x.size(), Quat::Identity()), SectionStiffness{Vec3(10, 5, 5), Vec3(1e-6, 2e-6, 2e-6)}, 1, Vec3::Ones()};
    ElementTerms      spring = [this](const std::size_t k, Eigen::Matrix<double, 12, 1> &r,
                                 Eigen::Matrix<double, 12, 12> *J) {
      const double k_s = 50; // N/m
      const Vec3   d   = rod.positions()[k + 1] - rod.positions()[k] - Vec3(2e-3, 0, 0);
      r.segment<3>(0) -= k_s * d;
      r.segment<3>(6) += k_s * d;
      if (J)
        for (unsigned a = 0; a < 2; ++a)
          for (unsigned b = 0; b < 2; ++b)
            J->block<3, 3>(6 * a, 6 * b) += (a == b ? 1.0 : -1.0) * k_s * Eigen::Matrix3d::Identity();
    };
    ElementList elements{1};
    NodalTerms  gravity = [](std::size_t, const Vec3 &, const Quat &, Vec6 &r, Mat6 &) { r[2] += 1e-3; };
    NodalTerms  spring_to_origin = [](std::size_t, const Vec3 &xi, const Quat &, Vec6 &r, Mat6 &J) {
      r.head<3>() += 20 * xi;
      J.topLeftCorner<3, 3>() += 20 * Eigen::Matrix3d::Identity();
    };
    NodalTerms both = [this](std::size_t i, const Vec3 &xi, const Quat &q, Vec6 &r, Mat6 &J) {
      gravity(i, xi, q, r, J);
      spring_to_origin(i, xi, q, r, J);
    };

    LoadedRod()
    {
      rod.constrain(0, {{true, true, true, true, true, true}});
      rod.forces().back()  = Vec3(0.01, -0.02, 0.005);
      rod.moments().back() = Vec3(0, 1e-5, 0);
      rod.set_element_terms(&spring, &elements);
    }
  };
} // namespace

TEST(SutureNewtonTrace, ResidualPartsAddUpToTheResidual)
{
  LoadedRod loaded;
  // away from the reference: every part is non-zero
  loaded.rod.set_node(4, Vec3(5.2e-3, 2.1e-3, 2.9e-3), Quat(Eigen::AngleAxisd(0.1, Vec3::UnitZ())));
  const Eigen::VectorXd r     = loaded.rod.residual(&loaded.both);
  const ResidualParts   parts = loaded.rod.residual_parts({&loaded.gravity, &loaded.spring_to_origin});
  ASSERT_EQ(parts.nodal.size(), 2u);
  const Eigen::VectorXd sum =
    parts.elastic + parts.self_contact + parts.applied + parts.element_terms + parts.nodal[0] + parts.nodal[1];
  EXPECT_LT((sum - r).norm(), 1e-14 * r.norm());
  for (const auto *p : {&parts.elastic, &parts.applied, &parts.element_terms, &parts.nodal[0], &parts.nodal[1]})
    EXPECT_GT(p->norm(), 1e-6 * r.norm());
  EXPECT_EQ(parts.self_contact.norm(), 0.0); // no contact set
  // each part is what it says: the applied loads are minus the forces and moments
  EXPECT_EQ(parts.applied.segment<3>(24), -loaded.rod.forces().back());
  EXPECT_EQ(parts.applied.segment<3>(27), -loaded.rod.moments().back());
  EXPECT_EQ(parts.nodal[0][6 * 2 + 2], 1e-3);
}

TEST(SutureNewtonTrace, ObserverSeesEveryIterateAndTheStateTheSolveStopsIn)
{
  LoadedRod                  loaded;
  NewtonParameters           prm;
  std::vector<NewtonIterate> seen;
  std::vector<double>        deltas;
  prm.observer = [&](const NewtonIterate &it) {
    seen.push_back(it);
    deltas.push_back(it.delta ? it.delta->norm() : -1);
  };
  const NewtonResult result = loaded.rod.solve(prm, &loaded.both);
  ASSERT_TRUE(result.converged) << result.reason;
  ASSERT_EQ(seen.size(), result.iterations + 1u);
  for (std::size_t k = 0; k < seen.size(); ++k)
    {
      EXPECT_EQ(seen[k].iteration, k);
      EXPECT_EQ(seen[k].delta == nullptr, k + 1 == seen.size()) << k; // the last: no step
      if (k + 1 < seen.size())
        {
          EXPECT_GT(deltas[k], 0) << k;
          EXPECT_GT(seen[k].step, 0) << k;
          EXPECT_LE(seen[k].step, 1) << k;
        }
    }
  EXPECT_EQ(seen.back().residual, result.residual);
}

TEST(SutureNewtonTrace, AFailedSolveIsWrittenWithEachPartsNorm)
{
  LoadedRod                                  loaded;
  const auto                                 file = suturesim::test_support::scratch_path() / "suture_newton_trace.csv";
  std::filesystem::remove(file);
  suturesim::scene::SutureNewtonTrace        trace({{"gravity", &loaded.gravity}, {"spring", &loaded.spring_to_origin}},
                                                   file.string());
  NewtonParameters                           prm;
  prm.max_iterations = 1; // fails: too few
  prm.tolerance      = 1e-14;
  prm.observer       = [&](const NewtonIterate &it) { trace.record(loaded.rod, it); };
  ASSERT_FALSE(loaded.rod.solve(prm, &loaded.both).converged);
  trace.write(0.5, 0.02);
  std::ifstream in(file);
  std::string   header, line;
  std::getline(in, header);
  EXPECT_NE(header.find("elastic [N|N m]"), std::string::npos);
  EXPECT_NE(header.find("gravity [N|N m]"), std::string::npos);
  EXPECT_NE(header.find("worst node spring [N|N m]"), std::string::npos);
  unsigned rows = 0;
  for (; std::getline(in, line); ++rows)
    EXPECT_EQ(line.rfind("0.5,0.02,1,", 0), 0u) << line;
  EXPECT_EQ(rows, 2u); // iteration 0 and the state it stopped in
}

namespace
{
  /// A cantilever of 10 mm along x (EI = 1e-6 N m²: tip stiffness 3EI/L³ = 3 N/m) pulled
  /// sideways at its tip by P = 5 mN and held there by a friction-like law of the
  /// pierce points' kind: f = −clamp(k_t (y − a), ±F), k_t = 1e4 N/m, F = 10 mN, anchor
  /// a = −1 mm. Equilibrium sticks within a band 2F/k_t = 2 µm wide near a. The law's
  /// slip branches are flat, so a full Newton step from either lands on the other,
  /// millimetres away: y = (P − F)/K = −1.7 mm, then (P + F)/K = +5 mm, and round again.
  struct FrictionHeldTip
  {
    std::vector<Vec3> x{Vec3(0, 0, 0), Vec3(2.5e-3, 0, 0), Vec3(5e-3, 0, 0), Vec3(7.5e-3, 0, 0), Vec3(1e-2, 0, 0)};
    RodModel          rod{x, std::vector<Quat>(x.size(), Quat::Identity()), SectionStiffness{Vec3(100, 50, 50), Vec3(1e-6, 1e-6, 1e-6)}, 1,
                 Vec3::Ones()};
    static constexpr double k_t = 1e4, F = 0.01, a = -1e-3;
    NodalTerms              friction = [](std::size_t i, const Vec3 &xi, const Quat &, Vec6 &r, Mat6 &J) {
      if (i != 4)
        return;
      const double trial = k_t * (xi[1] - a);
      r[1] += std::clamp(trial, -F, F); // the residual carries minus the force on the node
      J(1, 1) += std::abs(trial) < F ? k_t : 0.0;
    };

    FrictionHeldTip()
    {
      rod.constrain(0, {{true, true, true, true, true, true}});
      rod.forces().back() = Vec3(0, 0.005, 0);
    }

    /// The tip's trial force within the friction bound: it sticks.
    double
    trial_force() const
    {
      return k_t * (rod.positions().back()[1] - a);
    }
  };
} // namespace

TEST(SutureNewtonTrace, AStallOfFullStepsIsHandedToTheEnergyLineSearch)
{
  // full steps alone cycle between the slip branches
  FrictionHeldTip  cycling;
  NewtonParameters full;
  full.stall_window   = 0;
  full.max_iterations = 200;
  const NewtonResult stalled = cycling.rod.solve(full, &cycling.friction);
  EXPECT_FALSE(stalled.converged);
  EXPECT_EQ(stalled.line_search_from, 0u);
  std::printf("[ stall ] full steps: residual %.3e N after %u iterations\n", stalled.residual, stalled.iterations);

  // with the stall window the line search takes over and lands in the stick band
  FrictionHeldTip  held;
  NewtonParameters fallback = full;
  fallback.stall_window     = 20;
  const NewtonResult result = held.rod.solve(fallback, &held.friction);
  ASSERT_TRUE(result.converged) << result.reason;
  std::printf("[ stall ] line search from iteration %u, converged at %u (residual %.3e N)\n", result.line_search_from,
              result.iterations, result.residual);
  EXPECT_GE(result.line_search_from, 19u); // twenty iterations, 0 to 19, without progress
  EXPECT_LT(result.iterations, 200u);
  EXPECT_LT(std::abs(held.trial_force()), FrictionHeldTip::F); // it sticks
}

TEST(SutureNewtonTrace, TheStallWindowRunsOnAcrossActiveSetChanges)
{
  // The same cycle, with an active set that reports a change after every other step
  // (NewtonParameters::follow), as a pierce point at a node switches its carrier element
  // back and forth: the solve re-assembles but its stall window runs on, so the line
  // search still takes over. A window restarted at each change never closed: on
  // parameters/tearing/bite_spacing.prm at b = 6 mm, s = 3 mm, 97 of the 98 suture solves
  // that failed took 500 full steps (docs/tearing.md).
  FrictionHeldTip  held;
  NewtonParameters prm;
  prm.max_iterations = 200;
  unsigned steps = 0, changes = 0;
  prm.follow = [&] {
    const bool changed = ++steps % 2 == 0;
    changes += changed;
    return changed;
  };
  const NewtonResult result = held.rod.solve(prm, &held.friction);
  ASSERT_TRUE(result.converged) << result.reason << " after " << changes << " changes";
  std::printf("[ stall ] %u active-set changes; line search from iteration %u, converged at %u\n", changes,
              result.line_search_from, result.iterations);
  EXPECT_GE(changes, 10u);
  EXPECT_GE(result.line_search_from, 19u);
  EXPECT_LT(result.iterations, 200u);
  EXPECT_LT(std::abs(held.trial_force()), FrictionHeldTip::F); // it sticks
}

namespace
{
  /// A thread of 40 elements of 0.5 mm (the stitch's suture: a 3-0 monofilament of
  /// 3 GPa, 0.225 mm across), straight and stress free along x, clamped at its first
  /// node and held in position at its last; its nodes are then laid on a circular arc
  /// of the thread's length whose chord is @p chord, their rotations left as they were,
  /// so that each element is sheared by up to half the arc's angle: a slack thread far
  /// from equilibrium, as the stitch's thread is when its ends jump. Solved with the
  /// stitch's caps (half an element, 0.25 rad).
  NewtonResult
  lay_slack_thread(const double chord, const bool trust_region, std::vector<Vec3> *laid = nullptr)
  {
    const std::size_t n = 40;
    const double      h = 0.5e-3, length = n * h;
    std::vector<Vec3> x;
    for (std::size_t i = 0; i <= n; ++i)
      x.push_back(Vec3(i * h, 0, 0));
    const CrossSection section;
    RodModel rod(x, std::vector<Quat>(x.size(), Quat::Identity()), section.stiffness(), section.mass_per_length(),
                 section.rotational_inertia_per_length());
    rod.constrain(0, {{true, true, true, true, true, true}});
    rod.constrain(n, {{true, true, true, false, false, false}});
    // the arc's angle θ: 2 (L/θ) sin(θ/2) = chord, by Newton's method from θ = 2
    double theta = 2;
    for (int k = 0; k < 50; ++k)
      theta -= (2 * length / theta * std::sin(theta / 2) - chord) /
               (length / theta * std::cos(theta / 2) - 2 * length / (theta * theta) * std::sin(theta / 2));
    const double radius = length / theta;
    for (std::size_t i = 1; i <= n; ++i)
      {
        const double a = theta * (double(i) / n - 0.5);
        rod.set_node(i, Vec3(chord / 2 + radius * std::sin(a), 0, radius * (std::cos(a) - std::cos(theta / 2))),
                     Quat::Identity());
      }
    NewtonParameters prm;
    prm.max_iterations   = 500;
    prm.max_displacement = 0.5 * h;
    prm.max_rotation     = 0.25;
    prm.trust_region     = trust_region;
    const NewtonResult result = rod.solve(prm, nullptr);
    if (laid)
      *laid = rod.positions();
    return result;
  }
} // namespace

TEST(SutureNewtonTrace, ATrustRegionStepLaysASlackThreadWhereTheCappedNewtonCorrectionCrawls)
{
  // chords of 15, 10 and 5 mm of a 20 mm thread: arcs of 146°, 217° and 284°
  for (const double chord : {15e-3, 10e-3, 5e-3})
    {
      const NewtonResult capped = lay_slack_thread(chord, false);
      std::vector<Vec3>  laid;
      const NewtonResult trust  = lay_slack_thread(chord, true, &laid);
      std::printf("[ trust ] chord %.0f mm: capped Newton %s in %u iterations, trust region %s in %u\n", chord * 1e3,
                  capped.converged ? "converged" : "failed", capped.iterations,
                  trust.converged ? "converged" : "failed", trust.iterations);
      ASSERT_TRUE(trust.converged) << trust.reason;
      EXPECT_LE(trust.iterations, 100u);
      // the configuration is one the trust region is there for: the capped Newton
      // correction needs several times the iterations (it fails on the 10 mm chord)
      EXPECT_GT(capped.iterations, 2 * trust.iterations);
      // the thread is laid where it was put: its last node held, in the arc's plane
      EXPECT_NEAR(laid.back()[0], chord, 1e-12);
      for (const Vec3 &p : laid)
        EXPECT_NEAR(p[1], 0, 1e-9);
    }
}

TEST(SutureNewtonTrace, ACorrectionWithinTheCapsIsTheNewtonCorrection)
{
  // the trust region only replaces corrections the caps would cut: on the loaded rod,
  // whose corrections stay within generous caps, the iterates are Newton's to round-off
  std::vector<std::vector<double>> norms(2);
  for (const bool trust : {false, true})
    {
      LoadedRod        loaded;
      NewtonParameters prm;
      prm.max_displacement = 1;
      prm.max_rotation     = 10;
      prm.trust_region     = trust;
      prm.observer         = [&](const NewtonIterate &it) { norms[trust].push_back(it.residual); };
      ASSERT_TRUE(loaded.rod.solve(prm, &loaded.both).converged);
    }
  ASSERT_EQ(norms[0].size(), norms[1].size());
  for (std::size_t k = 0; k < norms[0].size(); ++k)
    EXPECT_EQ(norms[0][k], norms[1][k]);
}
