#pragma once
/**
 * @file
 * The standard surgical pass of a curved needle (the surgeon "follows the curve"): the
 * needle turns about its own arc centre C, which stays still, so that the tip runs
 * along the needle's circle into the tissue and out again and the hole is no larger than
 * the wire.
 *
 * Geometry, locally flat surface with outward normal n through the entry point E and a
 * bite direction b (in the surface, towards the exit): the arc's plane is spanned by b
 * and n. With the centre at height h above the surface, the circle of radius R meets the
 * surface at the entry angle α, cos α = h / R, reaches the bite depth δ = R − h below
 * it, and comes out at the exit X = E + 2 R sin α b (chord 2 R sin α). Given δ,
 * α = arccos(1 − δ/R); given α, δ = R (1 − cos α): with R fixed by the needle the two
 * are one choice. C = E + R sin α b + h n.
 *
 * The tip enters when it has turned to E and exits after a further turn of 2α; the
 * swage (Φ behind the tip) leaves the tissue after 2α + Φ. The planned motion starts
 * with the tip an approach distance (arc length) before E, turns at a constant angular
 * speed until the swage is out by the same distance, then translates the needle by a
 * pull vector over a pull duration (drawing the suture through).
 */

#include <suturesim/tools/curved_needle.h>

#include <vector>

namespace suturesim::tools
{
  struct PassParameters
  {
    Vector3d entry          = Vector3d::Zero(); ///< E, m
    Vector3d normal         = Vector3d::UnitZ(); ///< outward surface normal at E
    Vector3d bite_direction = Vector3d::UnitX(); ///< towards the exit (made ⟂ n)
    double   bite_depth     = 0;    ///< δ, m; 0: from the entry angle
    double   entry_angle    = M_PI / 2; ///< α, rad (used when bite_depth = 0)
    /// b, m; > 0: the pass straddles `crossing` symmetrically, entering b before it along
    /// the bite direction and leaving b beyond it, so sin α = b/R (entry, bite_depth and
    /// entry_angle are then not used). A bite × spacing study varies this one number.
    double   bite           = 0;
    Vector3d crossing       = Vector3d::Zero(); ///< where the stitch crosses the wound (with bite > 0), m
    double   start_time     = 0;    ///< s
    double   angular_speed  = 1;    ///< rad/s
    double   approach       = 1e-3; ///< arc length of the tip before E at the start, m
    Vector3d pull           = Vector3d::Zero(); ///< translation after the pass, m
    double   pull_duration  = 1;    ///< s
    /// a second translation after the pull (drawing the suture tight), m; zero: none
    Vector3d tighten        = Vector3d::Zero();
    double   tighten_duration = 1; ///< s
    /// The needle driver's regrasp (seed 001 §5–6): once the tip is out of the exit by
    /// this arc length (m; 0: none) the jaws let go, move along the needle to the middle
    /// of its exposed part and take it there; the turn then goes on. The driver first
    /// holds it at `grip` (fraction of the arc from the swage), which must then be out of
    /// the tissue. The driver's way along the needle is not a body: nothing touches it.
    double   regrasp_exposure = 0;
    double   regrasp_duration = 0.5; ///< s, from letting go to taking again
    double   grip             = 1.0 / 3; ///< 1
  };

  struct SurgicalPass
  {
    /// pose of the needle's body frame (origin at C) while the driver holds it as at
    /// the start; after a regrasp, the driver's, whose frame is the needle's turned
    /// about the arc's axis by the angle its jaws moved along the arc
    Trajectory trajectory;
    /// when the driver's jaws open (true) and close (false), in time order (s)
    std::vector<std::pair<double, bool>> jaws;
    Vector3d   centre, entry, exit;
    double     entry_angle = 0, bite_depth = 0, bite_width = 0;
    /// β, rad: how far the regrasp moved the jaws along the arc (as a turn about its
    /// axis, towards the tip); 0 without a regrasp
    double     regrasp_turn = 0;
    /// times at which the tip reaches E, the tip reaches X, the swage leaves at X, the
    /// turn ends, the pull ends, the tightening ends (= t_end without one) (s)
    double t_tip_entry = 0, t_tip_exit = 0, t_swage_exit = 0, t_turn_end = 0, t_end = 0, t_tightened = 0;
  };

  /// Plans the pass; throws std::invalid_argument for inconsistent input (a bite deeper
  /// than R, a bite direction along the normal, a needle too short to leave the
  /// tissue, a regrasp the exposed tip cannot give, ...). A regrasp holds the turn for
  /// its duration: every time after it is later by that much.
  SurgicalPass
  plan_pass(const CurvedNeedle &needle, const PassParameters &parameters);

  /// A series of @p stitches passes along a wound, pass k entering at E_k = E_0 + k s (s,
  /// the spacing, in the surface; with a bite, its wound crossing moves by k s likewise):
  /// a running (continuous) suture, or with @p interrupted an interrupted series, each
  /// pass drawn tight by its own tightening and tied off before the next.
  struct SeriesParameters
  {
    unsigned stitches          = 1;
    Vector3d spacing           = Vector3d::Zero(); ///< s, m
    double   transfer_duration = 1;                ///< s, from one pass's pull (tightening) to the next's start
    bool     interrupted       = false;
  };

  struct SurgicalSeries
  {
    Trajectory                trajectory; ///< pose of the needle's body frame (origin at C)
    std::vector<SurgicalPass> passes;     ///< each as plan_pass() plans it alone, at its own times
    std::vector<std::pair<double, bool>> jaws; ///< the passes' regrasps and reloads, in time order (s)
    /// the reloads (from, to), s: while the driver's jaws are open, the other hand's
    /// grasper holds the needle where it is
    std::vector<std::pair<double, double>> reloads;
    double                    t_end = 0, t_tightened = 0; ///< the last pull's end; the tightening's (s)

    /// The needle's pose at @p t in an interrupted series whose pass k's pull stopped at
    /// @p pulls[k] (s; the tail short enough to be held) and whose tightening stopped at
    /// @p ties[k] (the stitch tied off as its wound closed); ∞ or absent: it ran to its
    /// end. A stopped pull holds the needle still until the pull's planned end, and the
    /// tightening then moves it from there (its planned translation, offset by what the
    /// pull did not do). A stopped tightening holds the needle until its planned end.
    /// The transfer to the next pass then starts from where the needle is, the offset
    /// from the planned pose fading linearly to nothing at the next pass's start (a
    /// straight line when the transfer is one). After the last pass the needle stays.
    Pose
    pose(double t, const std::vector<double> &pulls, const std::vector<double> &ties) const;
  };

  /// Plans the series: each pass as plan_pass() with its entry and start time; after
  /// each but the last, its pull draws the suture through, then the needle is carried to
  /// the next pass's start over the transfer time, its centre in a straight line and the
  /// needle turning on the way it turned in the pass (keyframes every π/12), never back:
  /// turned on, the arc runs round the circle's part above the skin (the exit side, the
  /// top, the entry side), and with the centre no lower than the pass's that part stays
  /// out of the tissue. Slerp between the two poses alone would turn the short way, which
  /// for a shallow bite (Φ + 2α + 2 approach/R < π) is back through the tissue. The last
  /// pass pulls and tightens as a single one. In an interrupted series every pass
  /// tightens, and the transfer starts at the tightening's end; where the pull and the
  /// tightening together have lowered the needle, a lift along the normal back to the
  /// pass's height comes first, over half the transfer time more. Throws
  /// std::invalid_argument as plan_pass() does, and when the spacing is zero or out of
  /// the surface, the pull lowers the needle (a series needs it at or above the pass's
  /// height), or the transfer time is not positive.
  ///
  /// With a regrasp, each pass but the last ends with the driver holding the needle near
  /// its tip. Before the transfer the needle is reloaded, as a surgeon does with the
  /// other hand: that hand's grasper takes the needle and holds it still, the driver's
  /// jaws open and move back along the arc to the grip point (the frame turning back by
  /// the pass's β about the arc's axis) over the regrasp's duration, close, and the
  /// other hand lets go. The next pass then starts as the first did.
  SurgicalSeries
  plan_series(const CurvedNeedle &needle, const PassParameters &first, const SeriesParameters &series);
} // namespace suturesim::tools
