#include <suturesim/coupling/accurate/tissue_needle.h>
#include <suturesim/coupling/pierce_order.h>
#include <suturesim/io/state_json.h>
#include <suturesim/rod/rotation.h>

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

    /// Central-difference steps of the thread's tangents: positions (m), rotations (rad).
    constexpr double position_step = 1e-8, rotation_step = 1e-7;
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
  TissueNeedle::set_thread(const std::vector<rod::Vec3> *nodes, std::vector<double> element_lengths,
                           const std::vector<rod::Quat> *rotations)
  {
    thread.attach(nodes, element_lengths, rotations);
  }

  double
  TissueNeedle::curve_length() const
  {
    return needle.length() + (thread.attached() ? thread.length() : 0.0);
  }

  std::pair<Tensor<1, 3>, Tensor<1, 3>>
  TissueNeedle::curve(const double zeta) const
  {
    if (!thread.attached() || zeta <= needle.length())
      return {tensor(needle.point(current, zeta)), tensor(needle.tangent(current, zeta))};
    const auto [e, xi]     = thread.element(zeta - needle.length());
    const HermiteSegment h = thread.segment(e);
    return {tensor(h.at(xi)), tensor(-h.rate(xi).normalized())};
  }

  TissueNeedle::Offset
  TissueNeedle::across_element(const std::size_t e, const Eigen::Vector3d &x, const HermiteSegment &h,
                               const double u0) const
  {
    const double u = h.closest(x, u0);
    Offset       o;
    o.u                  = u;
    o.zeta               = needle.length() + thread.arc_length(e) + u * thread.element_length(e);
    o.tangent            = tensor(-h.rate(u).normalized());
    const Tensor<1, 3> d = tensor(x - h.at(u));
    o.across             = d - (d * o.tangent) * o.tangent;
    return o;
  }

  std::vector<std::size_t>
  TissueNeedle::thread_elements() const
  {
    std::vector<std::size_t> elements;
    for (const auto &p : pierce)
      if (on_thread(p))
        elements.push_back(thread.element(p.carrier - needle.length()).first);
    std::sort(elements.begin(), elements.end());
    elements.erase(std::unique(elements.begin(), elements.end()), elements.end());
    return elements;
  }

  std::vector<std::size_t>
  TissueNeedle::loaded_elements() const
  {
    std::vector<std::size_t> elements;
    for (const std::size_t e : thread_elements())
      {
        if (e > 0 && !thread_cut_at(e - 1))
          elements.push_back(e - 1);
        elements.push_back(e);
        if (e + 1 < thread.n_elements() && !thread_cut_at(e + 1))
          elements.push_back(e + 1);
      }
    std::sort(elements.begin(), elements.end());
    elements.erase(std::unique(elements.begin(), elements.end()), elements.end());
    return elements;
  }

  TissueNeedle::Offset
  TissueNeedle::measured_on(const std::size_t carrier, const double u0, const Eigen::Vector3d &x,
                            std::size_t &element) const
  {
    element        = carrier;
    const Offset o = across_element(carrier, x, thread.segment(carrier), u0);
    // past an end, on the neighbour's curve if the projection falls on it (where it
    // falls past the node on both, which the curves' differing curvatures allow in a
    // sliver at a bend's inside, on the carrier's curve continued)
    Offset     n;
    const auto beside = [&](const std::size_t k, const double from) {
      if (thread_cut_at(k))
        return false;
      n = across_element(k, x, thread.segment(k), from);
      return n.u >= 0 && n.u <= 1;
    };
    if ((o.u > 1 && carrier + 1 < thread.n_elements() && beside(carrier + 1, 0)) ||
        (o.u < 0 && carrier > 0 && beside(carrier - 1, 1)))
      {
        element = o.u > 1 ? carrier + 1 : carrier - 1;
        return n;
      }
    return o;
  }

  std::vector<std::size_t>
  TissueNeedle::thread_points() const
  {
    const std::size_t        offset = first_pierce_index();
    std::vector<std::size_t> indices;
    for (std::size_t j = 0; j < pierce.size(); ++j)
      if (on_thread(pierce[j]))
        indices.push_back(offset + j);
    return indices;
  }

  std::vector<TissueNeedle::ThreadPointState>
  TissueNeedle::thread_point_states(const std::vector<Point<3>> &x) const
  {
    const std::size_t             offset = first_pierce_index();
    std::vector<ThreadPointState> states;
    for (std::size_t j = 0; j < pierce.size(); ++j)
      if (on_thread(pierce[j]))
        {
          const auto [carrier, xi] = thread.element(pierce[j].carrier - needle.length());
          std::size_t      e;
          const Offset     o = measured_on(carrier, xi, eigen(x[offset + j]), e);
          FrictionResult   r;
          ThreadPointState s;
          pierce_force(pierce[j], o, &r, &s.normal);
          s.point    = offset + j;
          s.element  = e;
          s.u        = o.u;
          s.slip     = o.zeta - pierce[j].anchor;
          s.slipping = r.slipping;
          s.friction = r.force;
          s.across   = o.across.norm();
          states.push_back(s);
        }
    return states;
  }

  void
  TissueNeedle::thread_terms(const std::vector<Point<3>> &x, const std::size_t element,
                             Eigen::Matrix<double, 12, 1> &residual, Eigen::Matrix<double, 12, 12> *jacobian) const
  {
    const std::size_t offset = first_pierce_index();
    for (std::size_t j = 0; j < pierce.size(); ++j)
      {
        if (!on_thread(pierce[j]))
          continue;
        const auto [carrier, xi] = thread.element(pierce[j].carrier - needle.length());
        // measured on its carrier or a neighbour (measured_on()): the other points of
        // the loaded elements are passed over before any projection
        if (element + 1 < carrier || element > carrier + 1)
          continue;
        const Eigen::Vector3d xj = eigen(x[offset + j]);
        std::size_t           e;
        const double          u0 = measured_on(carrier, xi, xj, e).u;
        if (e != element)
          continue;
        AccuratePiercePoint   p  = pierce[j];
        // the point's force f on the tissue, measured across the element's curve with its
        // nodes somewhere, and f's reaction on those nodes at the curve's point c(u)
        // (HermiteSegment::reaction())
        const auto load = [&](const HermiteSegment &curve, FrictionResult *r_out, Offset *o_out) {
          const Offset       o = across_element(e, xj, curve, u0);
          const Tensor<1, 3> f = pierce_force(p, o, r_out, nullptr);
          if (o_out)
            *o_out = o;
          return curve.reaction(o.u, Eigen::Vector3d(f[0], f[1], f[2]));
        };
        const auto [xa, qa] = thread.node(e);
        const auto [xb, qb] = thread.node(e + 1);
        Offset         base;
        FrictionResult here;
        residual += load(thread.segment(xa, qa, xb, qb), &here, &base);
        if (!jacobian)
          continue;
        // differenced on the branch the law took here, unless one is held
        if (!p.branch)
          p.branch = FrictionBranch::of(here, base.zeta - p.anchor);
        for (unsigned c = 0; c < 12; ++c)
          {
            const bool   turn = c % 6 >= 3;
            const double h    = turn ? rotation_step : position_step;
            const auto   moved = [&](const double by) {
              rod::Vec3       ya = xa, yb = xb;
              rod::Quat       ra = qa, rb = qb;
              const rod::Vec3 v  = by * rod::Vec3::Unit(c % 3);
              rod::Vec3      &y  = c < 6 ? ya : yb;
              rod::Quat      &q  = c < 6 ? ra : rb;
              if (turn)
                q = rod::quaternion_exp(v) * q;
              else
                y += v;
              return load(thread.segment(ya, ra, yb, rb), nullptr, nullptr);
            };
            jacobian->col(c) += (moved(h) - moved(-h)) / (2 * h);
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
    puncture->update(t, needle.tip(pose), needle.tangent(pose, 0), surface);
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
    // on the thread, the carrier element's curve (extended)
    if (on_thread(p))
      return across_curve(p, x).zeta;
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
  TissueNeedle::projected_curve(const double zeta) const
  {
    const double end   = std::clamp(zeta, 0.0, needle.length());
    const auto [c, t]  = curve(end);
    return {c - (zeta - end) * t, t};
  }

  TissueNeedle::Offset
  TissueNeedle::across_curve(const AccuratePiercePoint &p, const Point<3> &x) const
  {
    if (on_thread(p))
      {
        const auto [carrier, xi] = thread.element(p.carrier - needle.length());
        std::size_t e;
        return measured_on(carrier, xi, eigen(x), e);
      }
    Offset o;
    o.zeta            = projection(p, x);
    const auto [c, t] = projected_curve(o.zeta);
    const Tensor<1, 3> d = Tensor<1, 3>(x) - c;
    o.tangent            = t;
    o.across             = d - (d * t) * t;
    return o;
  }

  Tensor<1, 3>
  TissueNeedle::pierce_force(const AccuratePiercePoint &p, const Offset &o, FrictionResult *r_out,
                             double *N_out) const
  {
    // the tie across the curve at the point's projection ζ, the friction along it by ζ − ζ_a
    const Tensor<1, 3> lambda = p.multiplier - (p.multiplier * o.tangent) * o.tangent;
    const Tensor<1, 3> f_perp = -(lambda + prm.transverse_stiffness * o.across);
    const double       N      = normal_force(prm.friction.grip, f_perp.norm(), prm.normal_smoothing).value;
    // the generalised force f_ζ acts along dx/dζ = −t
    const FrictionResult r = coulomb_friction(prm.friction, o.zeta, p.anchor, N, p.branch ? &*p.branch : nullptr);
    if (r_out)
      *r_out = r;
    if (N_out)
      *N_out = N;
    return f_perp - r.force * o.tangent;
  }

  Tensor<1, 3>
  TissueNeedle::pierce_force(const AccuratePiercePoint &p, const Point<3> &x, FrictionResult *r_out,
                             double *N_out, Tensor<2, 3> *df_dx) const
  {
    const Offset       o = across_curve(p, x);
    FrictionResult     r;
    const Tensor<1, 3> f = pierce_force(p, o, &r, N_out);
    if (r_out)
      *r_out = r;
    if (!df_dx)
      return f;
    if (on_thread(p))
      {
        // differenced on the branch the law took here (r), unless one is held
        AccuratePiercePoint q = p;
        q.branch              = p.branch ? *p.branch : FrictionBranch::of(r, o.zeta - p.anchor);
        for (unsigned k = 0; k < 3; ++k)
          {
            Point<3> plus = x, minus = x;
            plus[k] += position_step;
            minus[k] -= position_step;
            const Tensor<1, 3> rate = (pierce_force(q, across_curve(q, plus), nullptr, nullptr) -
                                       pierce_force(q, across_curve(q, minus), nullptr, nullptr)) /
                                      (2 * position_step);
            for (unsigned i = 0; i < 3; ++i)
              (*df_dx)[i][k] = rate[i];
          }
        return f;
      }
    // the curvature's part (|d_perp| / R against 1) is left out
    const Tensor<2, 3> ttT = outer_product(o.tangent, o.tangent);
    *df_dx                 = -prm.transverse_stiffness * (unit_symmetric_tensor<3>() - ttT);
    if (!r.slipping)
      *df_dx -= prm.friction.stiffness * ttT;
    return f;
  }

  double
  TissueNeedle::carried_to(const AccuratePiercePoint &p, const Point<3> &x) const
  {
    const double      L = needle.length();
    const std::size_t n = thread.n_elements();
    auto [e, xi]        = thread.element(p.carrier - L);
    const Eigen::Vector3d X = eigen(x);
    // u of x's projection on element k's curve (extended)
    const auto along = [&](const std::size_t k) { return across_element(k, X, thread.segment(k), 0.5).u; };
    // Walk while the projection lies beyond the element's ends by more than a tenth of
    // it. The slack is a dead zone, kept from the polyline (where a point at the outside
    // of a bend projects beyond the end of either element that meets there, and the
    // carrier swapped between the two on every round): within it the point stays on its
    // element, and is measured where the thread is, across the neighbour's curve
    // (measured_on()). The walk never turns round, so a point cannot swing back and
    // forth.
    constexpr double slack     = 0.1;
    int              last_step = 0;
    // nor does it pass a cut (cut_thread())
    for (std::size_t walked = 0; walked <= n; ++walked)
      {
        xi = along(e);
        if (xi > 1 + slack && e + 1 < n && !thread_cut_at(e + 1) && last_step >= 0)
          {
            ++e;
            last_step = 1;
          }
        else if (xi < -slack && e > 0 && !thread_cut_at(e - 1) && last_step <= 0)
          {
            --e;
            last_step = -1;
          }
        else
          break;
      }
    // kept inside the element, so that the carrier names it (ThreadCurve::element() of an
    // element's end names the next one); the point itself is measured and loaded where
    // it projects, past the end if it lies there (thread_terms())
    return L + thread.arc_length(e) + std::clamp(xi, 1e-9, 1 - 1e-9) * thread.element_length(e);
  }

  bool
  TissueNeedle::follow_thread(const std::vector<Point<3>> &x)
  {
    const std::size_t offset  = first_pierce_index();
    bool              changed = false;
    for (std::size_t j = 0; j < pierce.size(); ++j)
      if (on_thread(pierce[j]))
        {
          const double next   = carried_to(pierce[j], x[offset + j]);
          const double L      = needle.length();
          changed             = changed || thread.element(next - L).first != thread.element(pierce[j].carrier - L).first;
          pierce[j].carrier   = next;
        }
    return changed;
  }

  void
  TissueNeedle::hold_friction_branches(const std::vector<Point<3>> &x)
  {
    const std::size_t offset = first_pierce_index();
    for (std::size_t j = 0; j < pierce.size(); ++j)
      if (on_thread(pierce[j]))
        pierce[j].branch = branch_at(pierce[j], across_curve(pierce[j], x[offset + j]));
  }

  void
  TissueNeedle::release_friction_branches()
  {
    for (auto &p : pierce)
      p.branch.reset();
  }

  FrictionBranch
  TissueNeedle::branch_at(const AccuratePiercePoint &p, const Offset &o) const
  {
    if (p.branch)
      return *p.branch;
    FrictionResult r;
    pierce_force(p, o, &r, nullptr);
    return FrictionBranch::of(r, o.zeta - p.anchor);
  }

  double
  TissueNeedle::constraint_gap(const std::vector<Point<3>> &x) const
  {
    const std::size_t offset = first_pierce_index();
    double            gap    = 0;
    for (std::size_t j = 0; j < pierce.size(); ++j)
      gap = std::max(gap, across_curve(pierce[j], x[offset + j]).across.norm());
    return gap;
  }

  double
  TissueNeedle::update_multipliers(const std::vector<Point<3>> &x)
  {
    const double      gap    = constraint_gap(x);
    const std::size_t offset = first_pierce_index();
    for (std::size_t j = 0; j < pierce.size(); ++j)
      {
        const Offset       o    = across_curve(pierce[j], x[offset + j]);
        const Tensor<1, 3> next = pierce[j].multiplier + prm.transverse_stiffness * o.across;
        pierce[j].multiplier    = next - (next * o.tangent) * o.tangent;
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

  bool
  TissueNeedle::symmetric_at(const std::size_t k) const
  {
    const std::size_t offset = first_pierce_index();
    return k < offset || !on_thread(pierce[k - offset]) || symmetric_tangent();
  }

  void
  TissueNeedle::force(const std::size_t k, const Point<3> &x, Tensor<1, 3> &f, Tensor<2, 3> &df_dx) const
  {
    if (is_touch(k))
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
    f = pierce_force(pierce[k - first_pierce_index()], x, nullptr, nullptr, &df_dx);
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
    const std::size_t offset  = first_pierce_index();
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
            if (thread.attached() && on_needle[j] && anchors[j] > needle.length())
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
        const std::size_t offset = first_pierce_index();
        const bool        tip    = is_touch(k);
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
    std::vector<char> inside(thread.attached() ? thread.n_nodes() : 0, 0);
    for (std::size_t k = 0; k + 1 < pierce.size(); ++k)
      if (pierce[k].exit && !pierce[k + 1].exit)
        for (std::size_t i = 0; i < inside.size(); ++i)
          {
            const double zeta   = needle.length() + thread.arc_length(i);
            const double margin = thread.arc_length(std::min(i + 1, inside.size() - 1)) - thread.arc_length(i > 0 ? i - 1 : 0);
            inside[i] = inside[i] || (zeta > pierce[k].anchor - margin && zeta < pierce[k + 1].anchor + margin);
          }
    return inside;
  }

  nlohmann::json
  TissueNeedle::snapshot() const
  {
    nlohmann::json points = nlohmann::json::array(), events = nlohmann::json::array();
    for (const auto &p : pierce)
      points.push_back({{"X", io::triple(p.X)},
                        {"anchor", p.anchor},
                        {"carrier", p.carrier},
                        {"exit", p.exit},
                        {"multiplier", io::triple(p.multiplier)},
                        {"zeta", p.zeta},
                        {"normal", p.normal},
                        {"friction", p.friction},
                        {"slip_speed", p.slip_speed},
                        {"slipping", p.slipping}});
    for (const auto &e : log)
      events.push_back(event_state(e));
    return {{"puncture", puncture->snapshot()},
            {"pierce", points},
            {"events", events},
            {"pose", {{"position", io::triple(current.position)}, {"orientation", io::quaternion_array(current.orientation)}}},
            {"time", time},
            {"last_time", last_time},
            {"touch_value", touch_value}};
  }

  void
  TissueNeedle::restore(const nlohmann::json &j)
  {
    puncture->restore(j.at("puncture"));
    pierce.clear();
    for (const auto &p : j.at("pierce"))
      {
        AccuratePiercePoint a;
        a.X          = io::triple_as<dealii::Point<3>>(p.at("X"));
        a.anchor     = p.at("anchor").get<double>();
        a.carrier    = p.at("carrier").get<double>();
        a.exit       = p.at("exit").get<bool>();
        a.multiplier = io::triple_as<dealii::Tensor<1, 3>>(p.at("multiplier"));
        a.zeta       = p.at("zeta").get<double>();
        a.normal     = p.at("normal").get<double>();
        a.friction   = p.at("friction").get<double>();
        a.slip_speed = p.at("slip_speed").get<double>();
        a.slipping   = p.at("slipping").get<bool>();
        pierce.push_back(a);
      }
    log.clear();
    for (const auto &e : j.at("events"))
      log.push_back(event_from(e));
    current.position    = io::triple_as<Eigen::Vector3d>(j.at("pose").at("position"));
    current.orientation = io::quaternion(j.at("pose").at("orientation"));
    time                = j.at("time").get<double>();
    last_time           = j.at("last_time").get<double>();
    touch_value         = j.at("touch_value").get<double>();
    rebuild_points();
  }
} // namespace suturesim::coupling
