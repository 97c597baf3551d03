#include <suturesim/core/coulomb_law.h>
#include <suturesim/rod/contact_friction.h>

#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <limits>

namespace suturesim::rod
{
  namespace
  {
    /// dΔ/dx (3 × 12) of the closest points' vector Δ = p − q over the contact's four
    /// nodes (a, a + 1, b, b + 1): A + B du/dx. At fixed u = (s, t), Δ = Σ_k w_k x_k;
    /// B's columns b_j = ∂Δ/∂u_j = Σ_k c_jk x_k over the interior parameters (a clamped
    /// one stays at 0 or 1); du/dx = −(BᵀB)⁻¹ F_x from F = BᵀΔ = 0.
    Eigen::Matrix<double, 3, 12>
    closest_point_sensitivity(const ContactPair &c, const std::vector<Vec3> &x)
    {
      const std::array<double, 4> w{{1 - c.s, c.s, -(1 - c.t), -c.t}};
      const Vec3 delta = (1 - c.s) * x[c.a] + c.s * x[c.a + 1] - (1 - c.t) * x[c.b] - c.t * x[c.b + 1];
      std::array<Vec3, 2>                  b;
      std::array<std::array<double, 4>, 2> coefficient{};
      int                                  m = 0;
      if (c.s > 0 && c.s < 1)
        {
          b[m]           = x[c.a + 1] - x[c.a];
          coefficient[m] = {{-1, 1, 0, 0}};
          ++m;
        }
      if (c.t > 0 && c.t < 1)
        {
          b[m]           = x[c.b] - x[c.b + 1];
          coefficient[m] = {{0, 0, 1, -1}};
          ++m;
        }
      Eigen::Matrix<double, 3, 12> G;
      for (int n = 0; n < 4; ++n)
        G.block<3, 3>(0, 3 * n) = w[n] * Mat3::Identity();
      if (m == 0)
        return G;
      Eigen::MatrixXd BtB(m, m), Fx(m, 12);
      for (int i = 0; i < m; ++i)
        {
          for (int j = 0; j < m; ++j)
            BtB(i, j) = b[i].dot(b[j]);
          for (int n = 0; n < 4; ++n)
            Fx.block<1, 3>(i, 3 * n) = coefficient[i][n] * delta.transpose() + w[n] * b[i].transpose();
        }
      // the same test as the normal contact's sensitivity (rod_model.cc): parallel
      // segments have no unique closest points, and their parameters no derivative
      const Eigen::FullPivLU<Eigen::MatrixXd> lu(BtB);
      if (!lu.isInvertible())
        return G;
      const Eigen::MatrixXd U = -lu.solve(Fx);
      for (int j = 0; j < m; ++j)
        G += b[j] * U.row(j);
      return G;
    }
  } // namespace

  void
  FrictionAnchor::write(std::vector<double> &out) const
  {
    out.insert(out.end(), {double(a), double(b), s, t, sigma_a, sigma_b});
    for (const auto *v : {&nu_a[0], &nu_a[1], &nu_b[0], &nu_b[1], &normal, &slip})
      out.insert(out.end(), {(*v)[0], (*v)[1], (*v)[2]});
  }

  FrictionAnchor
  FrictionAnchor::read(const double *in)
  {
    FrictionAnchor h;
    // a segment index out of range (a damaged record) becomes one no rod has
    const auto index = [](const double v) {
      return v >= 0 && v < 4e9 ? static_cast<std::uint32_t>(v) : std::numeric_limits<std::uint32_t>::max() - 1;
    };
    h.a       = index(in[0]);
    h.b       = index(in[1]);
    h.s       = in[2];
    h.t       = in[3];
    h.sigma_a = in[4];
    h.sigma_b = in[5];
    std::size_t k = 6;
    for (auto *v : {&h.nu_a[0], &h.nu_a[1], &h.nu_b[0], &h.nu_b[1], &h.normal, &h.slip})
      {
        *v = Vec3(in[k], in[k + 1], in[k + 2]);
        k += 3;
      }
    return h;
  }

  void
  ContactFriction::setup(const ContactParameters &parameters, const std::vector<double> &rest_arc)
  {
    mu        = parameters.enabled ? parameters.friction : 0.0;
    stiffness = parameters.stick_stiffness;
    radius    = parameters.radius;
    arc       = rest_arc;
    double longest = 0;
    for (std::size_t e = 0; e + 1 < arc.size(); ++e)
      longest = std::max(longest, arc[e + 1] - arc[e]);
    match = 2 * longest + 4 * radius;
    history.clear();
  }

  FrictionTerm
  ContactFriction::evaluate(const ContactPair &c, const std::vector<Vec3> &x, const std::vector<Quat> &q,
                            const bool with_jacobian) const
  {
    FrictionTerm t;
    t.sigma_a = arc[c.a] + c.s * (arc[c.a + 1] - arc[c.a]);
    t.sigma_b = arc[c.b] + c.t * (arc[c.b + 1] - arc[c.b]);
    t.node    = {{c.a, c.a, c.b, c.b, c.a, c.a + 1, c.b, c.b + 1}};
    if (!active())
      return t;
    const FrictionAnchor *h       = nullptr;
    double                nearest = std::numeric_limits<double>::infinity();
    for (const auto &candidate : history)
      {
        const double da = std::abs(t.sigma_a - candidate.sigma_a), db = std::abs(t.sigma_b - candidate.sigma_b);
        if (da <= match && db <= match && da + db < nearest)
          {
            nearest = da + db;
            h       = &candidate;
          }
      }
    if (h == nullptr)
      return t;
    t.anchored = true;
    t.node[0]  = h->a;
    t.node[1]  = h->a + 1;
    t.node[2]  = h->b;
    t.node[3]  = h->b + 1;
    // the anchored surface points' slots: weight (signed: + on a, − on b) and the
    // surface vector r R ν of each node
    const std::array<double, 4> weight{{1 - h->s, h->s, -(1 - h->t), -h->t}};
    std::array<Vec3, 4>         arm;
    const std::array<const Vec3 *, 4> nu{{&h->nu_a[0], &h->nu_a[1], &h->nu_b[0], &h->nu_b[1]}};
    Vec3 gap = Vec3::Zero(); // P_a − P_b
    for (int k = 0; k < 4; ++k)
      {
        arm[k] = radius * (q[t.node[k]] * *nu[k]);
        gap += weight[k] * (x[t.node[k]] + arm[k]);
      }
    const Mat3 Pc = Mat3::Identity() - h->normal * h->normal.transpose();
    t.slip        = Pc * gap + h->slip;
    // J_d: x columns w P_c, θ columns −w P_c (r R ν)^ (δ(Rν) = θ × Rν)
    Eigen::Matrix<double, 3, 48> J = Eigen::Matrix<double, 3, 48>::Zero();
    for (int k = 0; k < 4; ++k)
      {
        J.block<3, 3>(0, 6 * k)     = weight[k] * Pc;
        J.block<3, 3>(0, 6 * k + 3) = -weight[k] * Pc * skew(arm[k]);
      }

    t.capacity        = mu * std::max(c.force, 0.0);
    const double slip = t.slip.norm();
    t.slipping        = !coulomb_sticks(stiffness, t.capacity, slip);
    const Vec3 f      = t.slipping ? Vec3(t.capacity / slip * t.slip) : Vec3(stiffness * t.slip);
    t.force           = f.norm();
    t.energy          = t.slipping ? t.capacity * slip - 0.5 * t.capacity * coulomb_slip_gap(stiffness, t.capacity)
                                   : 0.5 * stiffness * slip * slip;
    t.residual        = J.transpose() * f;
    if (!with_jacobian)
      return t;
    // ∂f/∂z: k_t J_d in stick; in slip the turn of d/|d| at fixed c, and c = μ N(x)
    // along it, ∂N/∂x = −φ''(g) n·dΔ/dx on the contact's four nodes
    Eigen::Matrix<double, 3, 48> df;
    if (!t.slipping)
      df = stiffness * J;
    else
      {
        const Vec3                         e  = t.slip / slip;
        const Eigen::Matrix<double, 1, 12> dN =
          -c.stiffness * c.normal.transpose() * closest_point_sensitivity(c, x);
        df = (t.capacity / slip) * (Mat3::Identity() - e * e.transpose()) * J;
        for (int n = 0; n < 4; ++n)
          df.block<3, 3>(0, 6 * (4 + n)) += mu * e * dN.segment<3>(3 * n);
      }
    t.jacobian = J.transpose() * df;
    // the moment rows w (r R ν) × f turn with the node: w (a fᵀ − (f·a) I), a = r R ν
    // (f is tangential to n_c, so P_c f = f)
    for (int k = 0; k < 4; ++k)
      t.jacobian.block<3, 3>(6 * k + 3, 6 * k + 3) +=
        weight[k] * (arm[k] * f.transpose() - f.dot(arm[k]) * Mat3::Identity());
    return t;
  }

  void
  ContactFriction::commit(const std::vector<ContactPair> &pairs, const std::vector<Vec3> &x,
                          const std::vector<Quat> &q)
  {
    if (!active())
      return;
    std::vector<FrictionAnchor> next;
    next.reserve(pairs.size());
    for (const auto &c : pairs)
      {
        const FrictionTerm t = evaluate(c, x, q, false);
        Vec3               g = Vec3::Zero();
        if (t.anchored)
          g = t.slipping ? Vec3(coulomb_slip_gap(stiffness, t.capacity) / t.slip.norm() * t.slip) : t.slip;
        FrictionAnchor h;
        h.a       = c.a;
        h.b       = c.b;
        h.s       = c.s;
        h.t       = c.t;
        h.sigma_a = t.sigma_a;
        h.sigma_b = t.sigma_b;
        h.normal  = c.normal;
        // the touching surface points: −n from a's centreline, +n from b's
        h.nu_a[0] = q[c.a].conjugate() * (-c.normal);
        h.nu_a[1] = q[c.a + 1].conjugate() * (-c.normal);
        h.nu_b[0] = q[c.b].conjugate() * c.normal;
        h.nu_b[1] = q[c.b + 1].conjugate() * c.normal;
        h.slip    = g - c.normal * c.normal.dot(g);
        next.push_back(h);
      }
    history = std::move(next);
  }
} // namespace suturesim::rod
