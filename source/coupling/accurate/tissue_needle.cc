#include <suturesim/coupling/accurate/tissue_needle.h>
#include <suturesim/coupling/pierce_order.h>
#include <suturesim/coupling/thread_tie.h>

#include <algorithm>
#include <cmath>

namespace suturesim::coupling
{
  using namespace dealii;

  namespace
  {
    Point<3>
    point(const Eigen::Vector3d &v)
    {
      return {v[0], v[1], v[2]};
    }
    Tensor<1, 3>
    tensor(const Eigen::Vector3d &v)
    {
      Tensor<1, 3> t;
      for (unsigned d = 0; d < 3; ++d)
        t[d] = v[d];
      return t;
    }
    Eigen::Vector3d
    eigen(const Point<3> &p)
    {
      return {p[0], p[1], p[2]};
    }
  } // namespace

  TissueNeedle::TissueNeedle(const tools::CurvedNeedle &geometry, const TissueNeedleParameters &parameters,
                             const std::vector<mesh::Triangle> &surface, const Eigen::Matrix3Xd &X0)
    : needle(geometry)
    , prm(parameters)
    , triangles(surface)
    , reference(X0)
  {
    puncture.emplace(prm.puncture, triangles, reference);
  }

  void
  TissueNeedle::set_thread(const std::vector<rod::Vec3> *nodes, std::vector<double> element_lengths)
  {
    thread = nodes;
    thread_s.assign(1, 0.0);
    for (const double l : element_lengths)
      thread_s.push_back(thread_s.back() + l);
  }

  double
  TissueNeedle::curve_length() const
  {
    return needle.length() + (thread ? thread_s.back() : 0.0);
  }

  std::pair<std::size_t, double>
  TissueNeedle::thread_element(const double s) const
  {
    const std::size_t n = thread_s.size() - 1;
    const std::size_t e = std::min<std::size_t>(
      n - 1, std::upper_bound(thread_s.begin(), thread_s.end(), std::max(0.0, s)) - thread_s.begin() - 1);
    const double xi = std::clamp((s - thread_s[e]) / (thread_s[e + 1] - thread_s[e]), 0.0, 1.0);
    return {e, xi};
  }

  std::pair<Tensor<1, 3>, Tensor<1, 3>>
  TissueNeedle::curve(const double zeta) const
  {
    if (!thread || zeta <= needle.length())
      return {tensor(needle.point(current, zeta)), tensor(needle.tangent(current, zeta))};
    const auto [e, xi]       = thread_element(zeta - needle.length());
    const auto           &x  = *thread;
    const Eigen::Vector3d c  = (1 - xi) * x[e] + xi * x[e + 1];
    return {tensor(c), tensor((x[e] - x[e + 1]).normalized())};
  }

  std::vector<std::size_t>
  TissueNeedle::thread_elements() const
  {
    std::vector<std::size_t> elements;
    for (const auto &p : pierce)
      if (on_thread(p))
        elements.push_back(thread_element(p.carrier - needle.length()).first);
    std::sort(elements.begin(), elements.end());
    elements.erase(std::unique(elements.begin(), elements.end()), elements.end());
    return elements;
  }

  std::vector<std::size_t>
  TissueNeedle::thread_points() const
  {
    const std::size_t        offset = touch_index() == 0 ? 1 : 0;
    std::vector<std::size_t> indices;
    for (std::size_t j = 0; j < pierce.size(); ++j)
      if (on_thread(pierce[j]))
        indices.push_back(offset + j);
    return indices;
  }

  void
  TissueNeedle::thread_terms(const std::vector<Point<3>> &x, const std::size_t element,
                             Eigen::Matrix<double, 12, 1> &residual, Eigen::Matrix<double, 12, 12> &jacobian) const
  {
    const std::size_t offset = touch_index() == 0 ? 1 : 0;
    for (std::size_t j = 0; j < pierce.size(); ++j)
      {
        if (!on_thread(pierce[j]))
          continue;
        const auto [e, xi] = thread_element(pierce[j].carrier - needle.length());
        if (e != element)
          continue;
        // the tie across the thread from its energy (exact, the element's turn
        // included); the friction along it as the force it is
        const auto            &xs = *thread;
        const Eigen::Vector3d  xj = eigen(x[offset + j]);
        const ThreadTie        tie = thread_tie(xj, xs[e], xs[e + 1], 1 - xi, prm.transverse_stiffness);
        Tensor<2, 3>           df_dx;
        FrictionResult         slip;
        double                 N = 0;
        const Tensor<1, 3>     f = pierce_force(pierce[j], x[offset + j], &slip, &N, &df_dx);
        const double           w[2] = {1 - xi, xi};
        const Eigen::Vector3d  t    = (xs[e] - xs[e + 1]).normalized();
        // in slip f_t = −F t with F = ∓μN, N = N₀ + s(|f⊥|): ∂f_t/∂x = (F/N) s' k⊥ t n̂ᵀ,
        // n̂ the tie force's direction. Left out of the tissue's symmetric tangent, but a stiff
        // tie (μ k⊥ of the tie's own order) makes the suture's Newton diverge without it.
        Tensor<1, 3> n_hat;
        for (unsigned i = 0; i < 3; ++i)
          n_hat[i] = f[i] + slip.force * t[i]; // f⊥ = f + F t
        const double tie_force = n_hat.norm();
        if (tie_force > 0)
          n_hat /= tie_force;
        // The friction's turn with the element: t = (x_a − x_b)/l turns by ∂t/∂x_a =
        // P/l = −∂t/∂x_b (P = I − t tᵀ) about the element's point c, and with it the
        // projection ζ = ζ_a − (x − c)·t (∂ζ/∂x_a = −d⊥ᵀ/l, d⊥ = P (x − c)) and, in slip,
        // the tie's length |d⊥| (∂|d⊥|/∂x_a = −(t·(x − c)) d̂ᵀ/l, d̂ = −n̂: the lever of a
        // point that lags along the thread). On −F t this gives, per node b of sign
        // σ_b = ±1, σ_b/l (F' t d⊥ᵀ − F P + (F/N) k⊥ (t·(x − c)) t d̂ᵀ), F' = ∂F/∂ζ: of
        // the order of F/l, the same as the thread's own geometric stiffness T/l across
        // itself.
        const double          l      = (xs[e] - xs[e + 1]).norm();
        const Eigen::Vector3d c      = (1 - xi) * xs[e] + xi * xs[e + 1];
        const double          lever  = (xj - c).dot(t);
        const Eigen::Vector3d d_perp = (xj - c) - lever * t;
        const double          N_rate =
          slip.slipping && N > 0
            ? slip.force / N * prm.transverse_stiffness *
                normal_force(prm.friction.grip, tie_force, prm.normal_smoothing).rate
            : 0.0;
        for (unsigned a = 0; a < 2; ++a)
          for (unsigned i = 0; i < 3; ++i)
            {
              // friction f − f⊥ on the tissue, its reaction on the node by weight
              residual[6 * a + i] += tie.gradient[3 * a + i] + w[a] * (f[i] - tie.tissue_force[i]);
              for (unsigned b = 0; b < 2; ++b)
                for (unsigned k = 0; k < 3; ++k)
                  {
                    // ∂(friction)/∂x = df_dx + k⊥ P
                    const double friction_rate =
                      df_dx[i][k] + prm.transverse_stiffness * ((i == k ? 1.0 : 0.0) - t[i] * t[k]) +
                      N_rate * t[i] * n_hat[k];
                    const double turn = (b == 0 ? 1.0 : -1.0) / l *
                                        (slip.derivative * t[i] * d_perp[k] -
                                         slip.force * ((i == k ? 1.0 : 0.0) - t[i] * t[k]) +
                                         N_rate * lever * t[i] * (-n_hat[k]));
                    jacobian(6 * a + i, 6 * b + k) +=
                      tie.hessian(3 * a + i, 3 * b + k) - w[a] * w[b] * friction_rate + w[a] * turn;
                  }
            }
      }
  }

  void
  TissueNeedle::rebuild_points()
  {
    X.clear();
    if (puncture->pressing())
      X.push_back(point(puncture->touch()->reference));
    for (const auto &p : pierce)
      X.push_back(p.X);
  }

  bool
  TissueNeedle::begin_step(const double t, const tools::Pose &pose, const Eigen::Matrix3Xd &surface)
  {
    time                  = t;
    current               = pose;
    const bool   before   = puncture->pressing();
    const double was_at   = before ? puncture->touch()->reference.norm() : -1;
    puncture->update(t, needle.tip(pose), surface);
    const bool changed = puncture->pressing() != before ||
                         (before && puncture->touch()->reference.norm() != was_at);
    if (changed)
      rebuild_points();
    return changed;
  }

  void
  TissueNeedle::save()
  {
    saved_puncture.emplace(*puncture);
    saved_pierce    = pierce;
    saved_log       = log.size();
    saved_pose      = current;
    saved_time      = time;
    saved_last_time = last_time;
  }

  void
  TissueNeedle::restore()
  {
    puncture.emplace(*saved_puncture);
    pierce    = saved_pierce;
    log.resize(saved_log);
    current   = saved_pose;
    time      = saved_time;
    last_time = saved_last_time;
    rebuild_points();
  }

  double
  TissueNeedle::projection(const AccuratePiercePoint &p, const Point<3> &x) const
  {
    // on the thread, the carrier's straight element (extended)
    if (on_thread(p))
      {
        const auto [c, t] = curve(p.carrier);
        return p.carrier - (Tensor<1, 3>(x) - c) * t;
      }
    // on the needle, the circle through the arc, taken within half a turn of the anchor
    // and continued straight along the end tangents beyond the tip and the swage
    const double    R   = needle.radius(), L = needle.length();
    const auto      X   = current.inverse_apply(eigen(x));
    const double    phi = needle.arc_angle() - p.anchor / R;
    double          psi = std::atan2(X[1], X[0]);
    psi += 2 * M_PI * std::round((phi - psi) / (2 * M_PI));
    const double zeta = R * (needle.arc_angle() - psi);
    const double end  = std::clamp(zeta, 0.0, L);
    if (zeta == end)
      return zeta;
    const auto [ce, te] = curve(end);
    return end - (Tensor<1, 3>(x) - ce) * te;
  }

  std::pair<Tensor<1, 3>, Tensor<1, 3>>
  TissueNeedle::projected_curve(const AccuratePiercePoint &p, const double zeta) const
  {
    if (on_thread(p))
      {
        const auto [c, t] = curve(p.carrier);
        return {c - (zeta - p.carrier) * t, t};
      }
    const double end   = std::clamp(zeta, 0.0, needle.length());
    const auto [c, t]  = curve(end);
    return {c - (zeta - end) * t, t};
  }

  TissueNeedle::Offset
  TissueNeedle::across_curve(const AccuratePiercePoint &p, const Point<3> &x) const
  {
    Offset o;
    o.zeta            = projection(p, x);
    const auto [c, t] = projected_curve(p, o.zeta);
    const Tensor<1, 3> d = Tensor<1, 3>(x) - c;
    o.tangent            = t;
    o.across             = d - (d * t) * t;
    return o;
  }

  Tensor<1, 3>
  TissueNeedle::pierce_force(const AccuratePiercePoint &p, const Point<3> &x, FrictionResult *r_out,
                             double *N_out, Tensor<2, 3> *df_dx) const
  {
    // the tie across the curve at the point's projection ζ, the friction along it by ζ − ζ_a
    const auto [zeta, t, d_perp] = across_curve(p, x);
    const Tensor<1, 3> lambda = p.multiplier - (p.multiplier * t) * t;
    const Tensor<1, 3> f_perp = -(lambda + prm.transverse_stiffness * d_perp);
    const double       N      = normal_force(prm.friction.grip, f_perp.norm(), prm.normal_smoothing).value;
    // the generalised force f_ζ acts along dx/dζ = −t
    const FrictionResult r = coulomb_friction(prm.friction, zeta, p.anchor, N);
    if (r_out)
      *r_out = r;
    if (N_out)
      *N_out = N;
    if (df_dx)
      {
        // the curvature's part (|d_perp| / R against 1) is left out
        const Tensor<2, 3> ttT = outer_product(t, t);
        *df_dx                 = -prm.transverse_stiffness * (unit_symmetric_tensor<3>() - ttT);
        if (!r.slipping)
          *df_dx -= prm.friction.stiffness * ttT;
      }
    return f_perp - r.force * t;
  }

  double
  TissueNeedle::carried_to(const AccuratePiercePoint &p, const Point<3> &x) const
  {
    const double      L = needle.length();
    const std::size_t n = thread_s.size() - 1;
    auto [e, xi]        = thread_element(p.carrier - L);
    const auto &nodes   = *thread;
    const Eigen::Vector3d X = eigen(x);
    // ξ of x's projection on element e's line
    const auto along = [&](const std::size_t k) {
      const Eigen::Vector3d u = nodes[k + 1] - nodes[k];
      return (X - nodes[k]).dot(u) / u.squaredNorm();
    };
    // Walk while the projection lies beyond the element's ends by more than a tenth of
    // it. The slack is a dead zone: a point at the outside of a bend projects beyond the
    // end of either element that meets there, and without it the carrier swapped
    // between the two on every round (a cycle of two that never converged, seen at the
    // stitch's tightening); within it the point stays on its element and is measured
    // across that element's line, continued by at most a tenth of an element. A point
    // at the inside of a bend (beyond both ends towards each other) would swing back and
    // forth too: the walk never turns round.
    constexpr double slack     = 0.1;
    int              last_step = 0;
    for (std::size_t walked = 0; walked <= n; ++walked)
      {
        xi = along(e);
        if (xi > 1 + slack && e + 1 < n && last_step >= 0)
          {
            ++e;
            last_step = 1;
          }
        else if (xi < -slack && e > 0 && last_step <= 0)
          {
            --e;
            last_step = -1;
          }
        else
          break;
      }
    // kept inside the element, so that the carrier names it (thread_element() of an
    // element's end names the next one): a point beyond an end loads that end's node
    return L + thread_s[e] + std::clamp(xi, 1e-9, 1 - 1e-9) * (thread_s[e + 1] - thread_s[e]);
  }

  bool
  TissueNeedle::follow_thread(const std::vector<Point<3>> &x)
  {
    const std::size_t offset  = touch_index() == 0 ? 1 : 0;
    bool              changed = false;
    for (std::size_t j = 0; j < pierce.size(); ++j)
      if (on_thread(pierce[j]))
        {
          const double next   = carried_to(pierce[j], x[offset + j]);
          const double L      = needle.length();
          changed             = changed || thread_element(next - L).first != thread_element(pierce[j].carrier - L).first;
          pierce[j].carrier   = next;
        }
    return changed;
  }

  double
  TissueNeedle::constraint_gap(const std::vector<Point<3>> &x) const
  {
    const std::size_t offset = touch_index() == 0 ? 1 : 0;
    double            gap    = 0;
    for (std::size_t j = 0; j < pierce.size(); ++j)
      gap = std::max(gap, across_curve(pierce[j], x[offset + j]).across.norm());
    return gap;
  }

  double
  TissueNeedle::update_multipliers(const std::vector<Point<3>> &x)
  {
    const double      gap    = constraint_gap(x);
    const std::size_t offset = touch_index() == 0 ? 1 : 0;
    for (std::size_t j = 0; j < pierce.size(); ++j)
      {
        const auto [zeta, t, across] = across_curve(pierce[j], x[offset + j]);
        const Tensor<1, 3> next      = pierce[j].multiplier + prm.transverse_stiffness * across;
        pierce[j].multiplier         = next - (next * t) * t;
      }
    return gap;
  }

  void
  TissueNeedle::add_pierce_point(const Point<3> &X, const double anchor)
  {
    AccuratePiercePoint p;
    p.X      = X;
    p.anchor  = anchor;
    p.carrier = anchor;
    p.zeta    = anchor;
    auto at   = std::upper_bound(pierce.begin(), pierce.end(), anchor,
                               [](const double a, const AccuratePiercePoint &q) { return a < q.anchor; });
    pierce.insert(at, p);
    rebuild_points();
  }

  void
  TissueNeedle::force(const std::size_t k, const Point<3> &x, Tensor<1, 3> &f, Tensor<2, 3> &df_dx) const
  {
    if (touch_index() == 0 && k == 0)
      {
        const auto        *touch = puncture->touch();
        const Tensor<1, 3> n     = tensor(touch->normal);
        const Tensor<1, 3> tip   = tensor(needle.tip(current));
        const double pen = touch->exit ? (tip - Tensor<1, 3>(x)) * n : (Tensor<1, 3>(x) - tip) * n;
        const Tensor<1, 3> push = touch->exit ? n : -n;
        f                       = prm.puncture.stiffness * std::max(0.0, pen) * push;
        df_dx = pen > 0 ? Tensor<2, 3>(-prm.puncture.stiffness * outer_product(n, n)) : Tensor<2, 3>();
        return;
      }
    f = pierce_force(pierce[k - (touch_index() == 0 ? 1 : 0)], x, nullptr, nullptr, &df_dx);
  }

  double
  TissueNeedle::touch_force(const std::vector<Point<3>> &x) const
  {
    if (touch_index() != 0)
      return 0;
    return puncture->normal_force(needle.tip(current), eigen(x[0]));
  }

  bool
  TissueNeedle::accept_step(const std::vector<Point<3>> &x)
  {
    bool              changed = false;
    const std::size_t offset  = touch_index() == 0 ? 1 : 0;
    const double      step    = time - last_time;
    std::vector<bool> on_needle;
    for (const auto &p : pierce)
      on_needle.push_back(p.anchor <= needle.length());
    // friction anchors by the return mapping at the converged positions
    for (std::size_t j = 0; j < pierce.size(); ++j)
      {
        auto          &p = pierce[j];
        FrictionResult r;
        double         N = 0;
        pierce_force(p, x[offset + j], &r, &N, nullptr);
        p.zeta       = projection(p, x[offset + j]);
        if (on_thread(p))
          p.carrier = carried_to(p, x[offset + j]);
        p.slip_speed = step > 0 ? (r.anchor - p.anchor) / step : 0;
        p.anchor     = r.anchor;
        p.normal     = N;
        p.friction   = r.force;
        p.slipping   = r.slipping;
      }
    // the touch: a puncture at the threshold turns its point into a pierce point at the
    // tip end of the thread
    touch_value = touch_force(x);
    const Eigen::Vector3d tip = needle.tip(current);
    if (puncture->accept(time, touch_value, tip))
      {
        AccuratePiercePoint p;
        p.X      = point(puncture->last_touch().reference);
        p.anchor = needle.closest(current, eigen(x[0]));
        p.zeta   = p.anchor;
        p.exit   = puncture->last_touch().exit;
        pierce.insert(pierce.begin(), p);
        on_needle.insert(on_needle.begin(), true);
        changed = true;
      }
    // order along needle and thread; a point that reaches the end of the curve (the
    // swage without a thread) is free
    std::vector<double> anchors;
    for (const auto &p : pierce)
      anchors.push_back(p.anchor);
    const double end = curve_length();
    if (!anchors.empty())
      {
        keep_order(anchors, prm.spacing, 0, end);
        for (std::size_t j = 0; j < pierce.size(); ++j)
          {
            if (thread && on_needle[j] && anchors[j] > needle.length())
              {
                log.push_back({"onto_suture", time, eigen(pierce[j].X), pierce[j].normal});
                pierce[j].carrier = anchors[j];
              }
            pierce[j].anchor = anchors[j];
          }
      }
    for (std::size_t j = pierce.size(); j-- > 0;)
      if (pierce[j].anchor >= end * (1 - 1e-9))
        {
          log.push_back({"released", time, eigen(pierce[j].X), pierce[j].normal});
          pierce.erase(pierce.begin() + j);
          changed = true;
        }
    last_time = time;
    if (changed)
      rebuild_points();
    return changed;
  }

  std::vector<PunctureEvent>
  TissueNeedle::all_events() const
  {
    std::vector<PunctureEvent> all = puncture->events();
    all.insert(all.end(), log.begin(), log.end());
    std::stable_sort(all.begin(), all.end(), [](const auto &a, const auto &b) { return a.time < b.time; });
    return all;
  }

  std::pair<Tensor<1, 3>, Tensor<1, 3>>
  TissueNeedle::needle_load(const std::vector<Point<3>> &x, const rod::Vec6 &swage_pull) const
  {
    const Tensor<1, 3> origin = tensor(current.position);
    Tensor<1, 3>       force  = tensor(swage_pull.head<3>());
    Tensor<1, 3>       torque = tensor(swage_pull.tail<3>()) +
                          cross_product_3d(tensor(needle.swage(current)) - origin, force);
    for (std::size_t k = 0; k < x.size(); ++k)
      {
        const std::size_t offset = touch_index() == 0 ? 1 : 0;
        const bool        tip    = touch_index() == 0 && k == 0;
        // points on the thread load the suture, not the needle
        if (!tip && on_thread(pierce[k - offset]))
          continue;
        Tensor<1, 3> f;
        Tensor<2, 3> unused;
        this->force(k, x[k], f, unused);
        const Tensor<1, 3> at = tip ? tensor(needle.tip(current)) : curve(pierce[k - offset].anchor).first;
        force -= f;
        torque -= cross_product_3d(at - origin, f);
      }
    return {force, torque};
  }

  std::vector<char>
  TissueNeedle::thread_nodes_in_tracts() const
  {
    std::vector<char> inside(thread ? thread_s.size() : 0, 0);
    for (std::size_t k = 0; k + 1 < pierce.size(); ++k)
      if (pierce[k].exit && !pierce[k + 1].exit)
        for (std::size_t i = 0; i < inside.size(); ++i)
          {
            const double zeta   = needle.length() + thread_s[i];
            const double margin = thread_s[std::min(i + 1, inside.size() - 1)] - thread_s[i > 0 ? i - 1 : 0];
            inside[i] = inside[i] || (zeta > pierce[k].anchor - margin && zeta < pierce[k + 1].anchor + margin);
          }
    return inside;
  }
} // namespace suturesim::coupling
