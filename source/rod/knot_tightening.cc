#include <suturesim/rod/knot_tightening.h>
#include <suturesim/rod/viscous_drag.h>

#include <algorithm>
#include <cmath>

namespace suturesim::rod
{
  namespace
  {
    /// The trefoil scaled by @p a, cut open at t = π with straight tails of length
    /// @p tail along the tangent there, resampled into elements of length about @p l and
    /// turned so that the tails lie along x.
    std::vector<Vec3>
    open_trefoil(const double a, const double tail, const double l)
    {
      const auto point = [&](const double t) {
        return Vec3(a * (std::sin(t) + 2 * std::sin(2 * t)), a * (std::cos(t) - 2 * std::cos(2 * t)),
                    -a * std::sin(3 * t));
      };
      const Vec3        axis = Vec3(3, 0, 3).normalized(); // the tangent at t = π
      std::vector<Vec3> dense;
      const int         core = 20000, ends = 200;
      for (int i = 0; i <= ends; ++i)
        dense.push_back(point(M_PI) - axis * tail * (1 - double(i) / ends));
      for (int i = 1; i <= core; ++i)
        dense.push_back(point(M_PI + 2 * M_PI * i / core));
      for (int i = 1; i <= ends; ++i)
        dense.push_back(point(M_PI) + axis * tail * i / ends);
      std::vector<double> arc{0};
      for (std::size_t i = 1; i < dense.size(); ++i)
        arc.push_back(arc.back() + (dense[i] - dense[i - 1]).norm());
      const int         elements = std::max(1, static_cast<int>(std::round(arc.back() / l)));
      const Quat        turn     = Quat::FromTwoVectors(axis, Vec3::UnitX());
      std::vector<Vec3> x;
      std::size_t       k = 0;
      for (int e = 0; e <= elements; ++e)
        {
          const double s = arc.back() * e / elements;
          while (k + 2 < arc.size() && arc[k + 1] < s)
            ++k;
          const double w = (s - arc[k]) / (arc[k + 1] - arc[k]);
          x.push_back(turn * ((1 - w) * dense[k] + w * dense[k + 1]));
        }
      return x;
    }

    /// Frames with d₁ along the centreline's nodal tangents, parallel transported.
    std::vector<Quat>
    transported_frames(const std::vector<Vec3> &x)
    {
      const std::size_t n = x.size();
      std::vector<Quat> q;
      Quat              frame = Quat::FromTwoVectors(Vec3::UnitX(), (x[1] - x[0]).normalized());
      for (std::size_t i = 0; i < n; ++i)
        {
          const Vec3 t = (x[std::min(i + 1, n - 1)] - x[i > 0 ? i - 1 : 0]).normalized();
          frame        = Quat::FromTwoVectors(frame * Vec3::UnitX(), t) * frame;
          q.push_back(frame);
        }
      return q;
    }

    std::vector<double>
    lengths(const std::vector<Vec3> &x)
    {
      std::vector<double> l;
      for (std::size_t i = 1; i < x.size(); ++i)
        l.push_back((x[i] - x[i - 1]).norm());
      return l;
    }
  } // namespace

  KnotTightening::KnotTightening(const KnotTighteningParameters &parameters)
    : prm(parameters)
    , knot(open_trefoil(prm.knot_size, prm.tail, prm.element))
    , frames(transported_frames(knot))
    , rest(lengths(knot))
    , rod(make(1, 0, knot, frames))
  {}

  double
  KnotTightening::bending_stiffness() const
  {
    return prm.section.moment[1];
  }

  Vec3
  KnotTightening::projection_normal()
  {
    return Vec3::UnitZ();
  }

  double
  KnotTightening::audoly_tension(const double eps, const double mu)
  {
    return 0.5 * std::pow(eps, 4) + mu * 0.492 * std::pow(eps, 3);
  }

  RodModel
  KnotTightening::make(const double s, const double tension, const std::vector<Vec3> &x,
                       const std::vector<Quat> &q) const
  {
    // the rest shape at s: the knot's relative rotations ψ and chords (in the elements'
    // midpoint frames) scaled by s, towards a straight rod along d₁ at s = 0
    std::vector<Vec3> xr{Vec3::Zero()};
    std::vector<Quat> qr{Quat::Identity()};
    for (std::size_t i = 0; i + 1 < knot.size(); ++i)
      {
        const Vec3 psi   = quaternion_log(frames[i].conjugate() * frames[i + 1]);
        const Quat mid   = qr.back() * quaternion_exp(0.5 * s * psi);
        const Vec3 chord = (frames[i] * quaternion_exp(0.5 * psi)).conjugate() * (knot[i + 1] - knot[i]);
        xr.push_back(xr.back() + mid * (s * chord + (1 - s) * rest[i] * Vec3::UnitX()));
        qr.push_back(qr.back() * quaternion_exp(s * psi));
      }
    RodModel m(xr, qr, prm.section, 0, Vec3::Zero());
    for (std::size_t i = 0; i < x.size(); ++i)
      m.set_node(i, x[i], q[i]);
    ContactParameters contact = prm.contact;
    contact.enabled           = true;
    contact.radius            = prm.radius;
    m.set_contact(contact);
    m.constrain(0, {{true, true, true, true, false, false}});
    m.constrain(x.size() - 1, {{false, true, true, false, false, false}});
    m.forces().back() = tension * Vec3::UnitX();
    return m;
  }

  std::string
  KnotTightening::settle(RodModel &m, unsigned &iterations) const
  {
    const double     h = prm.radius, B = bending_stiffness();
    NewtonParameters newton;
    newton.max_iterations   = 100;
    newton.tolerance        = 1e-8;
    newton.absolute_floor   = 1e-6 * B / (h * h);
    newton.max_displacement = 0.2 * h; // a strand moves less than a tenth of the contact distance
    newton.max_rotation     = 0.2;
    ViscousDrag       drag(m, prm.drag);
    std::vector<Vec3> start;
    const NodalTerms  terms = [&](std::size_t i, const Vec3 &x, const Quat &, Vec6 &r, Mat6 &J) {
      drag.add(i, x, r, J);
    };
    iterations = 0;
    // pseudo-time steps of dt ≤ 1 s: one that fails is retried from where it started
    // at a tenth of dt (a stiffer drag, a shorter move: a snap of the knot is followed
    // rather than jumped), and dt grows back by 2 after each success
    double dt = 1;
    for (int step = 0; step < 400; ++step)
      {
        start                        = m.positions();
        const std::vector<Quat> turn = m.rotations();
        drag.begin_step(&start, dt);
        const auto result = m.solve(newton, &terms);
        iterations += result.iterations;
        if (!result.converged)
          {
            if (dt < 1e-4)
              return "pseudo-time step " + std::to_string(step + 1) + ": " + result.reason;
            for (std::size_t i = 0; i < start.size(); ++i)
              m.set_node(i, start[i], turn[i]);
            dt *= 0.1;
            continue;
          }
        dt = std::min(1.0, 2 * dt);
        // the drag is what holds the nodes out of balance: the state is an equilibrium
        // once no node's drag exceeds 10⁻⁵ B/h² (≤ 0.04 % of the tensions pulled here)
        Vec6   r;
        Mat6   J;
        double largest = 0;
        for (std::size_t i = 1; i + 1 < start.size(); ++i)
          {
            r.setZero();
            drag.add(i, m.positions()[i], r, J);
            largest = std::max(largest, r.head<3>().norm());
          }
        if (largest < 1e-5 * B / (h * h))
          return "";
      }
    return "still moving after 400 pseudo-time steps";
  }

  bool
  KnotTightening::tie()
  {
    // p from 0 to 1: the tension ramped on the stress-free knot; from 1 to 2: the rest
    // shape straightened under it
    const double F0 = prm.pretension;
    double       p = 0, dp = 0.1;
    while (p < 2)
      {
        if (dp < 1e-4)
          {
            why = "the knot could not be tied: no equilibrium at p = " + std::to_string(p + dp) +
                  " (tension ramped to 1, rest shape straightened to 2): " + why;
            return false;
          }
        const double next_p = std::min(2.0, p + dp);
        RodModel     next   = make(std::min(1.0, 2 - next_p), F0 * std::min(1.0, next_p), rod.positions(),
                                   rod.rotations());
        const std::string failed = settle(next, last_iterations);
        if (!failed.empty())
          {
            dp *= 0.5;
            why = failed;
            continue;
          }
        rod = std::move(next);
        accept();
        p  = next_p;
        dp = std::min(2 * dp, 0.1);
      }
    // held where the tension left it, from now on pulled by displacement
    rod.forces().back() = Vec3::Zero();
    rod.constrain(rod.n_nodes() - 1, {{true, true, true, false, false, false}});
    return true;
  }

  void
  KnotTightening::accept()
  {
    rod.commit_contact();
    end_force = -rod.residual().segment<3>(0).dot(Vec3::UnitX());
  }

  bool
  KnotTightening::pull()
  {
    const double step = prm.pull_step;
    double       left = step, sub = step;
    last_iterations   = 0;
    while (left > 0)
      {
        if (sub < 1e-3 * step)
          {
            why = "no equilibrium after pulling " + std::to_string(pulled / prm.radius) + " h: " + why;
            return false;
          }
        // predictor: the tail beyond the knot's last contact moves with its end
        RodModel    trial = rod;
        const auto &cf    = rod.contact_forces();
        std::size_t tail  = rod.n_nodes() - 1;
        while (tail > 0 && cf[tail - 1] == 0)
          --tail;
        for (std::size_t i = tail; i < rod.n_nodes(); ++i)
          trial.set_node(i, rod.positions()[i] + sub * Vec3::UnitX(), rod.rotations()[i]);
        unsigned          iterations = 0;
        const std::string failed     = settle(trial, iterations);
        last_iterations += iterations;
        if (!failed.empty())
          {
            sub *= 0.5;
            why = failed;
            continue;
          }
        rod = std::move(trial);
        accept();
        pulled += sub;
        left -= sub;
        sub = std::min(left, 2 * sub);
      }
    return true;
  }

  KnotState
  KnotTightening::state() const
  {
    KnotState   s;
    const auto &x = rod.positions();
    const auto &cf = rod.contact_forces();
    const std::size_t n = x.size();
    s.pulled     = pulled;
    s.iterations = last_iterations;
    s.force      = end_force;
    double length = 0;
    for (const double l : rest)
      length += l;
    s.shortening = length - (x[n - 1] - x[0]).norm();
    std::size_t first = n, last = 0;
    for (std::size_t i = 0; i < n; ++i)
      if (cf[i] > 0)
        {
          first = std::min(first, i);
          last  = std::max(last, i);
          ++s.contacts;
        }
    double kappa = 0;
    for (std::size_t i = std::max<std::size_t>(first, 1); i + 1 < n && i <= last; ++i)
      {
        // the discrete curvature 2 tan(φ/2)/l̄ at node i
        const Vec3 a = (x[i] - x[i - 1]).normalized(), b = (x[i + 1] - x[i]).normalized();
        kappa = std::max(kappa, 2 * a.cross(b).norm() / (1 + a.dot(b)) / (0.5 * (rest[i - 1] + rest[i])));
      }
    s.radius = kappa > 0 ? 1 / kappa : 0;
    SelfContact contact;
    contact.setup(rod.contact().parameters(), x, rest);
    for (const auto &c : contact.update(x))
      s.closest = std::min(s.closest, c.distance / (2 * prm.radius));
    return s;
  }
} // namespace suturesim::rod
