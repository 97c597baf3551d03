// Penalty against Lagrange-multiplier enforcement of a pierce point's tie across the
// needle (coupling/accurate/tissue_needle.h). A material point inside a fixed-bottom
// block is pierced by a needle that passes 0.2 mm beside it radially and 0.1 mm across
// its plane, so the tie must pull the tissue onto the needle. With Lagrange multipliers
// (Uzawa updates between solves) the tie closes to the tolerance whatever k⊥; with
// penalty a gap |f⊥| / k⊥ remains, and for a body of point stiffness K the penalty
// solution differs from the constrained one by K δ / (K + k⊥), which falls as 1/k⊥
// (springs in series; Wriggers 2006, "Computational Contact Mechanics", §6.2). The test
// prints that convergence, checks it against the series formula with K taken from the
// Lagrange solution, and checks its order.
#include "block_model.h"

#include <suturesim/coupling/accurate/tissue_needle.h>
#include <suturesim/mesh/simplex_mesh.h>

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

using namespace suturesim;
using namespace dealii;

namespace
{
  struct Pierced
  {
    Point<3> x;                ///< the tissue point, m
    double   force  = 0;       ///< |f⊥| of the tie, N
    double   gap    = 0;       ///< |P⊥ d|, m
    unsigned rounds = 0;       ///< solves
  };

  /// A needle and a tissue surface far from the thread (one triangle 1 m away), for the
  /// pierce points' thread terms alone.
  struct ThreadBench
  {
    tools::CurvedNeedle               needle{0.008, 0.75 * M_PI, 0.0005};
    Eigen::Matrix3Xd                  reference = (Eigen::Matrix3Xd(3, 3) << 1, 1.01, 1, 0, 0, 0.01, 0, 0, 0).finished();
    std::vector<mesh::Triangle>       triangles{{{0, 1, 2}}};

    /// A needle with the thread @p nodes (element lengths @p lengths; its rotations
    /// @p rotations, or nullptr for the polyline) and one pierce point anchored at
    /// thread coordinate @p anchor beyond the swage (m).
    coupling::TissueNeedle
    pierced(const coupling::TissueNeedleParameters &p, const std::vector<rod::Vec3> &nodes,
            std::vector<double> lengths, const std::vector<rod::Quat> *rotations, const double anchor) const
    {
      coupling::TissueNeedle tie(needle, p, triangles, reference);
      tie.begin_step(0, tools::Pose(), reference);
      tie.set_thread(&nodes, std::move(lengths), rotations);
      tie.add_pierce_point(Point<3>(), needle.length() + anchor);
      return tie;
    }
  };
} // namespace

TEST(PierceEnforcement, PenaltyConvergesToTheLagrangeSolutionAtFirstOrderInTheStiffness)
{
  test_support::BlockModel block(" set Element degree = 2\n"
                                 " subsection Material\n  set Model = neo-Hookean\n  set Bulk modulus = 1e6\n"
                                 "  subsection neo-Hookean\n   set Shear modulus = 2e5\n  end\n end\n"
                                 " subsection Boundary conditions\n  set Fixed = bottom\n end\n",
                                 Point<3>(0.02, 0.02, 0.01), {4, 4, 2});
  auto      &model   = *block.model;
  const auto surface = model.boundary_surface();

  // the needle (R = 8 mm, 3/8) in the plane y = const, its point at φ = 45° beside X;
  // its tip lies 1.7 mm outside the face x = 0, out of the puncture's reach
  const tools::CurvedNeedle needle(0.008, 0.75 * M_PI, 0.0005);
  const Point<3>            X(0.0095, 0.0093, 0.0051);
  const Eigen::Vector3d     radial(std::sqrt(0.5), 0, std::sqrt(0.5)), across(0, 1, 0);
  const double              delta = 2e-4, delta_across = 1e-4;
  tools::Pose               pose;
  pose.orientation      = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));
  pose.position         = Eigen::Vector3d(X[0], X[1], X[2]) + (delta - needle.radius()) * radial + delta_across * across;
  const double anchor   = needle.radius() * (needle.arc_angle() - M_PI / 4);
  const double distance = std::hypot(delta, delta_across);
  ASSERT_NEAR((needle.point(pose, anchor) - Eigen::Vector3d(X[0], X[1], X[2])).norm(), distance, 1e-12);

  const double tolerance = 1e-10; // m, the Lagrange gap
  const auto   solve     = [&](const double k, const bool lagrange) {
    coupling::TissueNeedleParameters p;
    p.puncture.threshold   = 1;
    p.friction             = {0, 500, 0.05}; // μ = 0: the force is the tie's alone
    p.transverse_stiffness = k;
    p.lagrange             = lagrange;
    coupling::TissueNeedle tie(needle, p, surface.triangles, surface.reference);
    tie.begin_step(1, pose, surface.reference);
    tie.add_pierce_point(X, anchor);
    model.set_point_loads(&tie);
    Pierced result;
    for (;;)
      {
        const auto report = model.solve_static(1);
        EXPECT_TRUE(report.converged) << report.failure;
        ++result.rounds;
        const std::vector<Point<3>> x{model.point_position(0)};
        if (!lagrange || tie.constraint_gap(x) <= tolerance || result.rounds == 200)
          {
            Tensor<1, 3> f;
            Tensor<2, 3> unused;
            tie.force(0, x[0], f, unused);
            result.x     = x[0];
            result.gap   = tie.constraint_gap(x);
            result.force = f.norm();
            break;
          }
        tie.update_multipliers(x);
      }
    model.set_point_loads(nullptr);
    return result;
  };

  // the constrained solution, by two rates of the Uzawa iteration: the same point
  const Pierced lagrange = solve(1e4, true), lagrange_fast = solve(1e5, true);
  std::printf("Lagrange: |f| = %.6e N, gap %.2e m in %u solves (k = 1e4 N/m); %.2e m in %u solves (k = 1e5 N/m)\n",
              lagrange.force, lagrange.gap, lagrange.rounds, lagrange_fast.gap, lagrange_fast.rounds);
  ASSERT_LE(lagrange.gap, tolerance);
  ASSERT_LE(lagrange_fast.gap, tolerance);
  EXPECT_LT(lagrange_fast.rounds, lagrange.rounds); // a stiffer tie, a faster iteration
  EXPECT_LT(lagrange.x.distance(lagrange_fast.x), 1e-8);
  EXPECT_NEAR(lagrange.force, lagrange_fast.force, 1e-4 * lagrange.force);
  EXPECT_GT(lagrange.force, 0.05); // the tissue is moved 0.22 mm: the tie carries load

  // the body's stiffness at the point, seen by the constraint: K = f_L / δ; a penalty
  // tie in series with it leaves the gap K δ / (K + k⊥)
  const double K = lagrange.force / distance;
  std::printf("point stiffness K = f_L / delta = %.1f N/m\n", K);
  std::printf("%12s %14s %14s %14s %14s %8s\n", "k [N/m]", "gap [m]", "K d/(K+k) [m]", "|x - x_L| [m]",
              "|f - f_L| [N]", "order");
  double last = 0;
  for (const double k : {1e3, 1e4, 1e5, 1e6})
    {
      const Pierced penalty = solve(k, false);
      EXPECT_EQ(penalty.rounds, 1u);
      const double difference = penalty.x.distance(lagrange.x);
      const double order      = last > 0 ? std::log10(last / difference) : 0;
      const double series     = K * distance / (K + k);
      std::printf("%12.0e %14.4e %14.4e %14.4e %14.4e %8.3f\n", k, penalty.gap, series, difference,
                  std::abs(penalty.force - lagrange.force), order);
      EXPECT_NEAR(penalty.gap, penalty.force / k, 1e-9 * penalty.gap); // the penalty's gap is f / k
      EXPECT_NEAR(penalty.gap, series, 0.02 * series) << "k = " << k;   // springs in series
      EXPECT_NEAR(difference, penalty.gap, 0.02 * penalty.gap) << "k = " << k;
      if (k == 1e6) // k⊥ far past K: first order, log10((k + K) / (k/10 + K)) → 1
        {
          EXPECT_NEAR(order, 1.0, 0.05);
        }
      last = difference;
    }
  EXPECT_LT(last, 1e-2 * distance); // k = 1e6 N/m: within 1 % of the offset
}

TEST(PierceEnforcement, ThreadTermsMatchFiniteDifferencesAsTheElementMovesAndTurns)
{
  // A pierce point on a suture element (a thread without rotations: its polyline), in
  // stick and in slip, k⊥ = k_t = 5e4 N/m; the element's nodes moved (a) both by the
  // same vector, which leaves its direction alone: the tie, the stick's −k_t t tᵀ and,
  // in slip, the normal force's (F/N) N' k⊥ t n̂ᵀ (N' of the smoothed normal force);
  // (b) each its own way, which turns it: the friction's turn with the element too,
  // σ_b/l (F' t d⊥ᵀ − F P), of the order of F/l. The Jacobian (itself a central
  // difference, tissue_needle.h) must match central differences of the residual taken
  // along these directions with another step (1e-9 m against 1e-8 m per coordinate):
  // what this checks is that the residual is smooth there and that every column lands
  // on its node's slot.
  const ThreadBench                bench;
  coupling::TissueNeedleParameters p;
  p.friction             = {0.2, 5e4, 0.05};
  p.transverse_stiffness = 5e4;
  p.normal_smoothing     = 1; // N: of the tie force's order here, so that N' ≠ 1 counts
  std::vector<rod::Vec3> nodes{{0, 0, 0}, {-0.001, 0.0002, 0}, {-0.002, 0.0003, 0.0001}};
  coupling::TissueNeedle tie = bench.pierced(p, nodes, {0.00102, 0.00101}, nullptr, 0.0004); // element 0, ξ ≈ 0.4

  const Eigen::Vector3d c = 0.6 * nodes[0] + 0.4 * nodes[1], t = (nodes[0] - nodes[1]).normalized();
  const Eigen::Vector3d across = t.cross(Eigen::Vector3d::UnitZ()).normalized();
  for (const bool turn : {false, true})
    for (const double along : {1e-7, 2e-4}) // stick: k_t Δ = 5 mN < μN; slip: 10 N > μN
      {
        const std::string case_name = std::string(along > 1e-6 ? "slip" : "stick") + (turn ? ", turned" : ", translated");
        const Eigen::Vector3d         xt = c + 5e-5 * across + 2e-5 * Eigen::Vector3d::UnitZ() - along * t;
        const std::vector<Point<3>>   x{Point<3>(xt[0], xt[1], xt[2])};
        Eigen::Matrix<double, 12, 1>  r0 = Eigen::Matrix<double, 12, 1>::Zero();
        Eigen::Matrix<double, 12, 12> J  = Eigen::Matrix<double, 12, 12>::Zero();
        tie.thread_terms(x, 0, r0, &J);
        const Eigen::Vector3d         move_a(0.3, -0.8, 0.5);
        const Eigen::Vector3d         move_b = turn ? Eigen::Vector3d(-0.6, 0.2, 0.9) : move_a;
        Eigen::Matrix<double, 12, 1>  v = Eigen::Matrix<double, 12, 1>::Zero();
        v.segment<3>(0)                   = move_a;
        v.segment<3>(6)                   = move_b;
        const double                  h = 1e-9;
        const auto residual = [&](const double s) {
          const auto saved = nodes;
          nodes[0] += s * move_a;
          nodes[1] += s * move_b;
          Eigen::Matrix<double, 12, 1>  r = Eigen::Matrix<double, 12, 1>::Zero();
          tie.thread_terms(x, 0, r, nullptr);
          nodes = saved;
          return r;
        };
        const Eigen::Matrix<double, 12, 1> fd = (residual(h) - residual(-h)) / (2 * h);
        const Eigen::Matrix<double, 12, 1> Jv = J * v;
        std::printf("%s: |J v| = %.4e, |J v - FD| = %.3e\n", case_name.c_str(), Jv.norm(), (Jv - fd).norm());
        EXPECT_GT(Jv.norm(), 1e3) << case_name; // the tie and the friction both load the nodes
        EXPECT_LT((Jv - fd).norm(), 1e-6 * Jv.norm()) << case_name;
      }
}

TEST(PierceEnforcement, ThreadPointIsTiedToACurveWhoseTangentIsContinuousAtTheNodes)
{
  // A thread bent by 40° at its middle node, the rod's tangent director there halfway
  // between its elements' chords, and a tissue point 50 µm inside the bend next to that
  // node: carried by either element (u just below 1 on the first, just above 0 on the
  // second) it must feel the same force, since both elements' Hermite curves meet at the
  // node with one tangent (tissue_needle.h). On the polyline (no rotations given) the two
  // carriers measure across different lines and disagree: the carrier's flip was a jump
  // in the force, and the reason for the curve. The thread's Jacobian, with the nodes'
  // rotations among its unknowns now, must match central differences of the residual
  // when nodes move and turn.
  const ThreadBench                bench;
  coupling::TissueNeedleParameters p;
  p.friction             = {0.2, 1.0, 0.05}; // a soft stick: the carriers' anchors differ by 2 µm
  p.transverse_stiffness = 5e4;
  const double             l = 0.001, bend = 40 * M_PI / 180;
  const Eigen::Vector3d    t0(-1, 0, 0), t1(-std::cos(bend), std::sin(bend), 0); // along +s
  std::vector<rod::Vec3>   nodes{{0, 0, 0}, l * t0, l * t0 + l * t1};
  const auto frame = [](const Eigen::Vector3d &d1) { // R e₁ = d1
    return rod::Quat::FromTwoVectors(Eigen::Vector3d::UnitX(), d1.normalized());
  };
  std::vector<rod::Quat> rotations{frame(t0), frame(t0 + t1), frame(t1)};
  const Eigen::Vector3d  inside = (t1 - t0).normalized(); // towards the bend's inside
  const Eigen::Vector3d  xt     = nodes[1] + 5e-5 * inside + 1e-6 * (t0 + t1).normalized();
  const std::vector<Point<3>> x{Point<3>(xt[0], xt[1], xt[2])};
  const auto force_on = [&](const double anchor, const bool curve) {
    coupling::TissueNeedle tie = bench.pierced(p, nodes, {l, l}, curve ? &rotations : nullptr, anchor);
    Tensor<1, 3> f;
    Tensor<2, 3> df_dx;
    tie.force(0, x[0], f, df_dx);
    return f;
  };
  for (const bool curve : {true, false})
    {
      const Tensor<1, 3> first = force_on(l - 1e-6, curve), second = force_on(l + 1e-6, curve);
      const double       jump  = (first - second).norm() / first.norm();
      std::printf("%s: |f| = %.4f N, jump between the carriers %.3e\n", curve ? "curve" : "polyline", first.norm(), jump);
      if (curve)
        EXPECT_LT(jump, 1e-3);
      else
        EXPECT_GT(jump, 0.1);
    }

  coupling::TissueNeedle tie = bench.pierced(p, nodes, {l, l}, &rotations, 0.6 * l); // element 0, inside the bend's reach
  const Eigen::Vector3d         xp = 0.4 * nodes[0] + 0.6 * nodes[1] + 3e-5 * inside;
  const std::vector<Point<3>>   y{Point<3>(xp[0], xp[1], xp[2])};
  Eigen::Matrix<double, 12, 1>  r0 = Eigen::Matrix<double, 12, 1>::Zero();
  Eigen::Matrix<double, 12, 12> J  = Eigen::Matrix<double, 12, 12>::Zero();
  tie.thread_terms(y, 0, r0, &J);
  Eigen::Matrix<double, 12, 1> v;
  v << 0.3, -0.8, 0.5, 200, -100, 300, -0.6, 0.2, 0.9, -150, 250, 100; // m, rad per unit
  const double h        = 1e-9;
  const auto   residual = [&](const double s) {
    const auto saved_x = nodes;
    const auto saved_q = rotations;
    for (unsigned a = 0; a < 2; ++a)
      {
        nodes[a] += s * v.segment<3>(6 * a);
        rotations[a] = rod::quaternion_exp(s * v.segment<3>(6 * a + 3)) * rotations[a];
      }
    Eigen::Matrix<double, 12, 1>  r = Eigen::Matrix<double, 12, 1>::Zero();
    tie.thread_terms(y, 0, r, nullptr);
    nodes     = saved_x;
    rotations = saved_q;
    return r;
  };
  const Eigen::Matrix<double, 12, 1> fd = (residual(h) - residual(-h)) / (2 * h);
  const Eigen::Matrix<double, 12, 1> Jv = J * v;
  // the rotations' own part: the same direction with the nodes held
  Eigen::Matrix<double, 12, 1> turn_only = v;
  turn_only.segment<3>(0).setZero();
  turn_only.segment<3>(6).setZero();
  std::printf("moved and turned: |J v| = %.4e, |J v - FD| = %.3e; |J v| of the turns alone %.4e\n", Jv.norm(),
              (Jv - fd).norm(), (J * turn_only).norm());
  EXPECT_GT((J * turn_only).norm(), 1e-2 * Jv.norm()); // the tangents shape the curve
  EXPECT_LT((Jv - fd).norm(), 1e-6 * Jv.norm());
}

TEST(PierceEnforcement, APointPastItsCarriersEndIsMeasuredAcrossTheThreadWhereItIs)
{
  // A thread of two 1 mm elements, the first straight, the second bent by 40° (the
  // rod's tangent director turns from the node between them to the end): their curves
  // share the node's position and tangent, not its curvature. A pierce point carried by
  // the first element whose tissue point lies 50 µm beside the second, just past the
  // node, sits in its carrier's dead zone (TissueNeedle::carried_to() moves a carrier
  // only a tenth of an element past its end). It must be measured across the second
  // element's curve, 50 µm away; the first element's curve continued past the node
  // leaves the thread at second order (that measure made the hole's normal force change
  // as the thread slid, and the suture's Newton solve cycle between stick and slip:
  // docs/tearing.md). Its force then loads the second element only, and its measure
  // runs on without a jump as the point passes the node.
  const ThreadBench                bench;
  coupling::TissueNeedleParameters p;
  p.transverse_stiffness = 5e4;
  const double           l = 0.001, bend = 40 * M_PI / 180, offset = 5e-5;
  const Eigen::Vector3d  t0(-1, 0, 0), t1(-std::cos(bend), std::sin(bend), 0); // along +s
  std::vector<rod::Vec3> nodes{{0, 0, 0}, l * t0, l * t0 + l * (t0 + t1).normalized()};
  const auto             frame = [](const Eigen::Vector3d &d1) { // R e₁ = d1
    return rod::Quat::FromTwoVectors(Eigen::Vector3d::UnitX(), d1.normalized());
  };
  std::vector<rod::Quat> rotations{frame(t0), frame(t0), frame(t1)};
  coupling::ThreadCurve  thread;
  thread.attach(&nodes, {l, l}, &rotations);
  // the tissue point beside the thread's curve at parameter u of element e, in its plane
  const auto beside = [&](const std::size_t e, const double u) {
    const coupling::HermiteSegment h = thread.segment(e);
    const Eigen::Vector3d          n = Eigen::Vector3d::UnitZ().cross(h.rate(u)).normalized();
    return Eigen::Vector3d(h.at(u) + offset * n);
  };
  coupling::TissueNeedle tie = bench.pierced(p, nodes, {l, l}, &rotations, 0.5 * l); // carried by element 0
  const auto             state = [&](const Eigen::Vector3d &x) {
    return tie.thread_point_states({Point<3>(x[0], x[1], x[2])}).front();
  };

  const Eigen::Vector3d x     = beside(1, 0.05);
  const auto            there = state(x);
  const coupling::HermiteSegment carrier = thread.segment(0);
  const double          continued = (x - carrier.at(carrier.closest(x, 1))).norm();
  std::printf("past the node: measured on element %zu at u = %.4f, %.6e m across (the carrier's curve continued: "
              "u = %.4f, %.6e m)\n",
              there.element, there.u, there.across, carrier.closest(x, 1), continued);
  EXPECT_EQ(there.element, 1u);
  EXPECT_NEAR(there.u, 0.05, 1e-6);
  EXPECT_NEAR(there.across, offset, 1e-9);
  EXPECT_GT(std::abs(continued - offset), 1e-7); // the old measure's error, 1e-6 m here
  EXPECT_EQ(tie.loaded_elements(), (std::vector<std::size_t>{0, 1}));
  const std::vector<Point<3>>  at{Point<3>(x[0], x[1], x[2])};
  Eigen::Matrix<double, 12, 1> on_carrier = Eigen::Matrix<double, 12, 1>::Zero(), on_next = on_carrier;
  tie.thread_terms(at, 0, on_carrier, nullptr);
  tie.thread_terms(at, 1, on_next, nullptr);
  EXPECT_EQ(on_carrier.norm(), 0.0);
  EXPECT_GT(on_next.norm(), 1.0); // the tie: k⊥ × 50 µm = 2.5 N

  // through the node: the thread coordinate and the distance across it without a jump
  double zeta = 0, across = 0, largest_step = 0, largest_change = 0;
  for (int k = -20; k <= 20; ++k)
    {
      const double s  = 1 + k * 0.005; // in element lengths
      const auto   st = state(s < 1 ? beside(0, s) : beside(1, s - 1));
      const double z  = st.slip + 0.5 * l; // ζ − ζ_a, the anchor 0.5 l on
      if (k > -20)
        {
          largest_step   = std::max(largest_step, std::abs(z - zeta) / (0.005 * l));
          largest_change = std::max(largest_change, std::abs(st.across - across));
        }
      zeta   = z;
      across = st.across;
    }
  std::printf("through the node: dζ/ds up to %.6f, the distance across changes by up to %.3e m a step\n",
              largest_step, largest_change);
  EXPECT_NEAR(largest_step, 1.0, 0.01); // ζ advances with the point, at the rate of arc length
  EXPECT_LT(largest_change, 1e-9);
}
