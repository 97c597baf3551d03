#include <suturesim/rod/knot_tightening.h>
#include <suturesim/rod/rod_parameters.h>
#include <suturesim/rod/viscous_drag.h>

#include <suturesim/knot/curves.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <tuple>

namespace suturesim::rod
{
  namespace
  {
    /// A closed knot of knot/curves.h: where it is cut open, how close its strands pass
    /// (over its scale), and how the two passes through the cut are drawn apart (below).
    struct ClosedKnot
    {
      Vec3 (*curve)(double);
      double cut, clearance;
      int    lift;  // +1: the first tail above the last along the diagram's normal; −1 below
      double blend; // the parameter t over which the lift fades into the knot
    };

    ClosedKnot
    closed_knot(const std::string &name)
    {
      // each cut where the curve is furthest from its axis (3 there), so that straight
      // tails along the tangent pass outside the knot; the lift's side and blend are the
      // ones that keep the laid strands furthest apart (0.967, 0.987 and 0.999 of the
      // closed knot's clearance; RodKnot.TheLaidKnots… checks 0.95)
      if (name == "overhand")
        return {knot::trefoil, M_PI, knot::trefoil_clearance, -1, 1.0};
      if (name == "figure-eight")
        return {knot::figure_eight, 0, knot::figure_eight_clearance, 1, 0.8};
      if (name == "cinquefoil")
        return {knot::cinquefoil, 0, knot::cinquefoil_clearance, 1, 1.2};
      std::string known;
      for (const auto &k : KnotTightening::laid_knots())
        known += (known.empty() ? "" : ", ") + k;
      throw std::invalid_argument("no laid knot '" + name + "' (" + known + ")");
    }

    double
    smoothstep(const double x)
    {
      const double c = std::clamp(x, 0.0, 1.0);
      return c * c * (3 - 2 * c);
    }

    /// The closed knot @p c scaled by @p a, cut open with straight tails of length
    /// @p tail along the tangent τ at the cut, as a dense polyline. Cut open, the knot
    /// passes through the cut twice along τ (tail, knot, then the knot back through the
    /// cut and the other tail), so the two passes are lifted apart along the diagram's
    /// normal n (z made normal to τ) by the closed knot's clearance: the first by +c/2
    /// and the second by −c/2 (their tails entirely, the knot's ends faded out over the
    /// blend in t). Seen along n the laid knot is the closed one's diagram, its tails
    /// overlapping in one line. Returns n too.
    std::pair<std::vector<Vec3>, Vec3>
    open_knot(const ClosedKnot &c, const double a, const double tail)
    {
      const auto   point = [&](const double t) { return Vec3(a * c.curve(t)); };
      const double d     = 1e-6;
      const Vec3   tau   = (c.curve(c.cut + d) - c.curve(c.cut - d)).normalized();
      const Vec3   n     = (Vec3::UnitZ() - Vec3::UnitZ().dot(tau) * tau).normalized();
      const Vec3   lift  = 0.5 * c.lift * c.clearance * a * n;
      std::vector<Vec3> dense;
      const int         core = 20000, ends = 200;
      for (int i = 0; i <= ends; ++i)
        dense.push_back(point(c.cut) + lift - tau * tail * (1 - double(i) / ends));
      for (int i = 1; i <= core; ++i)
        {
          const double t = 2 * M_PI * i / core;
          dense.push_back(point(c.cut + t) + (1 - smoothstep(t / c.blend)) * lift -
                          smoothstep((t - 2 * M_PI + c.blend) / c.blend) * lift);
        }
      for (int i = 1; i <= ends; ++i)
        dense.push_back(point(c.cut) - lift + tau * tail * i / ends);
      return {std::move(dense), n};
    }

    /// H = N·E₁ + ½ N·Γ + ½ M·K at an element's centre (KnotTightening::first_integral()).
    double
    hamiltonian(const ElementState &e)
    {
      return e.N.x() + 0.5 * e.N.dot(e.Gamma) + 0.5 * e.M.dot(e.K);
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
    : KnotTightening(parameters, lay(parameters))
  {}

  KnotTightening::KnotTightening(const KnotTighteningParameters &parameters, LaidKnot laid)
    : prm(parameters)
    , normal(laid.normal)
    , knot(std::move(laid.x))
    , frames(std::move(laid.q))
    , rest(lengths(knot))
    , rod(make(1, 0, knot, frames))
  {}

  KnotTightening::LaidKnot
  KnotTightening::lay(const KnotTighteningParameters &p)
  {
    // the open knot turned so that its ends lie along x, resampled into elements of
    // about the element length with parallel-transported frames (a polyline centreline)
    auto [dense, n]    = open_knot(closed_knot(p.knot), p.knot_size, p.tail);
    const Quat    turn = Quat::FromTwoVectors(dense.back() - dense.front(), Vec3::UnitX());
    double        arc  = 0;
    for (std::size_t i = 1; i < dense.size(); ++i)
      arc += (dense[i] - dense[i - 1]).norm();
    for (Vec3 &x : dense)
      x = turn * x;
    RodParameters centreline;
    centreline.centreline = "polyline";
    centreline.polyline   = std::move(dense);
    centreline.elements   = std::max(1u, static_cast<unsigned>(std::lround(arc / p.element)));
    LaidKnot laid;
    centreline.initial_configuration(laid.x, laid.q);
    laid.normal = turn * n;
    laid.normal = (laid.normal - laid.normal.x() * Vec3::UnitX()).normalized();
    return laid;
  }

  const std::vector<std::string> &
  KnotTightening::laid_knots()
  {
    static const std::vector<std::string> names{"overhand", "figure-eight", "cinquefoil"};
    return names;
  }

  double
  KnotTightening::strand_clearance(const std::string &knot)
  {
    return 0.95 * closed_knot(knot).clearance;
  }

  double
  KnotTightening::bending_stiffness() const
  {
    return prm.section.moment[1];
  }

  Vec3
  KnotTightening::projection_normal() const
  {
    return normal;
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
        // and neither does their sum, which is what the two ends' reactions differ by
        // (a slow slide of the whole knot drags many nodes a little, the same way)
        Vec6   r;
        Mat6   J;
        double largest = 0;
        Vec3   sum     = Vec3::Zero();
        for (std::size_t i = 1; i + 1 < start.size(); ++i)
          {
            r.setZero();
            drag.add(i, m.positions()[i], r, J);
            largest = std::max(largest, r.head<3>().norm());
            sum += r.head<3>();
          }
        if (std::max(largest, sum.norm()) < 1e-5 * B / (h * h))
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
    unsigned     iterations = 0;
    double       failed_at  = 0;
    const bool   tied       = advance(2, 0.1, 0.1, 1e-4, [&](double, const double p) {
      RodModel          next   = make(std::min(1.0, 2 - p), F0 * std::min(1.0, p), rod.positions(), rod.rotations());
      const std::string failed = settle(next, iterations);
      if (!failed.empty())
        {
          failed_at = p;
          why       = failed;
          return false;
        }
      rod = std::move(next);
      accept();
      return true;
    });
    if (!tied)
      {
        why = "the knot could not be tied: no equilibrium at p = " + std::to_string(failed_at) +
              " (tension ramped to 1, rest shape straightened to 2): " + why;
        return false;
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
    // the two ends' reactions along x: equal and opposite at an exact equilibrium
    const Eigen::VectorXd r = rod.residual();
    end_force               = -r[0];
    last_end_force          = r[r.size() - 6];
  }

  bool
  KnotTightening::advance(const double total, const double first, const double largest, const double smallest,
                          const std::function<bool(double, double)> &attempt)
  {
    double done = 0, increment = first;
    while (done < total)
      {
        increment = std::min(increment, total - done);
        if (increment < smallest)
          return false;
        if (attempt(done, done + increment))
          {
            done += increment;
            increment = std::min(2 * increment, largest);
          }
        else
          increment *= 0.5;
      }
    return true;
  }

  bool
  KnotTightening::pull()
  {
    const double step = prm.pull_step;
    last_iterations   = 0;
    const bool pulled_step = advance(step, step, step, 1e-3 * step, [&](const double from, const double to) {
      // predictor: the tail beyond the knot's last contact moves with its end
      const double sub   = to - from;
      RodModel     trial = rod;
      const auto  &cf    = rod.contact_forces();
      std::size_t  tail  = rod.n_nodes() - 1;
      while (tail > 0 && cf[tail - 1] == 0)
        --tail;
      for (std::size_t i = tail; i < rod.n_nodes(); ++i)
        trial.set_node(i, rod.positions()[i] + sub * Vec3::UnitX(), rod.rotations()[i]);
      unsigned          iterations = 0;
      const std::string failed     = settle(trial, iterations);
      last_iterations += iterations;
      if (!failed.empty())
        {
          why = failed;
          return false;
        }
      rod = std::move(trial);
      accept();
      pulled += sub;
      return true;
    });
    if (!pulled_step)
      why = "no equilibrium after pulling " + std::to_string(pulled / prm.radius) + " h: " + why;
    return pulled_step;
  }

  void
  KnotTightening::loop_reading(KnotState &s, const std::size_t first, const std::size_t last) const
  {
    const auto       &cf     = rod.contact_forces();
    const auto        states = rod.element_states(); // once: H and the tension below
    for (const ElementState &e : states)
      s.first_integral_spread = std::max(s.first_integral_spread, std::abs(hamiltonian(e) / s.force - 1));
    s.end_force_imbalance = last_end_force / end_force - 1;
    if (first >= last)
      return;
    // the loop: the longest run of elements between first and last neither of whose
    // nodes is in contact
    std::size_t begin = 0, end = 0;
    for (std::size_t e = first; e < last;)
      {
        std::size_t f = e;
        while (f < last && cf[f] == 0 && cf[f + 1] == 0)
          ++f;
        if (f - e > end - begin)
          std::tie(begin, end) = std::pair{e, f};
        e = f + 1;
      }
    // the tension N·t (N turned to space, t along the element's axis) and the bending
    // curvature |K₂, K₃| at each element's centre, interpolated where N·t changes sign
    const auto tension = [&](const std::size_t e) {
      const Vec3 t = (states[e].Rm * (Vec3::UnitX() + states[e].Gamma)).normalized();
      return (states[e].Rm * states[e].N).dot(t);
    };
    const auto bending = [&](const std::size_t e) { return states[e].K.tail<2>().norm(); };
    double     sum     = 0;
    int        zeros   = 0;
    for (std::size_t e = begin; e + 1 < end; ++e)
      {
        const double a = tension(e), b = tension(e + 1);
        if ((a > 0) == (b > 0))
          continue;
        const double w = a / (a - b);
        sum += 1 / ((1 - w) * bending(e) + w * bending(e + 1));
        ++zeros;
      }
    s.loop_radius = zeros > 0 ? sum / zeros : 0;
  }

  std::vector<double>
  KnotTightening::first_integral() const
  {
    std::vector<double> H;
    for (const ElementState &e : rod.element_states())
      H.push_back(hamiltonian(e));
    return H;
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
    loop_reading(s, first, last);
    // the pairs of accept()'s assembly, at these positions
    for (const auto &c : rod.contact().pairs())
      s.closest = std::min(s.closest, c.distance / (2 * prm.radius));
    return s;
  }
} // namespace suturesim::rod
