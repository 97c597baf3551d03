#include <suturesim/coupling/pierce_order.h>
#include <suturesim/mesh/spread_kernel.h>
#include <suturesim/realtime/needle_coupling.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace suturesim::realtime
{
  NeedleCoupling::NeedleCoupling(const System &s, const std::vector<mesh::Triangle> &surface,
                                 const tools::CurvedNeedle &geometry,
                                 const NeedleCouplingParameters &parameters, SutureModel *suture_model)
    : prm(parameters)
    , triangles(surface)
    , suture(s.suture)
    , needle(geometry)
    , puncture(parameters.puncture, surface, s.nodes.reference)
    , sys(s)
  {
    if (suture.size() >= 2)
      link = (s.nodes.reference.col(suture.begin + 1) - s.nodes.reference.col(suture.begin)).norm();
    // throws std::invalid_argument naming the choices for an unknown name
    model = PierceModel::Registry::instance().get(prm.pierce_model).create(ParameterValues());
    model->attach(suture_model, prm.project);
    if (prm.load_radius > 0)
      {
        // sampled at the nodes, the kernel needs a node within ρ of every surface point:
        // the nearest vertex of its triangle is no further than the longest edge
        double longest = 0;
        for (const auto &t : surface)
          for (unsigned i = 0; i < 3; ++i)
            longest = std::max(longest, (s.nodes.reference.col(t[i]) - s.nodes.reference.col(t[(i + 1) % 3])).norm());
        if (prm.load_radius <= longest)
          throw ParameterError("Load radius", "the load radius " + std::to_string(prm.load_radius) +
                                                " m must exceed the tissue surface's longest edge, " +
                                                std::to_string(longest) +
                                                " m, in the realtime path (the kernel is sampled at the nodes)");
      }
    // the thread's nodes: the suture's, continued along the needle from the swage at the
    // same spacing (the needle's own length when there is no suture)
    thread_nodes.swage = needle.length();
    thread_nodes.link  = link > 0 ? link : needle.length();
    thread_nodes.first = -static_cast<long>(std::floor(needle.length() / thread_nodes.link + 1e-9));
    thread_nodes.last  = suture.size() >= 2 ? static_cast<long>(suture.size()) - 1 : 0;
    inside.assign(suture.size(), 0);
    // a pass makes two pierce points; room for a few stitches without allocating (a
    // point's own list of nodes is allocated once, when it is born)
    points.reserve(16);
    states.reserve(16);
    zeta_work.reserve(16);
    slip_work.reserve(16);
    taken_work.reserve(16);
    taken_force.reserve(16);
    taken_index.reserve(16);
    taken_slips.reserve(16);
  }

  void
  NeedleCoupling::set_pose(const tools::Pose &pose, const double t)
  {
    current_pose = pose;
    time         = t;
  }

  Vector3d
  NeedleCoupling::tissue_point(const PiercePoint &p, const Matrix3Xd &x) const
  {
    Vector3d point = p.offset;
    for (std::size_t j = 0; j < p.nodes.size(); ++j)
      point += p.weights[j] * x.col(p.nodes[j]);
    return point;
  }

  void
  NeedleCoupling::carry(PiercePoint &p, const coupling::SurfacePoint &at) const
  {
    const auto      &triangle = triangles[at.triangle];
    const Matrix3Xd &X        = sys.nodes.reference;
    Vector3d         origin   = Vector3d::Zero();
    for (unsigned i = 0; i < 3; ++i)
      origin += at.weights[i] * X.col(triangle[i]);
    // the constructor checked that the radius exceeds every surface edge, so the ball
    // holds at least the nearest vertex of the point's own triangle; should it not (or
    // without a radius), the point is the triangle's
    if (prm.load_radius > 0 && mesh::spread_weights(X, sys.nodes.mass, sys.tissue.begin, sys.tissue.end, origin,
                                                    prm.load_radius, p.nodes, p.weights))
      {
        if (prm.hidden)
          {
            // the share of the weights beyond the wound, as carried; when the load stops at
            // the wound, the kernel over the nodes in sight, renormalised (a point on a face
            // sees its own lip; with nothing in sight it is its triangle's, below)
            double      beyond = 0;
            double      kept   = 0;
            std::size_t m      = 0;
            for (std::size_t j = 0; j < p.nodes.size(); ++j)
              {
                const bool behind = prm.hidden(origin, X.col(p.nodes[j]));
                (behind ? beyond : kept) += p.weights[j];
                if (behind && !prm.load_across_wound)
                  continue;
                p.nodes[m]     = p.nodes[j];
                p.weights[m++] = p.weights[j];
              }
            p.nodes.resize(m);
            p.weights.resize(m);
            if (prm.load_across_wound)
              p.across_wound += beyond;
            else
              for (auto &w : p.weights)
                w /= kept;
          }
      }
    if (!p.nodes.empty())
      {
        p.offset = origin;
        for (std::size_t j = 0; j < p.nodes.size(); ++j)
          p.offset -= p.weights[j] * X.col(p.nodes[j]);
        return;
      }
    p.nodes.assign(triangle.begin(), triangle.end());
    p.weights.assign(at.weights.data(), at.weights.data() + 3);
  }

  void
  NeedleCoupling::gather_taken(const Matrix3Xd &x) const
  {
    taken_work.clear();
    taken_index.assign(points.size(), -1);
    const double L = needle.length();
    for (std::size_t k = 0; k < points.size(); ++k)
      if (taken(points[k]))
        {
          taken_index[k] = taken_work.size();
          taken_work.push_back({points[k].anchor - L, tissue_point(points[k], x)});
        }
  }

  NeedleCoupling::ThreadPoint
  NeedleCoupling::thread_at(const double zeta, const Matrix3Xd &x) const
  {
    ThreadPoint  at;
    const double L = needle.length();
    at.zeta        = zeta;
    if (zeta <= L || suture.size() < 2)
      {
        at.c = needle.point(current_pose, zeta);
        at.t = needle.tangent(current_pose, zeta);
        return at;
      }
    const double   u  = std::min((zeta - L) / link, double(suture.size() - 1) - 1e-12);
    at.on_suture      = true;
    at.k              = static_cast<std::uint32_t>(u);
    at.s              = u - at.k;
    const Vector3d a  = x.col(suture.begin + at.k), b = x.col(suture.begin + at.k + 1);
    at.c              = (1 - at.s) * a + at.s * b;
    const double l    = (a - b).norm();
    at.t              = l > 0 ? Vector3d((a - b) / l) : needle.tangent(current_pose, L);
    return at;
  }

  void
  NeedleCoupling::detect(const Matrix3Xd &x)
  {
    puncture.update(time, needle.tip(current_pose), needle.tangent(current_pose, 0), x);
    for (auto &p : points)
      p.at = thread_at(p.anchor, x);
  }

  Vector3d
  NeedleCoupling::pierce_force(const PiercePoint &p, const Matrix3Xd &x,
                               coupling::FrictionResult *friction, double *normal) const
  {
    const Vector3d d       = tissue_point(p, x) - p.at.c;
    const Vector3d d_perp  = d - d.dot(p.at.t) * p.at.t;
    const Vector3d f_perp  = -prm.transverse_stiffness * d_perp;
    const double   N       = prm.friction.grip + f_perp.norm();
    // ζ of the tissue point, to first order along the tangent from the located point
    const double zeta = p.at.zeta - d.dot(p.at.t);
    const auto   r    = model->tangential(prm.friction, zeta, p.anchor, N);
    if (friction)
      *friction = r;
    if (normal)
      *normal = N;
    // the generalised force f_ζ acts along dx/dζ = −t
    return f_perp - r.force * p.at.t;
  }

  void
  NeedleCoupling::distribute(const PiercePoint &p, const Vector3d &force, Matrix3Xd &f) const
  {
    for (std::size_t j = 0; j < p.nodes.size(); ++j)
      f.col(p.nodes[j]) += p.weights[j] * force;
    if (p.at.on_suture)
      {
        f.col(suture.begin + p.at.k) -= (1 - p.at.s) * force;
        f.col(suture.begin + p.at.k + 1) -= p.at.s * force;
      }
  }

  void
  NeedleCoupling::add_forces(const Matrix3Xd &x, Matrix3Xd &f) const
  {
    if (const auto *touch = puncture.touch())
      {
        const double   F     = puncture.normal_force(needle.tip(current_pose), puncture.position(touch->point, x));
        const Vector3d force = F * puncture.push_direction();
        const auto    &tri   = triangles[touch->point.triangle];
        for (unsigned i = 0; i < 3; ++i)
          f.col(tri[i]) += touch->point.weights[i] * force;
      }
    gather_taken(x);
    if (!taken_work.empty())
      model->taken_forces(sys, x, taken_work, taken_force);
    for (std::size_t k = 0; k < points.size(); ++k)
      {
        const auto &p = points[k];
        if (taken_index[k] >= 0)
          {
            // the model's force acts on the tissue point alone
            const Vector3d &force = taken_force[taken_index[k]];
            for (std::size_t j = 0; j < p.nodes.size(); ++j)
              f.col(p.nodes[j]) += p.weights[j] * force;
          }
        else
          distribute(p, pierce_force(p, x, nullptr, nullptr), f);
      }
  }

  std::optional<double>
  NeedleCoupling::energy(const Matrix3Xd &x) const
  {
    double e = 0;
    if (const auto *touch = puncture.touch(); touch != nullptr && prm.puncture.stiffness > 0)
      {
        const double F = puncture.normal_force(needle.tip(current_pose), puncture.position(touch->point, x));
        e += 0.5 * F * F / prm.puncture.stiffness;
      }
    for (const auto &p : points)
      {
        if (taken(p)) // the model's (seed 002's soft constraints): no potential
          return std::nullopt;
        const std::uint32_t a = suture.begin + p.at.k;
        const Vector3d      c = p.at.on_suture ? Vector3d((1 - p.at.s) * x.col(a) + p.at.s * x.col(a + 1)) : p.at.c;
        const Vector3d      d = tissue_point(p, x) - c;
        const Vector3d d_perp = d - d.dot(p.at.t) * p.at.t;
        e += 0.5 * prm.transverse_stiffness * d_perp.squaredNorm();
        const double zeta = p.at.zeta - d.dot(p.at.t);
        const auto   r    = model->tangential(prm.friction, zeta, p.anchor,
                                              prm.friction.grip + prm.transverse_stiffness * d_perp.norm());
        if (!r.slipping)
          e += 0.5 * prm.friction.stiffness * (zeta - p.anchor) * (zeta - p.anchor);
        else if (r.force != 0)
          return std::nullopt;
      }
    return e;
  }

  void
  NeedleCoupling::reset_multipliers()
  {
    touch_lambda = 0;
    for (auto &p : points)
      p.lambda_n = p.lambda_t = 0;
  }

  double
  NeedleCoupling::correct(PiercePoint &p, const Vector3d &n, const double C, const double alpha_tilde,
                          double &lambda, const double limit, Matrix3Xd &x, const VectorXd &w) const
  {
    double w_tissue = 0; // inverse mass of the tissue point p = Σ wᵢ xᵢ
    for (std::size_t j = 0; j < p.nodes.size(); ++j)
      w_tissue += p.weights[j] * p.weights[j] * w[p.nodes[j]];
    // Mass scaling: a suture node is some 300 times lighter than a tissue node, and a
    // few sweeps of a constraint between them throw the suture about (measured: the
    // anchor then oscillates by millimetres from step to step). Within this constraint
    // the suture nodes' inverse masses are capped at prm.mass_ratio times the tissue
    // point's — the corrections are shared as if the suture were that heavy, the
    // multipliers (forces) stay equal and opposite.
    const double        cap = prm.mass_ratio * w_tissue;
    const std::uint32_t a = suture.begin + p.at.k, b = a + 1;
    const double        w_a = p.at.on_suture ? std::min(w[a], cap) : 0.0;
    const double        w_b = p.at.on_suture ? std::min(w[b], cap) : 0.0;
    double denominator = alpha_tilde + w_tissue;
    if (p.at.on_suture)
      denominator += (1 - p.at.s) * (1 - p.at.s) * w_a + p.at.s * p.at.s * w_b;
    if (!(denominator > 0))
      return 0;
    double d_lambda = (-C - alpha_tilde * lambda) / denominator;
    if (std::isfinite(limit))
      {
        // keep |λ| within the limit, but never by a correction against the constraint's
        // own direction: the limit may shrink between sweeps (it follows λ_n), and
        // pulling λ back to it would throw the light suture nodes (w ≈ 4e7 1/kg) far
        const double clamped = std::clamp(lambda + d_lambda, -limit, limit) - lambda;
        d_lambda             = clamped * d_lambda > 0 ? clamped : 0.0;
      }
    lambda += d_lambda;
    for (std::size_t j = 0; j < p.nodes.size(); ++j)
      x.col(p.nodes[j]) += w[p.nodes[j]] * p.weights[j] * d_lambda * n;
    if (p.at.on_suture)
      {
        x.col(a) -= w_a * (1 - p.at.s) * d_lambda * n;
        x.col(b) -= w_b * p.at.s * d_lambda * n;
      }
    return d_lambda;
  }

  void
  NeedleCoupling::project(Matrix3Xd &x, const VectorXd &w, const double dt)
  {
    const double inv_dt2 = 1 / (dt * dt);
    if (const auto *touch = puncture.touch())
      {
        // unilateral: the touched point stays on its side of the tip, C ≥ 0
        const auto    &tri = triangles[touch->point.triangle];
        const Vector3d n   = touch->exit ? touch->normal : Vector3d(-touch->normal);
        const Vector3d tip = needle.tip(current_pose);
        const Vector3d xm  = puncture.position(touch->point, x);
        const double   C   = (xm - tip).dot(n) >= 0 ? 0.0 : (xm - tip).dot(n);
        // the tissue point is pushed along n: C = (x_m − tip)·n ≥ 0 with ∇C = n
        const double alpha = inv_dt2 / prm.puncture.stiffness;
        double       den   = alpha;
        for (unsigned i = 0; i < 3; ++i)
          den += touch->point.weights[i] * touch->point.weights[i] * w[tri[i]];
        if (C < 0 && den > 0)
          {
            const double d_lambda = std::max((-C - alpha * touch_lambda) / den, -touch_lambda);
            touch_lambda += d_lambda;
            for (unsigned i = 0; i < 3; ++i)
              x.col(tri[i]) += w[tri[i]] * touch->point.weights[i] * d_lambda * n;
          }
      }
    const double alpha_n = inv_dt2 / prm.transverse_stiffness;
    const double alpha_t = prm.friction.stiffness > 0 ? inv_dt2 / prm.friction.stiffness : 0;
    for (auto &p : points)
      {
        // transverse (node-path): back onto the thread
        const Vector3d d      = tissue_point(p, x) - p.at.c;
        const Vector3d d_perp = d - d.dot(p.at.t) * p.at.t;
        const double   C      = d_perp.norm();
        if (C > 0)
          {
            p.normal_direction = d_perp / C;
            correct(p, p.normal_direction, C, alpha_n, p.lambda_n, std::numeric_limits<double>::infinity(), x, w);
          }
        // along the thread: stick to the anchor within the Coulomb limit
        if (prm.friction.mu > 0 && prm.friction.stiffness > 0)
          {
            const Vector3d dd    = tissue_point(p, x) - p.at.c;
            const double   zeta  = p.at.zeta - dd.dot(p.at.t);
            // the limit in impulse units: μ (N₀ dt² + |λ⊥|)
            const double   limit = model->capped_stick()
                                       ? coupling::friction_limit(prm.friction,
                                                                  prm.friction.grip * dt * dt + std::abs(p.lambda_n))
                                       : std::numeric_limits<double>::infinity();
            correct(p, -p.at.t, zeta - p.anchor, alpha_t, p.lambda_t, limit, x, w);
          }
      }
    last_dt = dt;
  }

  void
  NeedleCoupling::add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, const double dt) const
  {
    if (!prm.project)
      {
        add_forces(x, f);
        return;
      }
    const double inv_dt2 = 1 / (dt * dt);
    if (const auto *touch = puncture.touch())
      {
        const auto    &tri = triangles[touch->point.triangle];
        const Vector3d n   = touch->exit ? touch->normal : Vector3d(-touch->normal);
        for (unsigned i = 0; i < 3; ++i)
          f.col(tri[i]) += touch->point.weights[i] * touch_lambda * inv_dt2 * n;
      }
    for (const auto &p : points)
      distribute(p, (p.lambda_n * p.normal_direction - p.lambda_t * p.at.t) * inv_dt2, f);
  }

  void
  NeedleCoupling::add_stiffness(Matrix6d &K, const Vector3d &centre) const
  {
    if (puncture.pressing())
      add_point_stiffness(K, needle.tip(current_pose) - centre, prm.puncture.stiffness);
    for (const auto &p : points)
      if (!taken(p) && !p.at.on_suture)
        add_point_stiffness(K, p.at.c - centre, prm.transverse_stiffness + prm.friction.stiffness);
      else if (!taken(p) && prm.geometric_suture) // its stick, through the thread
        add_point_stiffness(K, needle.swage(current_pose) - centre, prm.friction.stiffness);
  }

  std::pair<Vector3d, Vector3d>
  NeedleCoupling::needle_load(const Matrix3Xd &x, const Vector3d &origin, const double dt, const bool free) const
  {
    Vector3d     force = Vector3d::Zero(), torque = Vector3d::Zero();
    const auto   add   = [&](const Vector3d &at, const Vector3d &f) {
      force += f;
      torque += (at - origin).cross(f);
    };
    const double   inv_dt2 = 1 / (dt * dt);
    const Vector3d tip     = needle.tip(current_pose);
    if (const auto *touch = puncture.touch())
      {
        const double F = prm.project ? touch_lambda * inv_dt2
                                     : puncture.normal_force(tip, puncture.position(touch->point, x));
        add(tip, -F * puncture.push_direction());
      }
    for (const auto &p : points)
      if (!taken(p) && (!p.at.on_suture || prm.geometric_suture))
        {
          const Vector3d on_tissue = prm.project
                                       ? Vector3d((p.lambda_n * p.normal_direction - p.lambda_t * p.at.t) * inv_dt2)
                                       : pierce_force(p, x, nullptr, nullptr);
          if (p.at.on_suture && free) // its pull along the thread, as tension at the swage
            add(needle.swage(current_pose), -on_tissue.dot(p.at.t) * needle.tangent(current_pose, needle.length()));
          else
            add(p.at.c, -on_tissue);
        }
    return {force, torque};
  }

  bool
  NeedleCoupling::make_vertex(coupling::SurfacePoint &point, const Matrix3Xd &x)
  {
    if (!subdivision || (point.weights.array() == 1).any())
      return false;
    const Vector3d position = puncture.position(point, x);
    if (subdivision(point.triangle, point.weights) < 0)
      return false;
    // the triangle keeps its index and has the new vertex first
    point.weights = Vector3d(1, 0, 0);
    puncture.surface_changed(x);
    events_on_thread.push_back({"subdivision", time, position, 0});
    return true;
  }

  void
  NeedleCoupling::after_step(Nodes &nodes)
  {
    const Matrix3Xd &x = nodes.x;
    accept_touch(x);
    const double end = settle_anchors(x, time - last_time);
    // order along the thread, between the tip and the thread's far end
    if (!zeta_work.empty())
      {
        coupling::keep_order(zeta_work, model->order_gap(prm.spacing), 0, end);
        for (std::size_t k = 0; k < points.size(); ++k)
          points[k].anchor = zeta_work[k];
      }
    for (auto &p : points)
      p.at = thread_at(p.anchor, x);
    // the accepted points the model has taken over, for the suture's next update
    gather_taken(x);
    model->taken_accepted(taken_work);
    record_states(x);
    last_time = time;
  }

  void
  NeedleCoupling::accept_touch(const Matrix3Xd &x)
  {
    const Vector3d tip = needle.tip(current_pose);
    // the touch: its force decides the puncture
    double F = 0;
    if (const auto *touch = puncture.touch())
      F = prm.project && last_dt > 0 ? touch_lambda / (last_dt * last_dt)
                                     : puncture.normal_force(tip, puncture.position(touch->point, x));
    last_touch_force = F;
    if (puncture.accept(time, F, tip))
      {
        // a touch that punctured in the step it began in is subdivided now
        coupling::SurfacePoint at = puncture.last_touch().point;
        make_vertex(at, x);
        const auto &touch = puncture.last_touch();
        PiercePoint p;
        carry(p, at);
        // the stick starts where the point projects on the needle now
        p.anchor = model->first_anchor(needle.closest(current_pose, tissue_point(p, x)), thread_nodes);
        p.at     = thread_at(p.anchor, x);
        p.exit   = touch.exit;
        p.surface_normal = touch.normal;
        // the newest point is nearest the tip: first in thread order
        points.insert(points.begin(), p);
      }
    // seed 002: a new touch makes its point a vertex, pressed from the next step on
    if (const auto *touch = puncture.touch())
      {
        coupling::SurfacePoint at = touch->point;
        if (make_vertex(at, x))
          puncture.rename_touch(at);
      }
  }

  double
  NeedleCoupling::settle_anchors(const Matrix3Xd &x, const double step)
  {
    zeta_work.clear();
    slip_work.clear();
    states.resize(points.size());
    for (auto &p : points)
      p.at = thread_at(p.anchor, x);
    gather_taken(x);
    if (!taken_work.empty())
      model->taken_slip(sys, x, taken_work, prm.friction, taken_slips);
    for (std::size_t k = 0; k < points.size(); ++k)
      {
        auto  &p = points[k];
        double N = 0;
        if (taken_index[k] >= 0)
          {
            // the model's slip of a point it has taken over
            const auto &slip = taken_slips[taken_index[k]];
            auto       &st   = states[k];
            st.slip_speed    = step > 0 ? slip.slip / step : 0;
            st.slipping      = slip.slipping;
            st.normal        = N = slip.normal;
            st.friction      = slip.friction;
            p.anchor += slip.slip;
          }
        else
          {
            // the anchor of the accepted state is the model's (return mapping, or seed
            // 001's node slip) at the end-of-step positions, in both modes (under XPBD
            // the stick multiplier was clamped to the Coulomb limit, but a few
            // iterations may leave a violation whose elastic force k_t (ζ − ζ_a) exceeds
            // μN: that is slip, and the anchor must follow)
            pierce_force(p, x, nullptr, &N);
            const Vector3d d = tissue_point(p, x) - p.at.c;
            slip_work.push_back({p.anchor, p.at.zeta - d.dot(p.at.t), N, false, 0});
          }
        if ((taken_index[k] >= 0 || p.at.on_suture) && !p.passed_swage)
          {
            p.passed_swage = true;
            events_on_thread.push_back({"onto_suture", time, tissue_point(p, x), N});
          }
        zeta_work.push_back(p.anchor);
      }
    if (!slip_work.empty())
      {
        model->settle(slip_work, prm.friction, thread_nodes);
        std::size_t j = 0;
        for (std::size_t k = 0; k < points.size(); ++k)
          if (taken_index[k] < 0)
            {
              const auto &r    = slip_work[j++];
              auto       &s    = states[k];
              s.slip_speed     = step > 0 ? (r.anchor - points[k].anchor) / step : 0;
              s.slipping       = r.slipping;
              s.normal         = r.normal;
              s.friction       = r.friction;
              points[k].anchor = zeta_work[k] = r.anchor;
            }
      }
    // a point that reached the end of the thread (the swage without a suture, or the
    // suture's far end) is free: the thread has left its hole
    const double end = needle.length() + link * (suture.size() > 0 ? suture.size() - 1 : 0);
    for (std::size_t k = points.size(); k-- > 0;)
      if (points[k].anchor >= end * (1 - 1e-9))
        {
          events_on_thread.push_back({"released", time, tissue_point(points[k], x), states[k].normal});
          points.erase(points.begin() + k);
          states.erase(states.begin() + k);
          zeta_work.erase(zeta_work.begin() + k);
        }
    return end;
  }

  void
  NeedleCoupling::record_states(const Matrix3Xd &x)
  {
    std::fill(inside.begin(), inside.end(), 0);
    for (std::size_t k = 0; k < points.size(); ++k)
      {
        auto          &s = states[k];
        const Vector3d d = tissue_point(points[k], x) - points[k].at.c;
        s.zeta           = points[k].anchor - d.dot(points[k].at.t);
        s.anchor         = points[k].anchor;
        s.on_suture      = points[k].at.on_suture;
        s.exit           = points[k].exit;
        s.position       = tissue_point(points[k], x);
        s.reference      = tissue_point(points[k], sys.nodes.reference);
        s.surface_normal = points[k].surface_normal;
        s.across_wound   = points[k].across_wound;
        // thread between an exit point and the next entry point further along it lies
        // inside the tissue
        if (points[k].exit && k + 1 < points.size() && !points[k + 1].exit)
          for (std::uint32_t i = 0; i < suture.size(); ++i)
            {
              const double zeta = needle.length() + link * i;
              inside[i] = inside[i] || (zeta > points[k].anchor - link && zeta < points[k + 1].anchor + link);
            }
      }
  }

  Vector3d
  NeedleCoupling::tissue_force(const std::size_t k) const
  {
    const auto &p = points[k];
    if (taken_index[k] >= 0) // the model's force, as add_forces() last applied it
      return std::size_t(taken_index[k]) < taken_force.size() ? taken_force[taken_index[k]] : Vector3d::Zero();
    if (prm.project)
      return last_dt > 0 ? Vector3d((p.lambda_n * p.normal_direction - p.lambda_t * p.at.t) / (last_dt * last_dt))
                         : Vector3d::Zero();
    return pierce_force(p, sys.nodes.x, nullptr, nullptr);
  }

  void
  NeedleCoupling::tear_free(const std::size_t k)
  {
    events_on_thread.push_back({"torn_free", time, states[k].position, tissue_force(k).norm()});
    points.erase(points.begin() + k);
    states.erase(states.begin() + k);
    if (k < taken_index.size())
      taken_index.erase(taken_index.begin() + k);
    if (k < zeta_work.size())
      zeta_work.erase(zeta_work.begin() + k);
  }

  void
  NeedleCoupling::move_into(const std::size_t k, const std::size_t onto)
  {
    events_on_thread.push_back({"torn_into_hole", time, states[k].position, tissue_force(k).norm()});
    points[k].nodes          = points[onto].nodes;
    points[k].weights        = points[onto].weights;
    points[k].offset         = points[onto].offset;
    points[k].surface_normal = points[onto].surface_normal;
    points[k].across_wound   = points[onto].across_wound;
    states[k].reference      = states[onto].reference;
    states[k].position       = states[onto].position;
  }
} // namespace suturesim::realtime
