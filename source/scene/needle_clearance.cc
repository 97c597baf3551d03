#include <suturesim/scene/needle_clearance.h>

#include <suturesim/collision/volume_penetration.h>

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
        const bool last = k + 1 == planned.passes.size();
        open.emplace_back(planned.passes[k].t_turn_end,
                          last ? std::numeric_limits<double>::infinity()
                               : planned.passes[k + 1].trajectory.start_time());
        pull_ends.push_back(planned.passes[k].t_end);
        // a running series tightens its last pass only, the others go on to the transfer
        tighten_ends.push_back(last || parameters.series.interrupted ? planned.passes[k].t_tightened
                                                                      : planned.passes[k].t_end);
      }
  }

  const char *
  NeedleClearance::motion(const std::size_t k, const double t) const
  {
    if (t < pull_ends[k])
      return "Pull";
    // after the last pass's tightening the needle stays where that put it
    return t < tighten_ends[k] || k + 1 == open.size() ? "Tighten" : "Transfer duration";
  }

  std::string
  NeedleClearance::check(const double t, const tools::Pose &pose, const Eigen::Matrix3Xd &vertices,
                         const std::vector<std::array<std::uint32_t, 3>> &triangles)
  {
    if (!needle || triangles.empty() || t < next_check)
      return "";
    next_check = t + 5e-3;
    std::size_t k = 0;
    while (k < open.size() && !(t >= open[k].first && t < open[k].second))
      ++k;
    if (k == open.size())
      return "";
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
        std::ostringstream why;
        why.precision(4);
        why << "the needle's " << name << " went back into the tissue at t = " << t << " s, at (" << at[0] << ", "
            << at[1] << ", " << at[2] << ") m, after pass " << k + 1 << "'s turn ended at " << open[k].first
            << " s: Needle/Pass/" << motion(k, t)
            << " drives it there (a tie-off stops that motion only once the wound closes); the run stops there";
        return why.str();
      }
    return "";
  }
} // namespace suturesim::scene
