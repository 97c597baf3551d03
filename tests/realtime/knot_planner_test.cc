// Seed 002's knot planner (knot/planner.h) on ropes laid out by hand: the codes its plans
// tie, an instruction done, and every way a plan fails, each with its reason.
#include <suturesim/knot/curves.h>
#include <suturesim/knot/planner.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

using namespace suturesim::knot;
using Eigen::Vector3d;

namespace
{
  /// A rope 1 mm a link (coordinates in mm): along x from the origin to 20, round a half
  /// circle of radius 5 and back along y = 10 to x = 10, then @p down links down towards
  /// the first part at height @p z, which it crosses from 11 links on (at x = 10); the
  /// last link is @p last long.
  Eigen::Matrix3Xd
  rope(const int down, const double z, const double last = 1)
  {
    std::vector<Vector3d> p;
    for (int i = 0; i <= 20; ++i)
      p.emplace_back(i, 0, 0);
    for (int k = 1; k <= 15; ++k)
      p.emplace_back(20 + 5 * std::sin(M_PI * k / 15), 5 - 5 * std::cos(M_PI * k / 15), 0);
    for (int x = 19; x >= 10; --x)
      p.emplace_back(x, 10, 0);
    for (int k = 1; k <= down; ++k)
      p.emplace_back(10, 10 - k - (k == down ? last - 1 : 0), z);
    Eigen::Matrix3Xd m(3, static_cast<Eigen::Index>(p.size()));
    for (std::size_t k = 0; k < p.size(); ++k)
      m.col(static_cast<Eigen::Index>(k)) = 1e-3 * p[k];
    return m;
  }

  PlannerSettings
  overhand()
  {
    PlannerSettings s;
    s.knot             = "overhand";
    s.clearance        = 2e-3;
    s.instruction_time = 1;
    return s;
  }
} // namespace

TEST(KnotPlanner, PlansTieTheTrefoilAndTheFigureEight)
{
  EXPECT_EQ(tied_code(instructions("overhand")).text(), "O1 U2 O3 U1 O2 U3");
  // minimal plans, one instruction a crossing: the planner takes their length as the
  // knot's crossing number when it checks a pulled knot
  EXPECT_EQ(tied_code(instructions("overhand")).crossings(), instructions("overhand").size());
  EXPECT_EQ(tied_code(instructions("figure-eight")).crossings(), instructions("figure-eight").size());
  EXPECT_EQ(tied_code(instructions("figure-eight")).text(), "O1 U2 O3 U4 O2 U1 O4 U3");
  // the overhand's end taken round once more ties the (2, 5) torus knot: the code the
  // cinquefoil of knot/curves.h reads cut open and seen along z, alternating, five
  // crossings, determinant 5
  const GaussCode cinquefoil = tied_code(instructions("cinquefoil"));
  EXPECT_EQ(cinquefoil.text(), "O1 U2 O3 U4 O5 U1 O2 U3 O4 U5");
  EXPECT_EQ(cinquefoil.crossings(), instructions("cinquefoil").size());
  EXPECT_EQ(cinquefoil.determinant(), 5);
  Eigen::Matrix3Xd laid(3, 801);
  for (int k = 0; k <= 800; ++k)
    laid.col(k) = suturesim::knot::cinquefoil(0.05 + (2 * M_PI - 1e-3) * k / 800);
  const GaussCode seen = KnotDiagram(laid, Projection(Vector3d::UnitZ())).gauss_code();
  EXPECT_TRUE(seen.is_cut_of(cinquefoil) || seen.mirrored().is_cut_of(cinquefoil)) << seen.text();
  // the square and granny knots: two half knots, each a trefoil read closed through the
  // tails, the first by the last end (instructions 1-3), the second by the first end;
  // six crossings, the least of the sum of two trefoils, determinant 3 × 3. The
  // crossings labelled past @p first lie together along the rope in a code of a sum (one
  // knot's code set into the other's): the entries they span, first to last
  const auto block_of_sum = [](const GaussCode &code, const unsigned first) {
    std::size_t from = code.entries().size(), to = 0;
    for (std::size_t p = 0; p < code.entries().size(); ++p)
      if (code.entries()[p].label > first)
        from = std::min(from, p), to = std::max(to, p);
    return to - from;
  };
  for (const std::string knot : {"square", "granny"})
    {
      const auto      plan = instructions(knot);
      const GaussCode code = tied_code(plan);
      EXPECT_EQ(code.crossings(), plan.size()) << knot;
      EXPECT_EQ(code.reduced(), code) << knot;
      EXPECT_EQ(code.determinant(), 9) << knot;
      const GaussCode half = tied_code({plan.begin(), plan.begin() + 3});
      EXPECT_EQ(half.determinant(), 3) << knot;
      EXPECT_EQ(half.reduced().crossings(), 3u) << knot;
      // the second half knot's crossings (4-6 as tied) lie together along the rope
      EXPECT_EQ(block_of_sum(code, 3), 5u) << knot << ": " << code.text();
      for (std::size_t i = 3; i < plan.size(); ++i)
        EXPECT_TRUE(plan[i].first_end) << knot;
    }
  EXPECT_EQ(tied_code(instructions("square")).text(), "O1 U2 O3 U1 U4 O5 U6 O4 U5 O6 O2 U3");
  // the codes do not tell the square knot from the granny: which way a half knot turns
  // is in the crossings' signs, which the rope's diagram has (GaussCode::writhe())
  EXPECT_EQ(tied_code(instructions("granny")).text(), "U1 O2 U3 O1 U4 O5 U6 O4 U5 O6 U2 O3");
  // the surgeon's knot: the first half knot doubled (five crossings by the last end,
  // read closed the (2, 5) torus knot, determinant 5, as the cinquefoil), the second as
  // the square knot's; eight crossings, the least of 5_1 # 3_1, determinant 5 × 3, the
  // five crossings labelled 4-8 together along the rope (the code of a sum)
  {
    const auto      plan = instructions("surgeon");
    const GaussCode code = tied_code(plan);
    EXPECT_EQ(code.crossings(), 8u);
    EXPECT_EQ(code.reduced(), code);
    EXPECT_EQ(code.determinant(), 15);
    const GaussCode doubled = tied_code({plan.begin(), plan.begin() + 5});
    EXPECT_EQ(doubled.reduced().crossings(), 5u);
    EXPECT_EQ(doubled.determinant(), 5);
    EXPECT_EQ(block_of_sum(code, 3), 9u) << code.text();
    EXPECT_EQ(code.text(), "O1 U2 O3 U1 U4 O5 U6 O7 U8 O4 U5 O6 U7 O8 O2 U3");
  }
  EXPECT_THROW(instructions("bowline"), std::invalid_argument);
  EXPECT_THROW(tied_code({{true, 3}}), std::invalid_argument);
}

TEST(KnotPlanner, AnyPlanGivenToTheOtherEndTiesItsCodeReadFromThatEnd)
{
  // the spans of a first-end instruction are counted from the last end: the plan with
  // every instruction given to the other end ties the same rope read backwards
  for (const auto &knot : planned_knots())
    {
      auto other = instructions(knot);
      for (auto &step : other)
        step.first_end = !step.first_end;
      auto backwards = tied_code(instructions(knot)).entries();
      std::reverse(backwards.begin(), backwards.end());
      EXPECT_EQ(tied_code(other), GaussCode(backwards)) << knot;
    }
}

TEST(KnotPlan, TextReadsBackEveryNamedPlanAndACustomPlanDrivesThePlanner)
{
  for (const auto &knot : planned_knots())
    {
      const auto plan = instructions(knot);
      const auto read = parse_plan(plan_text(plan));
      ASSERT_EQ(read.size(), plan.size()) << knot;
      for (std::size_t k = 0; k < plan.size(); ++k)
        {
          EXPECT_EQ(read[k].over, plan[k].over) << knot << ' ' << k;
          EXPECT_EQ(read[k].span, plan[k].span) << knot << ' ' << k;
          EXPECT_EQ(read[k].first_end, plan[k].first_end) << knot << ' ' << k;
          EXPECT_DOUBLE_EQ(read[k].at, plan[k].at) << knot << ' ' << k;
          EXPECT_DOUBLE_EQ(read[k].draw, plan[k].draw) << knot << ' ' << k;
        }
    }
  // metrics.knot.plan records a plan as given: fractions and draws to 15 digits
  const auto fine = parse_plan(plan_text(parse_plan("under 0 at 0.123456789012; over 1 draw 0.0123456789; under 2")));
  EXPECT_DOUBLE_EQ(fine[0].at, 0.123456789012);
  EXPECT_DOUBLE_EQ(fine[1].draw, 0.0123456789);
  // the defaults: the last end, the middle of the span, no draw; spaces and a final ';'
  const auto overhand_text = parse_plan(" under 0 ;over 1;  last under 2 at 0.5 draw 0 ;");
  EXPECT_EQ(tied_code(overhand_text), tied_code(instructions("overhand")));
  EXPECT_FALSE(overhand_text[0].first_end);
  EXPECT_DOUBLE_EQ(overhand_text[0].at, 0.5);
  EXPECT_DOUBLE_EQ(overhand_text[0].draw, 0);
  // the overhand tied by the first end instead
  const auto first = parse_plan("first under 0 at 0.25 draw 0.01; first over 1; first under 2");
  EXPECT_TRUE(first[0].first_end);
  EXPECT_TRUE(first[2].first_end);
  EXPECT_DOUBLE_EQ(first[0].at, 0.25);
  EXPECT_DOUBLE_EQ(first[0].draw, 0.01);
  EXPECT_EQ(tied_code(first).reduced().crossings(), 3U);
  // a custom plan is the planner's plan: the first step goes down for "under 0"
  PlannerSettings s = overhand();
  s.knot            = "custom";
  s.instructions    = parse_plan("under 0; over 1; under 2");
  KnotPlanner     planner(s);
  const auto      start = rope(5, 0);
  EXPECT_LT(planner.move(start, 1e-3, 1e-3, 0).last.z(), start(2, start.cols() - 1));
  s.instructions.clear();
  EXPECT_THROW(KnotPlanner{s}, std::invalid_argument) << "a custom knot without instructions";
}

TEST(KnotPlan, RefusesATextItCannotTieAndSaysWhy)
{
  const auto refusal = [](const std::string &text) {
    try
      {
        parse_plan(text);
      }
    catch (const std::invalid_argument &e)
      {
        return std::string(e.what());
      }
    return std::string("accepted");
  };
  const std::vector<std::pair<std::string, std::string>> cases{
    {"", "no instruction"},
    {" ; ;", "no instruction"},
    {"sideways 0", "instruction 1 ('sideways 0'): expected 'over' or 'under', not 'sideways'"},
    {"first", "expected 'over' or 'under', not ''"},
    {"under", "the span must be a whole number"},
    {"under -1", "the span must be a whole number 0-999, not '-1'"},
    {"under 1e3", "the span must be a whole number"},
    {"under 0; over 3", "instruction 2 (' over 3'): span 3 is past the rope's spans then (0 to 2)"},
    {"under 0 at 1.5; over 1; under 2", "'at' must be within [0, 1]"},
    {"under 0 at nan; over 1; under 2", "expected 'at <fraction>' or 'draw <metres>'"},
    {"under 0 draw -0.01; over 1; under 2", "'draw' must be within [0, 1] m"},
    {"under 0 pull 2; over 1; under 2", "expected 'at <fraction>' or 'draw <metres>'"},
    {"under 0", "reduce to 0 of its 1 crossings"},
    {"under 0; under 1", "reduce to 0 of its 2 crossings"}};
  for (const auto &[text, why] : cases)
    EXPECT_NE(refusal(text).find(why), std::string::npos) << "'" << text << "': " << refusal(text);
  std::string many;
  for (int k = 0; k < 33; ++k)
    many += "under 0;";
  EXPECT_NE(refusal(many).find("more than 32 instructions"), std::string::npos) << refusal(many);
}

TEST(KnotPlanner, MovesTheEndDownAndOnForAnUnderCrossingAndCountsItDone)
{
  KnotPlanner     planner(overhand());
  const auto      start = rope(5, 0);
  const Vector3d  from  = start.col(start.cols() - 1);
  const Vector3d  to    = planner.move(start, 1e-3, 1e-3, 0).last;
  EXPECT_EQ(planner.phase(), KnotPlanner::Phase::tying);
  EXPECT_NEAR((to - from).norm(), 0.02 * 1e-3, 1e-12) << "one step at the planner's speed";
  EXPECT_LT(to.z(), from.z()) << "instruction 1 passes under: the end goes down";
  // the end has come down across the first part below it: instruction 1 done
  planner.move(rope(13, -1), 2e-3, 1e-3, 0);
  EXPECT_EQ(planner.instructions_done(), 1u);
  ASSERT_EQ(planner.events().size(), 1u);
  EXPECT_EQ(planner.events()[0].code, "O1 U1");
  EXPECT_TRUE(planner.failure().empty());
}

TEST(KnotPlanner, MovesOneEndAndHoldsTheOther)
{
  // the square knot's plan moves the last end first, the first end later: the first
  // end is held where it lies until then
  PlannerSettings s = overhand();
  s.knot            = "square";
  KnotPlanner     planner(s);
  EXPECT_TRUE(planner.moves_first_end());
  EXPECT_FALSE(KnotPlanner(overhand()).moves_first_end());
  const auto  start = rope(5, 0);
  const Ends  to    = planner.move(start, 1e-3, 1e-3, 0);
  EXPECT_FALSE(planner.moving_first_end());
  EXPECT_EQ(to.first, Vector3d(start.col(0)));
  EXPECT_NEAR((to.last - start.col(start.cols() - 1)).norm(), 0.02 * 1e-3, 1e-12);
}

TEST(KnotPlanner, TheFirstEndsOwnInertiaWeightSteersOnlyTheFirstEnd)
{
  // PlannerSettings::first_end_inertia replaces W while the first end moves (a needle
  // held by its driver), and leaves the last end's W alone: the first end's step with
  // its own W = 0 is the step with W = 0, not the step with W = 2
  const auto start = rope(5, 0);
  const auto step  = [&](const std::string &plan, const double W, const double first_W) {
    PlannerSettings s   = overhand();
    s.knot              = "custom";
    s.instructions      = parse_plan(plan);
    s.inertia           = W;
    s.first_end_inertia = first_W;
    KnotPlanner planner(s);
    const Ends  to = planner.move(start, 1e-3, 1e-3, 0);
    return std::pair<Vector3d, Vector3d>(to.first - start.col(0), to.last - start.col(start.cols() - 1));
  };
  const std::string first_end = "first under 0; first over 1; first under 2";
  const auto        own       = step(first_end, 2, 0);
  EXPECT_LT((own.first - step(first_end, 0, -1).first).norm(), 1e-15);
  EXPECT_GT((own.first - step(first_end, 2, -1).first).norm(), 1e-6) << "W = 2 steers the first end otherwise";
  EXPECT_NEAR(own.first.norm(), 0.02 * 1e-3, 1e-12);
  const std::string last_end = "under 0; over 1; under 2";
  EXPECT_LT((step(last_end, 2, 0).second - step(last_end, 2, -1).second).norm(), 1e-15);
}

TEST(KnotPlanner, FailsOnACrossingTheWrongWay)
{
  KnotPlanner planner(overhand());
  planner.move(rope(5, 0), 1e-3, 1e-3, 0);
  planner.move(rope(13, 1), 2e-3, 1e-3, 0); // over, where the plan says under
  EXPECT_EQ(planner.phase(), KnotPlanner::Phase::failed);
  EXPECT_NE(planner.failure().find("the end crossed over"), std::string::npos) << planner.failure();
  EXPECT_DOUBLE_EQ(planner.failure_time(), 2e-3);
  // a failed plan holds the end where it was
  const Vector3d held = planner.move(rope(13, 1), 3e-3, 1e-3, 0).last;
  EXPECT_EQ(held, planner.move(rope(13, 1), 4e-3, 1e-3, 0).last);
}

TEST(KnotPlanner, FailsWhenAnInstructionTakesTooLongOrTheRopeDoesNotFollow)
{
  KnotPlanner slow(overhand());
  for (double t = 1e-3; t < 1.5; t += 0.1)
    slow.move(rope(5, 0), t, 1e-3, 0);
  EXPECT_EQ(slow.phase(), KnotPlanner::Phase::failed);
  EXPECT_NE(slow.failure().find("was not done within"), std::string::npos) << slow.failure();

  KnotPlanner held(overhand());
  held.move(rope(5, 0), 1e-3, 1e-3, 0);
  held.move(rope(5, 0, 1.2), 2e-3, 1e-3, 0); // the end's link 1.2 mm
  EXPECT_EQ(held.phase(), KnotPlanner::Phase::failed);
  EXPECT_NE(held.failure().find("stretched by 20"), std::string::npos) << held.failure();
}

TEST(KnotPlanner, WaitsForItsStartTime)
{
  PlannerSettings s = overhand();
  s.start_time      = 0.5;
  KnotPlanner     planner(s);
  const auto      r = rope(5, 0);
  EXPECT_EQ(planner.move(r, 0.1, 1e-3, 0).last, Vector3d(r.col(r.cols() - 1)));
  EXPECT_EQ(planner.phase(), KnotPlanner::Phase::waiting);
}

TEST(KnotPlanner, TakesItsPlaneBeforeItStartsAndKeepsItAfter)
{
  // a plane read from the scene at the start (a stitch's pierce points): set while the
  // planner waits, unit, recorded in its settings; refused once the plan has started,
  // when the diagram's spans already lie in the old plane, and refused zero
  PlannerSettings s = overhand();
  s.start_time      = 0.5;
  KnotPlanner planner(s);
  const auto  r = rope(5, 0);
  planner.move(r, 0.1, 1e-3, 0);
  planner.set_normal(Vector3d(0, 2, 0));
  EXPECT_EQ(planner.projection().n, Vector3d(0, 1, 0));
  EXPECT_EQ(planner.settings().normal, Vector3d(0, 1, 0));
  EXPECT_THROW(planner.set_normal(Vector3d::Zero()), std::invalid_argument);
  EXPECT_EQ(planner.projection().n, Vector3d(0, 1, 0)) << "a refused normal leaves the plane as it was";
  planner.set_normal(Vector3d(0, 0, 1));
  planner.move(r, 0.5, 1e-3, 0);
  ASSERT_EQ(planner.phase(), KnotPlanner::Phase::tying);
  EXPECT_THROW(planner.set_normal(Vector3d(0, 1, 0)), std::logic_error);
  EXPECT_EQ(planner.projection().n, Vector3d(0, 0, 1));
}

namespace
{
  /// The mirror image of knot::trefoil() (z → −z: its code from +z, cut at t = 0.1, is
  /// the overhand plan's), scaled by 5 mm and laid as a rope of @p nodes nodes 1 mm apart
  /// along its arc from t = 0.1.
  Eigen::Matrix3Xd
  trefoil_rope(const Eigen::Index nodes)
  {
    const auto at = [](const double t) -> Vector3d { return 5e-3 * trefoil(t).cwiseProduct(Vector3d(1, 1, -1)); };
    Eigen::Matrix3Xd m(3, nodes);
    double           t    = 0.1;
    Vector3d         last = at(t);
    m.col(0)              = last;
    for (Eigen::Index k = 1; k < nodes; ++k)
      {
        // march along the curve in fine steps until 1 mm from the last node
        while ((at(t) - last).norm() < 1e-3)
          t += 1e-5;
        last     = at(t);
        m.col(k) = last;
      }
    return m;
  }
} // namespace

TEST(KnotPlanner, CountsATrefoilTracedByItsEndAndFailsOnlyWhenItComesUndoneWhileTightening)
{
  // the rope grows along the trefoil, its end tracing the curve: its crossings come one at
  // a time, the way and in the spans the overhand's instructions ask for
  PlannerSettings s  = overhand();
  s.instruction_time = 100;
  s.tighten_distance = 1; // tightening until the knot comes undone
  KnotPlanner planner(s);
  const auto  full = trefoil_rope(200);
  Eigen::Index n   = 10;
  double       t   = 0;
  for (; n <= full.cols() && planner.phase() != KnotPlanner::Phase::tightening; ++n)
    planner.move(full.leftCols(n), t += 1e-3, 1e-3, 0);
  ASSERT_EQ(planner.phase(), KnotPlanner::Phase::tightening) << planner.failure();
  --n; // the rope that made the last crossing
  ASSERT_EQ(planner.events().size(), 3u);
  EXPECT_EQ(planner.events()[2].code, "O1 U2 O3 U1 O2 U3");
  // pulled on while the rope keeps the knot: still tightening
  planner.move(full.leftCols(n), t += 1e-3, 1e-3, 0);
  EXPECT_EQ(planner.phase(), KnotPlanner::Phase::tightening);
  EXPECT_GT(planner.shortening(), 0);
  // the knot turned over (half a turn about x: seen from its other side, over and under
  // swapped) is the same knot with its three crossings, though its code is no longer
  // the plan's: still tightening
  Eigen::Matrix3Xd turned = full.leftCols(n);
  turned.row(1) *= -1;
  turned.row(2) *= -1;
  EXPECT_EQ(KnotDiagram(turned, Projection(Vector3d::UnitZ())).gauss_code().text(), "U1 O2 U3 O1 U2 O3");
  planner.move(turned, t += 1e-3, 1e-3, 0);
  EXPECT_EQ(planner.phase(), KnotPlanner::Phase::tightening) << planner.failure();
  // the same rope rising along its length (every strand over the ones before it, an
  // ascending diagram: U1 U2 U3 O1 O2 O3, which the Reidemeister moves undo) reads no
  // knot: it came undone, as an FTL knot pulled tight does, its strands passing through
  // each other
  Eigen::Matrix3Xd undone = full.leftCols(n);
  for (Eigen::Index k = 0; k < n; ++k)
    undone(2, k) = 1e-5 * static_cast<double>(k);
  planner.move(undone, t += 1e-3, 1e-3, 0);
  EXPECT_EQ(planner.phase(), KnotPlanner::Phase::failed);
  EXPECT_NE(planner.failure().find("came undone while tightening"), std::string::npos) << planner.failure();
  EXPECT_NE(planner.failure().find("fewer crossings than the knot's 3"), std::string::npos) << planner.failure();
}
