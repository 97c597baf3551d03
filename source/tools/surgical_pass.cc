#include <suturesim/tools/surgical_pass.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace suturesim::tools
{
  namespace
  {
    /// Keyframes for a turn by @p angle (rad): one every π/12 at most, since slerp between
    /// two keyframes turns the short way.
    unsigned
    turn_segments(const double angle)
    {
      return std::max(1u, static_cast<unsigned>(std::ceil(angle / (M_PI / 12))));
    }
  } // namespace

  SurgicalPass
  plan_pass(const CurvedNeedle &needle, const PassParameters &p)
  {
    const double R = needle.radius(), Phi = needle.arc_angle();
    if (needle.straight())
      throw std::invalid_argument("surgical pass: a pass turns a curved needle about its arc centre; a straight needle "
                                  "moves by keyframes");
    if (!(p.normal.norm() > 0))
      throw std::invalid_argument("surgical pass: the surface normal is zero");
    const Vector3d n = p.normal.normalized();
    Vector3d       b = p.bite_direction - p.bite_direction.dot(n) * n;
    if (!(b.norm() > 1e-9 * p.bite_direction.norm()))
      throw std::invalid_argument("surgical pass: the bite direction lies along the normal");
    b.normalize();

    SurgicalPass pass;
    if (p.bite > 0)
      {
        if (p.bite > R)
          throw std::invalid_argument("surgical pass: a bite wider than the needle radius "
                                      "(the arc cannot straddle the wound)");
        pass.entry_angle = std::asin(p.bite / R);
      }
    else if (p.bite_depth > 0)
      {
        if (p.bite_depth > R)
          throw std::invalid_argument("surgical pass: a bite deeper than the needle radius "
                                      "(the needle would enter backwards)");
        pass.entry_angle = std::acos(1 - p.bite_depth / R);
      }
    else
      {
        if (!(p.entry_angle > 0 && p.entry_angle <= M_PI / 2))
          throw std::invalid_argument("surgical pass: entry angle must lie in (0, pi/2]");
        pass.entry_angle = p.entry_angle;
      }
    const double alpha = pass.entry_angle;
    const double h     = R * std::cos(alpha);
    pass.bite_depth    = R - h;
    pass.bite_width    = 2 * R * std::sin(alpha);
    pass.entry         = p.bite > 0 ? Vector3d(p.crossing - p.bite * b) : p.entry;
    pass.centre        = pass.entry + R * std::sin(alpha) * b + h * n;
    pass.exit          = pass.entry + pass.bite_width * b;
    if (!(p.angular_speed > 0) || !(p.pull_duration > 0) || !(p.approach >= 0) || !(p.tighten_duration > 0))
      throw std::invalid_argument("surgical pass: angular speed, pull and tighten durations must be > 0");
    if (2 * alpha + Phi >= 2 * M_PI)
      throw std::invalid_argument("surgical pass: the needle's arc closes on itself inside the tissue");

    // world angles θ in the arc's plane, from b towards n, about e = b × n
    const Vector3d e       = b.cross(n);
    const double   theta_E = std::atan2(-std::cos(alpha), -std::sin(alpha));
    const double   eps     = p.approach / R;
    // body frame: x → b, y → n, z → e; the tip sits at body angle Φ, so a turn ψ puts
    // it at world angle ψ + Φ and the swage at ψ
    Eigen::Matrix3d frame;
    frame << b, n, e;
    const Quaterniond base(frame);
    const double      psi_start = theta_E - Phi - eps;
    const double      psi_end   = theta_E + 2 * alpha + eps;
    const double      w         = p.angular_speed;
    const double      t0        = p.start_time;
    pass.t_tip_entry            = t0 + eps / w;
    pass.t_tip_exit             = pass.t_tip_entry + 2 * alpha / w;
    pass.t_swage_exit           = pass.t_tip_exit + Phi / w;
    pass.t_turn_end             = t0 + (psi_end - psi_start) / w;

    // the driver's turn ψ_d(t): with a regrasp it holds at ψ_r while its jaws move β along
    // the arc (its frame turning about the arc's axis), then turns on, β ahead
    double psi_r = psi_end, beta = 0, hold = 0;
    if (p.regrasp_exposure > 0)
      {
        const double L = needle.length(), zeta_jaws = (1 - p.grip) * L, zeta_take = p.regrasp_exposure / 2;
        if (!(p.grip > 0 && p.grip < 1) || !(p.regrasp_duration > 0))
          throw std::invalid_argument("surgical pass: the grip must lie in (0, 1) of the arc and the regrasp "
                                      "duration be > 0");
        psi_r = theta_E + 2 * alpha - Phi + p.regrasp_exposure / R; // the tip out by the exposure
        if (!(psi_r < psi_end) || !(zeta_take < zeta_jaws))
          throw std::invalid_argument("surgical pass: the regrasp exposure must leave the tip out before the turn "
                                      "ends, with its middle nearer the tip than the driver's grip");
        // the jaws let go above the skin: the point they hold, at world angle ψ_r + its
        // body angle, lies above the surface's plane through E
        const double jaws_angle = psi_r + Phi - zeta_jaws / R;
        if (!(R * std::sin(jaws_angle) + h > 0))
          throw std::invalid_argument("surgical pass: the driver's jaws would be in the tissue when they let the "
                                      "needle go: the grip must lie nearer the swage");
        beta              = (zeta_jaws - zeta_take) / R;
        pass.regrasp_turn = beta;
        hold              = p.regrasp_duration;
        const double t_r = t0 + (psi_r - psi_start) / w;
        pass.jaws        = {{t_r, true}, {t_r + hold, false}};
        pass.t_swage_exit += pass.t_swage_exit > t_r ? hold : 0;
        pass.t_turn_end += hold;
      }
    pass.t_end = pass.t_turn_end + p.pull_duration;
    // keyframes every π/12 at most: slerp turns the short way, and the position (the
    // centre) stays put
    const auto turn = [&](const double from, const double to, const double t_from, const bool jaws_moving) {
      const unsigned segments = turn_segments(to - from);
      for (unsigned k = 0; k <= segments; ++k)
        {
          const double psi = from + (to - from) * k / segments;
          const double t   = t_from + (jaws_moving ? hold * k / segments : (psi - from) / w);
          pass.trajectory.add(t, {pass.centre, base * Quaterniond(Eigen::AngleAxisd(psi, Vector3d::UnitZ()))});
        }
    };
    turn(psi_start, psi_r, t0, false);
    if (beta > 0)
      {
        const double t_r = pass.jaws.front().first;
        turn(psi_r, psi_r + beta, t_r, true);              // the jaws move along the arc
        turn(psi_r + beta, psi_end + beta, t_r + hold, false); // and the turn goes on
      }
    const Pose last = pass.trajectory.pose(pass.t_turn_end);
    pass.trajectory.add(pass.t_end, {last.position + p.pull, last.orientation});
    pass.t_tightened = pass.t_end;
    if (!p.tighten.isZero())
      {
        pass.t_tightened = pass.t_end + p.tighten_duration;
        pass.trajectory.add(pass.t_tightened, {last.position + p.pull + p.tighten, last.orientation});
      }
    return pass;
  }

  SurgicalSeries
  plan_series(const CurvedNeedle &needle, const PassParameters &first, const SeriesParameters &series)
  {
    if (series.stitches == 0)
      throw std::invalid_argument("surgical series: at least one stitch");
    const Vector3d n = first.normal.normalized();
    if (series.stitches > 1)
      {
        if (!(series.spacing.norm() > 0) || std::abs(series.spacing.normalized().dot(n)) > 1e-9)
          throw std::invalid_argument("surgical series: the spacing must be > 0 and lie in the surface");
        if (!(series.transfer_duration > 0))
          throw std::invalid_argument("surgical series: the transfer duration must be > 0");
        if (first.pull.dot(n) < 0)
          throw std::invalid_argument("surgical series: the pull must not lower the needle towards the skin");
      }
    SurgicalSeries result;
    PassParameters p = first;
    for (unsigned k = 0; k < series.stitches; ++k)
      {
        const bool last = k + 1 == series.stitches;
        p.entry         = first.entry + k * series.spacing;
        p.crossing      = first.crossing + k * series.spacing;
        p.tighten       = last || series.interrupted ? first.tighten : Vector3d::Zero();
        const auto pass = plan_pass(needle, p);
        if (k == 0) // as planned, bit for bit (add() normalises the orientation again)
          result.trajectory = pass.trajectory;
        else
          for (const auto &[t, pose] : pass.trajectory.keyframes())
            result.trajectory.add(t, pose);
        result.passes.push_back(pass);
        result.jaws.insert(result.jaws.end(), pass.jaws.begin(), pass.jaws.end());
        result.t_end       = pass.t_end;
        result.t_tightened = pass.t_tightened;
        if (last)
          break;
        // the reload: the needle held still by the other hand while the driver's frame
        // turns back by β about the arc's axis (its body z), jaws open
        double     t_from = series.interrupted ? pass.t_tightened : pass.t_end;
        const Pose held   = pass.trajectory.pose(t_from);
        if (pass.regrasp_turn > 0)
          {
            const double   beta = pass.regrasp_turn, d = first.regrasp_duration;
            const unsigned segments = turn_segments(beta);
            for (unsigned j = 1; j <= segments; ++j)
              result.trajectory.add(t_from + d * j / segments,
                                    {held.position,
                                     held.orientation * Quaterniond(Eigen::AngleAxisd(-beta * j / segments,
                                                                                      Vector3d::UnitZ()))});
            result.jaws.insert(result.jaws.end(), {{t_from, true}, {t_from + d, false}});
            result.reloads.emplace_back(t_from, t_from + d);
            t_from += d;
          }
        // an interrupted series' tightening may draw the needle down beside the wound: it
        // is lifted back to the pass's height along the normal first, over half the
        // transfer time, so that the transfer's straight line stays above it
        const double lift = series.interrupted ? -(first.pull + first.tighten).dot(n) : 0;
        if (lift > 0)
          {
            const Pose down = result.trajectory.pose(t_from);
            t_from += 0.5 * series.transfer_duration;
            result.trajectory.add(t_from, {down.position + lift * n, down.orientation});
          }
        // on to the next pass's start, turning on about the pass's axis by the angle
        // that completes the turn (2π less the short way back, when that is backwards)
        PassParameters next           = p;
        next.entry                    = p.entry + series.spacing;
        next.crossing                 = p.crossing + series.spacing;
        next.start_time               = t_from + series.transfer_duration;
        const Pose              start = plan_pass(needle, next).trajectory.pose(next.start_time);
        const Pose              from  = result.trajectory.pose(t_from);
        const Vector3d          axis  = pass.trajectory.velocity(pass.t_tip_entry).second.normalized();
        const Eigen::AngleAxisd rest(start.orientation * from.orientation.inverse());
        const double            turn     = rest.axis().dot(axis) >= 0 ? rest.angle() : 2 * M_PI - rest.angle();
        const unsigned          segments = turn_segments(turn);
        for (unsigned j = 1; j < segments; ++j)
          {
            const double f = double(j) / segments;
            result.trajectory.add(t_from + f * series.transfer_duration,
                                  {from.position + f * (start.position - from.position),
                                   Quaterniond(Eigen::AngleAxisd(f * turn, axis)) * from.orientation});
          }
        p.start_time = next.start_time;
      }
    return result;
  }

  Pose
  SurgicalSeries::pose(const double t, const std::vector<double> &pulls, const std::vector<double> &ties) const
  {
    const double never = std::numeric_limits<double>::infinity();
    // the pass whose span [start, next start) holds t
    std::size_t k = 0;
    while (k + 1 < passes.size() && t >= passes[k + 1].trajectory.keyframes().begin()->first)
      ++k;
    const SurgicalPass &pass = passes[k];
    // a pull stopped within the pull (before its turn ended: at the turn's end)
    const double pull = k < pulls.size() && pulls[k] < pass.t_end ? std::max(pulls[k], pass.t_turn_end) : never;
    const double tie  = k < ties.size() && ties[k] < pass.t_tightened ? ties[k] : never;
    const Vector3d behind =
      pull < never ? Vector3d(trajectory.pose(pull).position - trajectory.pose(pass.t_end).position) : Vector3d::Zero();
    // the needle as it went up to u (≤ the tightening's end), before any tie
    const auto went = [&](const double u) {
      if (u < pull)
        return trajectory.pose(u);
      if (u <= pass.t_end)
        return trajectory.pose(pull);
      Pose moved = trajectory.pose(u);
      moved.position += behind;
      return moved;
    };
    if (t < std::min(tie, pass.t_tightened))
      return went(t);
    const Pose held = went(std::min(tie, pass.t_tightened));
    if (k + 1 == passes.size() || t <= pass.t_tightened)
      return held;
    // the transfer, from where the needle is
    const double next = passes[k + 1].trajectory.keyframes().begin()->first;
    const double f    = (t - pass.t_tightened) / (next - pass.t_tightened);
    Pose         pose = trajectory.pose(t);
    pose.position += (1 - f) * (held.position - trajectory.pose(pass.t_tightened).position);
    return pose;
  }
} // namespace suturesim::tools
