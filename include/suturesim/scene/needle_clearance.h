#pragma once
/**
 * @file
 * A planned pass's needle kept out of the tissue once its pass is over, in both paths.
 *
 * After the turn (tools::SurgicalPass::t_turn_end, the swage out of the exit by the
 * approach) the needle driver only translates the needle: the pull, the tightening and,
 * in a series, the transfer to the next pass's start. A surgeon never drives the needle
 * back into the skin there, and the scene's contact does not stop it: the suture's node
 * at the swage is then pressed into the tissue by a prescribed motion, which the
 * accurate path's Newton cannot follow (on the bite × spacing scene with its earlier
 * tightening it failed at 10.504 s, after six halvings; docs/tearing.md) and the
 * realtime path passes through without a word. So a needle whose swage or tip is inside the
 * tissue in one of those windows is refused with the scene's one-line error, naming
 * Needle/Pass/Pull or Tighten and the time.
 *
 * Inside: the winding number of the tissue's closed, deformed surface exceeds ½
 * (collision::winding_number). Its cost, a solid angle per surface triangle and point, is
 * paid at most once per 5 ms of motion and only where a point lies within the surface's
 * bounding box.
 */

#include <suturesim/core/parameter_file.h>
#include <suturesim/scene/needle_parameters.h>
#include <suturesim/tools/curved_needle.h>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <optional>
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

    /// Refuses, through @p pass (the scope of Needle/Pass), the needle in pose @p pose at
    /// motion time @p t (s) when its swage or tip lies inside the closed surface
    /// @p triangles of @p vertices (m) within a window. Checks at most every 5 ms of @p t.
    void
    check(double t, const tools::Pose &pose, const Eigen::Matrix3Xd &vertices,
          const std::vector<std::array<std::uint32_t, 3>> &triangles, const ParameterScope &pass);

    /// The windows (from, to), s.
    const std::vector<std::pair<double, double>> &
    windows() const
    {
      return open;
    }

  private:
    std::optional<tools::CurvedNeedle>     needle;
    std::vector<std::pair<double, double>> open;
    std::vector<double>                    pull_ends; ///< each pass's pull's end, s
    double                                 next_check = -1;
  };
} // namespace suturesim::scene
