// Seed 003's stitch evaluation (tearing/stitch_evaluation.h) on punctures whose measures
// are known in closed form: a wound of two vertical faces 0.4 mm apart, stitches across it.
#include <suturesim/tearing/stitch_evaluation.h>

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

using namespace suturesim;
using coupling::PunctureEvent;
using Eigen::Vector3d;

namespace
{
  constexpr double R = 0.008, gap = 0.0004, top = 0.006;

  /// Two rectangular faces, x = 0 (lip A, x < 0) and x = gap (lip B), y in [-10, 10] mm,
  /// z in [0, top], each wound counter-clockwise seen from the gap (outward from its
  /// lip); and a skin triangle beside them that is not a face.
  tearing::Wound
  slit()
  {
    Eigen::Matrix3Xd X(3, 11);
    X << 0, 0, 0, 0, gap, gap, gap, gap, -0.02, -0.02, -0.001,              //
        -0.01, 0.01, 0.01, -0.01, -0.01, 0.01, 0.01, -0.01, -0.01, 0.01, 0, //
        0, 0, top, top, 0, 0, top, top, top, top, top;
    const std::vector<std::array<std::uint32_t, 3>> triangles{
        {{0, 1, 2}}, {{0, 2, 3}}, {{4, 6, 5}}, {{4, 7, 6}}, {{8, 9, 10}}};
    return tearing::Wound(X, triangles, {1, 1, 1, 1, 0});
  }

  PunctureEvent
  puncture(const bool exit, const double t, const Vector3d &X, const Vector3d &n, const Vector3d &direction)
  {
    PunctureEvent e;
    e.kind      = exit ? "puncture_exit" : "puncture_entry";
    e.time      = t;
    e.reference = X;
    e.normal    = n;
    e.direction = direction.normalized();
    return e;
  }

  /// A stitch across the slit in the plane y = @p y: in at @p d before lip A's face, out
  /// through A's face, in through B's and out @p d beyond it; the needle meets the skin at
  /// @p angle (rad) on entry and exit, and the faces square.
  std::vector<PunctureEvent>
  stitch(const double y, const double d, const double angle, const double t0)
  {
    const Vector3d up = Vector3d::UnitZ(), down_in(std::cos(angle), 0, -std::sin(angle));
    const Vector3d down_out(std::cos(angle), 0, std::sin(angle));
    return {puncture(false, t0, {-d, y, top}, up, down_in),
            puncture(true, t0 + 1, {0, y, top - 0.0017}, Vector3d::UnitX(), Vector3d::UnitX()),
            puncture(false, t0 + 2, {gap, y, top - 0.0017}, -Vector3d::UnitX(), Vector3d::UnitX()),
            puncture(true, t0 + 3, {gap + d, y, top}, up, down_out)};
  }
} // namespace

TEST(StitchEvaluation, OneStitchAcrossTheWoundHasItsClosedFormMeasures)
{
  const auto    wound = slit();
  const double  d = 0.005, angle = 1.2;
  auto          events = stitch(0, d, angle, 0);
  PunctureEvent touch; // not a puncture: ignored
  touch.kind = "touch_entry";
  events.insert(events.begin(), touch);
  const auto stitches = tearing::evaluate_stitches(events, wound, R, {});
  ASSERT_EQ(stitches.size(), 1u);
  const auto &s = stitches[0];
  ASSERT_TRUE(s.exit.has_value());
  EXPECT_EQ(s.between.size(), 2u); // out of A's face, into B's
  EXPECT_TRUE(s.crosses_wound());
  const double c = 2 * d + gap;
  EXPECT_NEAR(s.bite_width, c, 1e-15);
  EXPECT_NEAR(s.bite_depth, R - std::sqrt(R * R - c * c / 4), 1e-15);
  EXPECT_NEAR(s.entry_edge_distance, d, 1e-15);
  EXPECT_NEAR(s.exit_edge_distance, d, 1e-15);
  EXPECT_NEAR(s.entry_angle, angle, 1e-12);
  EXPECT_NEAR(s.exit_angle, angle, 1e-12);
  EXPECT_TRUE(std::isnan(s.spacing)); // alone
  // default limits: the bite depth (1.92 mm) from the edge, no neighbour to be near
  EXPECT_DOUBLE_EQ(s.edge_limit, s.bite_depth);
  EXPECT_DOUBLE_EQ(s.spacing_limit, 2 * s.bite_depth);
  EXPECT_FALSE(s.too_close_to_edge);
  EXPECT_FALSE(s.too_close_to_neighbour);

  // a limit beyond the exit's distance flags it; one just inside does not
  tearing::StitchLimits limits;
  limits.edge_distance = d * (1 + 1e-9);
  EXPECT_TRUE(tearing::evaluate_stitches(events, wound, R, limits)[0].too_close_to_edge);
  limits.edge_distance = d * (1 - 1e-9);
  EXPECT_FALSE(tearing::evaluate_stitches(events, wound, R, limits)[0].too_close_to_edge);
}

TEST(StitchEvaluation, ABiteNearTheEdgeAndNeighboursNearEachOtherAreFlagged)
{
  const auto wound = slit();
  // three stitches along the wound at y = 0, 3 and 9 mm; the middle one with a 1 mm bite
  std::vector<PunctureEvent> events;
  for (const auto &[y, d] : {std::pair{0.0, 0.005}, std::pair{0.003, 0.001}, std::pair{0.009, 0.005}})
    {
      const auto one = stitch(y, d, M_PI / 2, 10 * events.size());
      events.insert(events.end(), one.begin(), one.end());
    }
  tearing::StitchLimits limits;
  limits.edge_distance = 0.002;
  limits.spacing       = 0.004;
  const auto s         = tearing::evaluate_stitches(events, wound, R, limits);
  ASSERT_EQ(s.size(), 3u);
  // the chords' midpoints lie over the wound's middle, whatever the bite: y apart
  EXPECT_NEAR(s[0].spacing, 0.003, 1e-15);
  EXPECT_NEAR(s[1].spacing, 0.003, 1e-15);
  EXPECT_NEAR(s[2].spacing, 0.006, 1e-15);
  EXPECT_NEAR(s[1].entry_edge_distance, 0.001, 1e-15);
  EXPECT_EQ(std::vector<bool>({s[0].too_close_to_edge, s[1].too_close_to_edge, s[2].too_close_to_edge}),
            std::vector<bool>({false, true, false}));
  EXPECT_EQ(std::vector<bool>({s[0].too_close_to_neighbour, s[1].too_close_to_neighbour, s[2].too_close_to_neighbour}),
            std::vector<bool>({true, true, false}));
  const auto json = tearing::stitches_json(s);
  EXPECT_EQ(json.at("count"), 3);
  EXPECT_EQ(json.at("too_close_to_edge"), 1);
  EXPECT_EQ(json.at("too_close_to_neighbour"), 2);
  EXPECT_EQ(json.at("stitches")[1].at("punctures"), 4);
  // the CSV: a header and a row per stitch, flags as 0/1 in the last two columns
  std::istringstream       csv(tearing::stitches_csv(s));
  std::string              line;
  std::vector<std::string> rows;
  while (std::getline(csv, line))
    rows.push_back(line);
  ASSERT_EQ(rows.size(), 4u);
  EXPECT_EQ(rows[2].substr(rows[2].size() - 4), ",1,1");
  EXPECT_EQ(rows[3].substr(rows[3].size() - 4), ",0,0");
}

TEST(StitchEvaluation, WithoutAWoundOrAnExitTheMeasuresThatNeedThemAreNull)
{
  // a pass into one body (no wound faces): entry and exit are one stitch, no distances
  const tearing::Wound       none;
  const Vector3d             up = Vector3d::UnitZ();
  std::vector<PunctureEvent> events{puncture(false, 0, {0, 0, top}, up, -up),
                                    puncture(true, 1, {0.006, 0, top}, up, up),
                                    puncture(false, 2, {0.02, 0, top}, up, {1, 0, -1})};
  tearing::StitchLimits      limits;
  limits.edge_distance = 1; // would flag anything with a distance
  const auto s         = tearing::evaluate_stitches(events, none, R, limits);
  ASSERT_EQ(s.size(), 2u);
  EXPECT_FALSE(s[0].crosses_wound());
  EXPECT_NEAR(s[0].entry_angle, M_PI / 2, 1e-12);
  EXPECT_TRUE(std::isnan(s[0].entry_edge_distance));
  EXPECT_FALSE(s[0].too_close_to_edge);
  // the second pass has not come out: no exit, no chord, no depth
  EXPECT_FALSE(s[1].exit.has_value());
  EXPECT_NEAR(s[1].entry_angle, M_PI / 4, 1e-12);
  EXPECT_TRUE(std::isnan(s[1].bite_depth));
  const auto json = tearing::stitches_json(s);
  EXPECT_TRUE(json.at("stitches")[1].at("exit").is_null());
  EXPECT_TRUE(json.at("stitches")[1].at("bite_depth").is_null());
  EXPECT_TRUE(json.at("stitches")[0].at("entry_edge_distance").is_null());
  // a chord longer than the needle's diameter has no arc of radius R
  events[1].reference = {2.5 * R, 0, top};
  EXPECT_TRUE(std::isnan(tearing::evaluate_stitches(events, none, R, {})[0].bite_depth));
}

TEST(StitchEvaluation, TheWoundHidesTheOtherLipFromAPointOnAFaceAndNotItsOwn)
{
  // Wound::hides, the visibility criterion of a spread pierce point (Pierce points/Load
  // across the wound = false): from a point on lip A's face, the other lip's face is out
  // of sight across the gap though the segment crosses no face strictly between its ends
  // (separates() says no: each end is on its own lip's side); lip A's face and interior
  // are in sight, lip B's interior is behind B's face.
  const tearing::Wound w = slit();
  const double         z = top - 0.0017;
  const Vector3d       a(0, 0, z);
  const Vector3d       on_b(gap, 0.001, z - 0.0005), on_a(0, 0.001, z - 0.001), in_a(-0.001, 0.0005, z),
    in_b(gap + 0.001, 0, z), above_a(-0.001, 0, top);
  EXPECT_FALSE(w.separates(a, on_b));
  for (const auto &[b, hidden] : {std::pair{on_b, true}, std::pair{on_a, false}, std::pair{in_a, false},
                                  std::pair{in_b, true}, std::pair{above_a, false}})
    {
      EXPECT_EQ(w.hides(a, b), hidden) << b.transpose();
      EXPECT_EQ(w.hides(b, a), hidden) << b.transpose(); // a symmetric relation
    }
  // from inside lip A: its own face in sight, the other lip's face behind A's face
  EXPECT_FALSE(w.hides(in_a, on_a));
  EXPECT_TRUE(w.hides(in_a, on_b));
  // the faces' common plane with the skin triangle beside them: a point on the skin
  // (no face) sees lip A's face
  EXPECT_FALSE(w.hides(above_a, on_a));
  EXPECT_FALSE(tearing::Wound().hides(a, on_b));
}
