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

    /// Checks the needle in pose @p pose at motion time @p t (s) against the closed
    /// surface @p triangles of @p vertices (m), at most once every 5 ms of @p t: its swage
    /// or tip inside it within a window ends the run (reason()).
    void
    check(double t, const tools::Pose &pose, const Eigen::Matrix3Xd &vertices,
          const std::vector<std::array<std::uint32_t, 3>> &triangles);

    /// Why the run ends here, the first time check() found the needle inside; "" while
    /// it has not.
    const std::string &
    reason() const
    {
      return why;
    }

  private:
    /// After pass k's turn, until the next pass starts (s).
    struct Window
    {
      double from, to;
      double pull_end;    ///< the pass's pull's end
      double tighten_end; ///< its tightening's (its pull's where the transfer follows it)
      bool   last;        ///< after the last pass's tightening the needle stays put
    };

    /// The entry of Needle/Pass whose motion carries the needle at time @p t of window
    /// @p w: Pull, Tighten or (a series' transfer to the next pass) Transfer duration.
    static const char *
    motion(const Window &w, double t);

    std::optional<tools::CurvedNeedle> needle;
    std::vector<Window>                windows;
    double                             next_check = -1;
    std::string                        why;
  };
} // namespace suturesim::scene
