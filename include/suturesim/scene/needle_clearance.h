#pragma once
/**
 * @file
 * A planned pass's needle kept out of the tissue once its pass is over, in both paths.
 *
 * After the turn (tools::SurgicalPass::t_turn_end, the swage out of the exit by the
 * approach) the needle driver carries the needle away: the pull, the tightening and, in
 * a series, the transfer to the next pass's start. A surgeon never drives the needle
 * back into the skin there, and the scene's contact does not stop it: the suture's node
 * at the swage is then pressed into the tissue by a prescribed motion, which the
 * accurate path's Newton cannot follow (on the bite × spacing scene with its earlier
 * tightening it failed at 10.504 s, after six halvings; docs/tearing.md) and the
 * realtime path passes through without a word. So a needle whose swage or tip is inside
 * the tissue in one of those windows ends the run there, as incomplete (exit 6, the
 * reason naming Needle/Pass/Pull, Tighten or Transfer duration, the time and the
 * point): what the run computed until then stands (a study keeps its onsets), what the
 * scene asked for after it cannot be done. Not an input error: a tie-off stops the
 * motion when the wound closes, which only the run knows.
 *
 * Inside: the winding number of the tissue's closed, deformed surface exceeds ½
 * (collision::winding_number). Its cost, a solid angle per surface triangle and point, is
 * paid at most once per 5 ms of motion and only where a point lies within the surface's
 * bounding box.
 */

#include <suturesim/scene/needle_parameters.h>
#include <suturesim/tools/curved_needle.h>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace suturesim::scene
{
  class NeedleClearance
  {
  public:
    /// The windows of @p parameters' planned passes (Motion = pass): from each pass's turn
    /// end to the next pass's start, the last one open-ended. None (no check) for a
    /// needle moved by keyframes, or let go by its jaws (the driver's pose is then not
    /// the needle's).
    explicit NeedleClearance(const NeedleParameters &parameters);

    /// Why the run stops at motion time @p t (s), the needle in pose @p pose: its swage or
    /// tip inside the closed surface @p triangles of @p vertices (m) within a window; ""
    /// while it is clear, or between checks (at most one every 5 ms of @p t).
    std::string
    check(double t, const tools::Pose &pose, const Eigen::Matrix3Xd &vertices,
          const std::vector<std::array<std::uint32_t, 3>> &triangles);

  private:
    /// The entry of Needle/Pass whose motion carries the needle at time @p t of window
    /// @p k: Pull, Tighten or (a series' transfer to the next pass) Transfer duration.
    const char *
    motion(std::size_t k, double t) const;

    std::optional<tools::CurvedNeedle>     needle;
    std::vector<std::pair<double, double>> open;
    std::vector<double>                    pull_ends;    ///< each pass's pull's end, s
    std::vector<double>                    tighten_ends; ///< and its tightening's (its pull's without one), s
    double                                 next_check = -1;
  };
} // namespace suturesim::scene
