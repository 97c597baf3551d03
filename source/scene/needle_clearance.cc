#include <suturesim/scene/needle_clearance.h>

#include <suturesim/collision/volume_penetration.h>

#include <algorithm>
#include <limits>
#include <sstream>

namespace suturesim::scene
{
  NeedleClearance::NeedleClearance(const NeedleParameters &parameters)
  {
    if (!parameters.present() || parameters.motion != "pass" || parameters.released())
      return;
    needle.emplace(parameters.needle());
    const auto planned = parameters.planned_series();
    for (std::size_t k = 0; k < planned.passes.size(); ++k)
      {
        const auto &pass = planned.passes[k];
        const bool  last = k + 1 == planned.passes.size();
        // a running series tightens its last pass only, the others go on to the transfer
        windows.push_back({pass.t_turn_end,
                           last ? std::numeric_limits<double>::infinity()
                                : planned.passes[k + 1].trajectory.start_time(),
                           pass.t_end, last || parameters.series.interrupted ? pass.t_tightened : pass.t_end, last});
      }
  }

  const char *
  NeedleClearance::motion(const Window &w, const double t)
  {
    if (t < w.pull_end)
      return "Pull";
    return t < w.tighten_end || w.last ? "Tighten" : "Transfer duration";
  }

  void
  NeedleClearance::check(const double t, const tools::Pose &pose, const Eigen::Matrix3Xd &vertices,
                         const std::vector<std::array<std::uint32_t, 3>> &triangles)
  {
    if (!needle || triangles.empty() || !why.empty() || t < next_check)
      return;
    next_check = t + 5e-3;
    const auto w = std::find_if(windows.begin(), windows.end(),
                                [t](const Window &v) { return t >= v.from && t < v.to; });
    if (w == windows.end())
      return;
    // the surface's bounding box: most of the time the needle is well above it
    Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
    for (const auto &tri : triangles)
      for (const auto v : tri)
        {
          lo = lo.cwiseMin(vertices.col(v));
          hi = hi.cwiseMax(vertices.col(v));
        }
    const std::pair<const char *, Eigen::Vector3d> ends[] = {{"swage", needle->swage(pose)},
                                                             {"tip", needle->tip(pose)}};
    for (const auto &[name, at] : ends)
      {
        if ((at.array() < lo.array()).any() || (at.array() > hi.array()).any() ||
            collision::winding_number(at, vertices, triangles) <= 0.5)
          continue;
        std::ostringstream text;
        text.precision(4);
        text << "the needle's " << name << " went back into the tissue at t = " << t << " s, at (" << at[0] << ", "
             << at[1] << ", " << at[2] << ") m, after pass " << w - windows.begin() + 1 << "'s turn ended at "
             << w->from << " s: Needle/Pass/" << motion(*w, t)
             << " drives it there (a tie-off stops that motion only once the wound closes); the run stops there";
        why = text.str();
        return;
      }
  }
} // namespace suturesim::scene
