// The Cosserat rod element and model: tangents against central finite differences
// (conventions.md §6) and objectivity (a superposed rigid motion changes neither the
// strains nor the energy, and rotates the residual with it).
#include <suturesim/rod/generalized_alpha.h>
#include <suturesim/rod/rod_model.h>

#include "rod_test_support.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <random>

using namespace suturesim::rod;

namespace
{
  std::mt19937 rng(12345);


  using test_support::anisotropic_section;

  /// A curved, twisted stress-free shape of @p n elements: nodes @p x and rotations @p q.
  void
  curved_shape(const unsigned n, std::vector<Vec3> &x, std::vector<Quat> &q)
  {
    for (unsigned i = 0; i <= n; ++i)
      {
        const double s = double(i) / n;
        x.emplace_back(s, 0.2 * std::sin(3 * s), 0.1 * s * s);
        q.push_back(quaternion_exp(Vec3(1.5 * s, 0.3 * s, 0.4 * std::sin(2 * s))));
      }
  }

  /// A free rod with a curved, twisted stress-free shape, then moved away from it.
  RodModel
  deformed_rod(const unsigned n, const double amplitude)
  {
    std::vector<Vec3> x;
    std::vector<Quat> q;
    curved_shape(n, x, q);
    RodModel model(x, q, anisotropic_section(), 0.7, Vec3(0.01, 0.02, 0.03));
    for (unsigned i = 0; i <= n; ++i)
      model.set_node(i, x[i] + test_support::random_vector(rng, amplitude * 0.1),
                     quaternion_exp(test_support::random_vector(rng, amplitude)) * q[i]);
    return model;
  }

  double
  energy_at(const ElementReference &ref, const Vec3 &x1, const Quat &q1, const Vec3 &x2,
            const Quat &q2, const Vec12 &d)
  {
    return element_state(x1 + d.segment<3>(0), quaternion_exp(d.segment<3>(3)) * q1,
                         x2 + d.segment<3>(6), quaternion_exp(d.segment<3>(9)) * q2, ref,
                         anisotropic_section())
      .energy;
  }
} // namespace

// Gradient and Hessian of the pulled-back element energy W(x + Δx, exp(θ̂)R) against
// central differences of the energy, for random configurations with large relative
// rotations (up to ~1.4 rad per element) and non-zero reference strains.
TEST(RodElement, TangentMatchesFiniteDifferences)
{
  for (int trial = 0; trial < 20; ++trial)
    {
      const Vec3 x1 = test_support::random_vector(rng, 1);
      const Vec3 x2 = x1 + Vec3(1, 0, 0) + test_support::random_vector(rng, 0.5);
      const Quat q1 = quaternion_exp(test_support::random_vector(rng, 2));
      const Quat q2 = quaternion_exp(test_support::random_vector(rng, 0.8)) * q1;
      ElementReference ref;
      ref.length = 0.9;
      ref.gamma0 = Vec3(1, 0.1, -0.05);
      ref.kappa0 = Vec3(0.2, -0.3, 0.1);
      Vec12 g;
      Mat12 H;
      element_tangent(x1, q1, x2, q2, ref, anisotropic_section(), g, &H);
      Vec12        g_fd;
      Mat12        H_fd;
      const double h = 1e-5;
      for (int i = 0; i < 12; ++i)
        {
          const Vec12 ei = Vec12::Unit(i) * h;
          g_fd[i] = (energy_at(ref, x1, q1, x2, q2, ei) - energy_at(ref, x1, q1, x2, q2, -ei)) / (2 * h);
          for (int j = 0; j < 12; ++j)
            {
              const Vec12 ej = Vec12::Unit(j) * h;
              H_fd(i, j) = (energy_at(ref, x1, q1, x2, q2, ei + ej) - energy_at(ref, x1, q1, x2, q2, ei - ej) -
                            energy_at(ref, x1, q1, x2, q2, ej - ei) + energy_at(ref, x1, q1, x2, q2, -ei - ej)) /
                           (4 * h * h);
            }
        }
      // central differences: O(h²) ≈ 1e-10 truncation for the gradient; the Hessian's
      // fourth-difference round-off is ε|W|/h² ≈ 1e-6 relative
      EXPECT_LT((g - g_fd).norm(), 1e-8 * g.norm()) << "trial " << trial;
      EXPECT_LT((H - H_fd).norm(), 2e-5 * H.norm()) << "trial " << trial;
      EXPECT_LT((H - H.transpose()).norm(), 1e-12 * H.norm());
    }
}

namespace
{
  /// The relative error ‖J − J_fd‖/‖J‖ of the assembled Jacobian of one random
  /// configuration (seed @p seed) of a 6-element rod. J_fd: central differences D(s) of
  /// the residual along x + εe_k and exp(εê_k)R, extrapolated as (4 D(h) − D(2h))/3, whose
  /// truncation error is O(h⁴) instead of O(h²). Variant 0: elastic, fixed-direction end
  /// moment, interior-point self-contact; 1: with generalized-α inertia terms; 2: with an
  /// element spring (a point inside an element, as a pierce point loads the suture). For
  /// variant 2 @p without_spring receives ‖J − J(no spring)‖.
  double
  jacobian_fd_error(const int variant, const unsigned seed, const double h,
                    double *without_spring = nullptr)
  {
    rng.seed(seed);
    RodModel model         = deformed_rod(6, 0.4);
    model.moments().back() = Vec3(0.1, 0.3, 0.2);
    model.forces()[2]      = Vec3(0.2, -0.1, 0.05);
    // contact between the first and the last segments, brought close
    model.set_node(6, model.positions()[0] + Vec3(0.02, 0.08, 0.03), model.rotations()[6]);
    model.set_contact(ContactParameters{true, 50.0, 0.01, 0.05});
    GeneralizedAlpha ga(model, 0.8, 0.3);
    ga.initialize(std::vector<Vec3>(7, Vec3(0.1, 0, 0)), std::vector<Vec3>(7, Vec3(0, 0.5, 0)));
    // move away from tₙ so that Ψ ≠ 0
    for (std::size_t i = 0; i < 7; ++i)
      model.set_node(i, model.positions()[i] + test_support::random_vector(rng, 0.01),
                     quaternion_exp(test_support::random_vector(rng, 0.2)) * model.rotations()[i]);
    const NodalTerms  terms = ga.inertia_terms(0.01);
    const NodalTerms *extra = variant == 1 ? &terms : nullptr;
    // a spring k (c − p) at c = 0.3 x₂ + 0.7 x₃ (element 2) towards a fixed point p
    const ElementTerms spring = [&model](const std::size_t e, Vec12 &r, Mat12 *J) {
      const double w[2] = {0.3, 0.7}, k = 30;
      const Vec3   c    = w[0] * model.positions()[e] + w[1] * model.positions()[e + 1];
      for (int a = 0; a < 2; ++a)
        {
          r.segment<3>(6 * a) += w[a] * k * (c - Vec3(0.4, 0.3, 0.2));
          for (int b = 0; b < 2; ++b)
            if (J)
              J->block<3, 3>(6 * a, 6 * b) += w[a] * w[b] * k * Mat3::Identity();
        }
    };
    const ElementList springs{2};
    if (variant == 2)
      model.set_element_terms(&spring, &springs);
    const Eigen::MatrixXd J = model.dense_jacobian(extra); // assembles: the contact forces
    EXPECT_GT(model.contact_forces()[0] + model.contact_forces()[6], 0) << "contact must be active, seed " << seed;
    const double error = test_support::jacobian_fd_error(model, h, extra);
    if (without_spring != nullptr)
      {
        model.set_element_terms(nullptr, nullptr);
        *without_spring = (J - model.dense_jacobian(extra)).norm();
      }
    return error;
  }
} // namespace

// The assembled Jacobian (elastic, fixed-direction end moment, self-contact with interior
// closest points, generalized-α inertia terms, element terms) against finite differences.
// This checks the −½ r̂ correction of a non-conservative moment, the envelope Hessian of
// the contact and the J_r(Ψ)⁻¹ of the inertia. The error floor of the differences,
// measured over the 3 variants × 8 configurations below for h = 1e-3 … 1e-6: smallest at
// h = 3e-5, where it is 4.7e-13 … 6.0e-11 (the largest where the contact's smoothing is
// most curved; above h it falls as h⁴, below it rises as round-off ε‖r‖/h). Tolerance
// 6e-10, 10 × the largest. A wrong term shows far above it: dropping the element spring's
// blocks (variant 2) changes J by more than 1 (checked).
TEST(RodModel, JacobianMatchesFiniteDifferences)
{
  const double h = 3e-5, tolerance = 6e-10;
  double       worst     = 0;
  unsigned     springs   = 0;
  for (const int variant : {0, 1, 2})
    for (unsigned seed = 1; seed <= 8; ++seed)
      {
        double       spring_part = 0;
        const double error = jacobian_fd_error(variant, seed, h, variant == 2 ? &spring_part : nullptr);
        std::printf("variant %d (0 static, 1 inertia, 2 element spring), configuration %u: "
                    "|J - J_fd|/|J| = %.2e\n", variant, seed, error);
        EXPECT_LT(error, tolerance) << "variant " << variant << ", configuration " << seed;
        if (variant == 2)
          {
            // the spring's own blocks are there (not only the elastic ones)
            EXPECT_GT(spring_part, 1.0);
            ++springs;
          }
        worst = std::max(worst, error);
      }
  EXPECT_EQ(springs, 8u);
  std::printf("largest FD error %.2e, tolerance %.2e\n", worst, tolerance);
}

// linearize() and solve_linearized(): the factorised Jacobian solves J x = b for several
// right-hand sides (the condensation of the suture onto the tissue's points needs 3 per
// point), with the block LU of an open rod and the sparse LU when contact couples
// distant nodes; constrained components of x are zero.
TEST(RodModel, LinearizedSolvesMatchTheJacobian)
{
  for (const bool with_contact : {false, true})
    {
      RodModel model = deformed_rod(6, 0.4);
      model.set_node(6, model.positions()[0] + Vec3(0.02, 0.08, 0.03), model.rotations()[6]);
      if (with_contact)
        model.set_contact(ContactParameters{true, 50.0, 0.01, 0.05});
      model.constrain(0, {{true, true, true, true, true, true}});
      const Eigen::MatrixXd J = model.dense_jacobian();
      // with contact, the premise: some node pair beyond neighbours is coupled, so the
      // sparse LU is the one at work
      bool distant = false;
      for (Eigen::Index i = 0; i < J.rows(); ++i)
        for (Eigen::Index j = 0; j < J.cols(); ++j)
          distant = distant || (std::abs(i / 6 - j / 6) > 1 && J(i, j) != 0);
      EXPECT_EQ(distant, with_contact);
      const Eigen::VectorXd r = model.linearize();
      EXPECT_EQ(r, model.residual());
      for (int trial = 0; trial < 3; ++trial)
        {
          const Eigen::VectorXd b = Eigen::VectorXd::Random(J.rows());
          const Eigen::VectorXd x = model.solve_linearized(b);
          EXPECT_EQ(x.head<6>().norm(), 0) << "contact " << with_contact;
          // J on the free rows and columns
          const Eigen::VectorXd Jx = J.bottomRightCorner(J.rows() - 6, J.cols() - 6) * x.tail(x.size() - 6);
          EXPECT_LT((Jx - b.tail(b.size() - 6)).norm(), 1e-9 * b.norm() * J.norm())
            << "contact " << with_contact;
        }
    }
}

// Objectivity and rigid-body invariance: (1) the stress-free rod moved by a large rigid
// rotation and translation has zero strain and zero residual; (2) a deformed rod moved
// rigidly keeps its energy and its residual rotates with it.
TEST(RodModel, RigidMotionIsStrainFree)
{
  const Quat Q     = quaternion_exp(Vec3(2.1, -1.3, 0.7)); // 2.6 rad about a skew axis
  const Vec3 shift = Vec3(0.3, -2, 5);
  {
    RodModel  model = deformed_rod(8, 0);
    const auto x    = model.positions();
    const auto q    = model.rotations();
    for (std::size_t i = 0; i < x.size(); ++i)
      model.set_node(i, Q * x[i] + shift, Q * q[i]);
    for (const auto &s : model.element_states())
      {
        EXPECT_LT(s.Gamma.norm(), 1e-13);
        EXPECT_LT(s.K.norm(), 1e-13);
      }
    EXPECT_LT(model.residual().norm(), 1e-12);
  }
  {
    RodModel              model = deformed_rod(8, 0.5);
    const double          W0    = model.potential_energy();
    const Eigen::VectorXd r0    = model.residual();
    const auto            x     = model.positions();
    const auto            q     = model.rotations();
    for (std::size_t i = 0; i < x.size(); ++i)
      model.set_node(i, Q * x[i] + shift, Q * q[i]);
    EXPECT_NEAR(model.potential_energy(), W0, 1e-13 * std::abs(W0));
    const Eigen::VectorXd r1 = model.residual();
    for (std::size_t i = 0; i < x.size(); ++i)
      for (int part = 0; part < 2; ++part)
        EXPECT_LT((Vec3(r1.segment<3>(6 * i + 3 * part)) - Q * Vec3(r0.segment<3>(6 * i + 3 * part))).norm(),
                  1e-12 * r0.norm());
  }
}

// A cut (RodModel::cut, an interrupted series' thread cut beside a stitch's knot): the rod
// cut at element 3 of 8 is the two rods of nodes 0-3 and 4-8 built alone from the same
// stress-free shape, to round-off: the same residual on each piece in a deformed state,
// the pieces' energies adding up, no Jacobian block across the cut, and under end loads,
// each piece clamped at its outer end, Newton's equilibrium is theirs; uncut, the same
// loads bend the one rod elsewhere.
TEST(RodModel, ACutRodIsItsTwoPieces)
{
  constexpr unsigned n = 8, cut = 3;
  std::vector<Vec3>  x;
  std::vector<Quat>  q;
  curved_shape(n, x, q);
  const auto piece = [&](const unsigned from, const unsigned to) {
    return RodModel({x.begin() + from, x.begin() + to + 1}, {q.begin() + from, q.begin() + to + 1},
                    anisotropic_section(), 0.7, Vec3(0.01, 0.02, 0.03));
  };
  RodModel whole = piece(0, n), uncut = piece(0, n), a = piece(0, cut), b = piece(cut + 1, n);
  whole.cut(cut);
  EXPECT_TRUE(whole.is_cut(cut));
  EXPECT_FALSE(whole.is_cut(cut + 1));
  // a deformed state, the same on both
  for (unsigned i = 0; i <= n; ++i)
    {
      const Vec3 xi = x[i] + test_support::random_vector(rng, 0.04);
      const Quat qi = quaternion_exp(test_support::random_vector(rng, 0.4)) * q[i];
      whole.set_node(i, xi, qi);
      (i <= cut ? a : b).set_node(i <= cut ? i : i - cut - 1, xi, qi);
    }
  const Eigen::VectorXd r = whole.residual(), ra = a.residual(), rb = b.residual();
  EXPECT_LT((r.head(ra.size()) - ra).norm(), 1e-12 * ra.norm());
  EXPECT_LT((r.tail(rb.size()) - rb).norm(), 1e-12 * rb.norm());
  EXPECT_NEAR(whole.potential_energy(), a.potential_energy() + b.potential_energy(),
              1e-12 * whole.potential_energy());
  const Eigen::MatrixXd J = whole.dense_jacobian();
  EXPECT_EQ((J.block<6, 6>(6 * cut, 6 * (cut + 1)).norm()), 0);
  EXPECT_EQ((J.block<6, 6>(6 * (cut + 1), 6 * cut).norm()), 0);
  EXPECT_EQ(whole.element_states()[cut].energy, 0);

  // equilibrium under loads at the cut ends, each piece clamped at its outer end
  const std::array<bool, 6> clamp{{true, true, true, true, true, true}};
  const Vec3                load_a(0, 0, -2e-3), load_b(1e-3, 2e-3, 0);
  for (RodModel *m : {&whole, &uncut, &a, &b})
    for (unsigned i = 0; i < m->n_nodes(); ++i)
      m->set_node(i, m == &b ? x[i + cut + 1] : x[i], m == &b ? q[i + cut + 1] : q[i]);
  for (RodModel *m : {&whole, &uncut})
    {
      m->constrain(0, clamp);
      m->constrain(n, clamp);
      m->forces()[cut]     = load_a;
      m->forces()[cut + 1] = load_b;
    }
  a.constrain(0, clamp);
  a.forces()[cut] = load_a;
  b.constrain(n - cut - 1, clamp);
  b.forces()[0] = load_b;
  NewtonParameters newton;
  newton.max_iterations = 100;
  for (RodModel *m : {&whole, &uncut, &a, &b})
    ASSERT_TRUE(m->solve(newton).converged);
  const double moved = (a.positions()[cut] - x[cut]).norm();
  EXPECT_GT(moved, 1e-3); // the loads deform the pieces measurably
  for (unsigned i = 0; i <= n; ++i)
    {
      const Vec3 &alone = i <= cut ? a.positions()[i] : b.positions()[i - cut - 1];
      EXPECT_LT((whole.positions()[i] - alone).norm(), 1e-10 * moved) << "node " << i;
    }
  EXPECT_GT((uncut.positions()[cut] - a.positions()[cut]).norm(), 0.1 * moved);
  std::printf("cut end moved %.4e m; cut rod against its pieces %.2e m; uncut rod %.4e m away\n", moved,
              (whole.positions()[cut] - a.positions()[cut]).norm(),
              (uncut.positions()[cut] - a.positions()[cut]).norm());
}
