#include <suturesim/rod/rod_model.h>

#include <Eigen/LU>
#include <Eigen/SparseCore>
#include <Eigen/SparseLU>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace suturesim::rod
{
  struct RodModel::System
  {
    BlockTridiagonal                    J;     // the couplings of neighbouring nodes
    Eigen::VectorXd                     r;
    std::vector<Eigen::Triplet<double>> extra; // couplings beyond neighbours
    // the factorisation when contact couples distant nodes (sparse_factorized)
    Eigen::SparseLU<Eigen::SparseMatrix<double>> sparse;
    Eigen::SparseMatrix<double>                  A;
    bool                                         sparse_factorized = false;

    void
    reset(const std::size_t n, const bool jacobian)
    {
      r.setZero(6 * n);
      extra.clear();
      if (!jacobian)
        return;
      J.reset(n);
    }

    /// Adds an n×n block (n = 3: translations; 6: the whole node) at nodes (a, b).
    template <int n>
    void
    add_block(const std::size_t a, const std::size_t b, const Eigen::Matrix<double, n, n> &k)
    {
      if (a == b)
        J.diagonal(a).template topLeftCorner<n, n>() += k;
      else if (b == a + 1)
        J.upper(a).template topLeftCorner<n, n>() += k;
      else if (a == b + 1)
        J.lower(b).template topLeftCorner<n, n>() += k;
      else
        for (int i = 0; i < n; ++i)
          for (int j = 0; j < n; ++j)
            extra.emplace_back(6 * a + i, 6 * b + j, k(i, j));
    }

    /// Adds a 3×3 translational block at nodes (a, b).
    void
    add_translational(const std::size_t a, const std::size_t b, const Mat3 &k)
    {
      add_block<3>(a, b, k);
    }
  };

  RodModel::RodModel(const std::vector<Vec3> &x, const std::vector<Quat> &q,
                     const SectionStiffness &section, const double mass_per_length,
                     const Vec3 &rotational_inertia_per_length)
    : pos(x)
    , rot(q)
    , stiffness(section)
    , lumped(x.size())
    , fixed(x.size(), std::array<bool, 6>{{false, false, false, false, false, false}})
    , cut_element(x.size() - 1, 0)
    , force(x.size(), Vec3::Zero())
    , moment(x.size(), Vec3::Zero())
    , contact_force(x.size(), 0.0)
  {
    if (x.size() < 2 || x.size() != q.size())
      throw std::invalid_argument("RodModel: needs at least two nodes, each with a rotation");
    for (auto &r : rot)
      r.normalize();
    for (std::size_t e = 0; e + 1 < x.size(); ++e)
      {
        reference.push_back(make_reference(pos[e], rot[e], pos[e + 1], rot[e + 1]));
        // lumped inertia: half of each adjacent element to each node
        for (const std::size_t n : {e, e + 1})
          {
            lumped[n].mass += 0.5 * mass_per_length * reference[e].length;
            lumped[n].rotational += 0.5 * reference[e].length * rotational_inertia_per_length;
          }
      }
  }

  RodModel::Workspace::Workspace()
    : system(std::make_unique<System>())
  {}
  RodModel::Workspace::Workspace(const Workspace &)
    : Workspace()
  {}
  RodModel::Workspace &
  RodModel::Workspace::operator=(const Workspace &)
  {
    return *this;
  }
  RodModel::Workspace::~Workspace() = default;
  RodModel::~RodModel() = default;

  void
  RodModel::set_node(const std::size_t i, const Vec3 &x, const Quat &q)
  {
    pos[i] = x;
    rot[i] = q.normalized();
  }

  void
  RodModel::restore_node(const std::size_t i, const Vec3 &x, const Quat &q)
  {
    pos[i] = x;
    rot[i] = q;
  }

  void
  RodModel::constrain(const std::size_t node, const std::array<bool, 6> &f)
  {
    fixed[node] = f;
  }

  void
  RodModel::cut(const std::size_t element)
  {
    cut_element.at(element) = 1;
  }

  void
  RodModel::set_contact(const ContactParameters &parameters)
  {
    std::vector<double> lengths, arc{0.0};
    for (const auto &r : reference)
      {
        lengths.push_back(r.length);
        arc.push_back(arc.back() + r.length);
      }
    self_contact.setup(parameters, pos, lengths);
    contact_friction.setup(parameters, arc);
  }

  void
  RodModel::commit_contact()
  {
    if (contact_friction.active())
      contact_friction.commit(self_contact.update(pos), pos, rot);
  }

  double
  RodModel::potential_energy()
  {
    double e = 0;
    for (std::size_t k = 0; k < n_elements(); ++k)
      if (!cut_element[k])
        e += element_state(pos[k], rot[k], pos[k + 1], rot[k + 1], reference[k], stiffness).energy;
    for (const auto &c : self_contact.update(pos))
      e += contact_friction.evaluate(c, pos, rot, false).energy;
    e += self_contact.energy();
    for (std::size_t i = 0; i < n_nodes(); ++i)
      e -= force[i].dot(pos[i]);
    return e;
  }

  double
  RodModel::kinetic_energy(const std::vector<Vec3> &velocity, const std::vector<Vec3> &omega) const
  {
    double e = 0;
    for (std::size_t i = 0; i < n_nodes(); ++i)
      e += 0.5 * lumped[i].mass * velocity[i].squaredNorm() +
           0.5 * omega[i].dot(lumped[i].rotational.cwiseProduct(omega[i]));
    return e;
  }

  void
  RodModel::assemble(System &s, const NodalTerms *extra, const bool with_jacobian, const unsigned parts)
  {
    const std::size_t n = n_nodes();
    s.reset(n, with_jacobian);
    Vec12 g;
    Mat12 H;
    for (std::size_t k = 0; k < n_elements() && (parts & elastic_part); ++k)
      {
        if (cut_element[k])
          continue;
        if (with_jacobian)
          {
            element_tangent(pos[k], rot[k], pos[k + 1], rot[k + 1], reference[k], stiffness, g, &H);
            s.J.add_pair(k, H);
          }
        else
          element_tangent(pos[k], rot[k], pos[k + 1], rot[k + 1], reference[k], stiffness, g, nullptr);
        s.r.segment<12>(6 * k) += g;
      }
    if (with_jacobian)
      for (std::size_t i = 0; i < n; ++i)
        s.J.diagonal(i).block<3, 3>(3, 3) -= 0.5 * skew(s.r.segment<3>(6 * i + 3));

    if (parts & self_contact_part)
      add_self_contact(s, with_jacobian);
    for (std::size_t i = 0; i < n && (parts & applied_part); ++i)
      {
        s.r.segment<3>(6 * i) -= force[i];
        s.r.segment<3>(6 * i + 3) -= moment[i];
      }
    if (element_terms && element_list && (parts & element_terms_part))
      for (const std::size_t k : *element_list)
        {
          Vec12 r = Vec12::Zero();
          Mat12 J = Mat12::Zero();
          (*element_terms)(k, r, with_jacobian ? &J : nullptr);
          s.r.segment<12>(6 * k) += r;
          if (with_jacobian)
            s.J.add_pair(k, J);
        }
    if (extra && (parts & nodal_part))
      for (std::size_t i = 0; i < n; ++i)
        {
          Vec6 r = Vec6::Zero();
          Mat6 J = Mat6::Zero();
          (*extra)(i, pos[i], rot[i], r, J);
          s.r.segment<6>(6 * i) += r;
          if (with_jacobian)
            s.J.diagonal(i) += J;
        }
  }

  void
  RodModel::add_self_contact(System &s, const bool with_jacobian)
  {
    std::fill(contact_force.begin(), contact_force.end(), 0.0);
    for (const auto &c : self_contact.update(pos))
      {
        const std::array<std::size_t, 4> node{{c.a, c.a + 1, c.b, c.b + 1}};
        const std::array<double, 4>      w{{1 - c.s, c.s, -(1 - c.t), -c.t}};
        for (int i = 0; i < 4; ++i)
          {
            s.r.segment<3>(6 * node[i]) -= c.force * w[i] * c.normal;
            contact_force[node[i]] += c.force * std::abs(w[i]);
          }
        if (with_jacobian)
          {
            // Hessian of the envelope φ(x) = Φ(|Δ(x, u*(x))| − 2r), u = (s, t) at the
            // closest points: φ_xx − φ_xu φ_uu⁻¹ φ_ux over the parameters that are
            // interior (clamped ones are fixed at 0 or 1 and contribute no sensitivity).
            const Mat3 K = c.stiffness * c.normal * c.normal.transpose() -
                           (c.force / c.distance) * (Mat3::Identity() - c.normal * c.normal.transpose());
            Eigen::Matrix<double, 12, 12> H;
            for (int i = 0; i < 4; ++i)
              for (int j = 0; j < 4; ++j)
                H.block<3, 3>(3 * i, 3 * j) = w[i] * w[j] * K;
            const Vec3 gf = -c.force * c.normal; // ∂Φ/∂Δ
            std::vector<std::pair<Vec3, std::array<double, 4>>> params;
            if (c.s > 0 && c.s < 1)
              params.push_back({pos[c.a + 1] - pos[c.a], {{-1, 1, 0, 0}}});
            if (c.t > 0 && c.t < 1)
              params.push_back({pos[c.b] - pos[c.b + 1], {{0, 0, 1, -1}}});
            const int m = params.size();
            if (m > 0)
              {
                Eigen::MatrixXd Bxu(12, m), Huu(m, m);
                for (int j = 0; j < m; ++j)
                  {
                    for (int k = 0; k < 4; ++k)
                      Bxu.block<3, 1>(3 * k, j) = w[k] * K * params[j].first + params[j].second[k] * gf;
                    for (int i = 0; i < m; ++i)
                      Huu(i, j) = params[i].first.dot(K * params[j].first);
                  }
                const Eigen::FullPivLU<Eigen::MatrixXd> lu(Huu);
                if (lu.isInvertible())
                  H -= Bxu * lu.solve(Bxu.transpose());
              }
            for (int i = 0; i < 4; ++i)
              for (int j = 0; j < 4; ++j)
                s.add_translational(node[i], node[j], H.block<3, 3>(3 * i, 3 * j));
          }
        if (!contact_friction.active())
          continue;
        const FrictionTerm f = contact_friction.evaluate(c, pos, rot, with_jacobian);
        if (!f.anchored)
          continue;
        // rows: the anchors' nodes only (the contact's own nodes, slots 4–7, enter
        // through the normal force's columns)
        for (int i = 0; i < 4; ++i)
          {
            s.r.segment<6>(6 * f.node[i]) += f.residual.segment<6>(6 * i);
            for (int j = 0; j < 8 && with_jacobian; ++j)
              s.add_block<6>(f.node[i], f.node[j], f.jacobian.block<6, 6>(6 * i, 6 * j));
          }
      }
  }

  void
  RodModel::factorize(System &s) const
  {
    const std::size_t n = n_nodes();
    // constrained components: zero row and column, unit diagonal
    for (std::size_t i = 0; i < n; ++i)
      for (unsigned c = 0; c < 6; ++c)
        if (fixed[i][c])
          s.J.constrain(i, c);
    s.sparse_factorized = !s.extra.empty();
    if (!s.sparse_factorized)
      {
        // block LU (Thomas): O(N) for the block-tridiagonal Jacobian of an open rod
        s.J.factorize();
        return;
      }
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(36 * 3 * n + s.extra.size());
    s.J.append_nonzeros(t);
    for (const auto &e : s.extra)
      if (!fixed[e.row() / 6][e.row() % 6] && !fixed[e.col() / 6][e.col() % 6])
        t.push_back(e);
    s.A.resize(6 * n, 6 * n);
    s.A.setFromTriplets(t.begin(), t.end());
    s.sparse.compute(s.A);
    if (s.sparse.info() != Eigen::Success)
      throw std::domain_error("sparse LU of the rod Jacobian failed (singular)");
  }

  Eigen::VectorXd
  RodModel::substitute(System &s, Eigen::VectorXd b) const
  {
    const std::size_t n = n_nodes();
    for (std::size_t i = 0; i < n; ++i)
      for (unsigned c = 0; c < 6; ++c)
        if (fixed[i][c])
          b[6 * i + c] = 0;
    if (s.sparse_factorized)
      return s.sparse.solve(b);
    return s.J.solve(b);
  }

  Eigen::VectorXd
  RodModel::solve_linear(System &s) const
  {
    factorize(s);
    return substitute(s, -s.r);
  }

  const Eigen::VectorXd &
  RodModel::linearize(const NodalTerms *extra)
  {
    assemble(*work.system, extra, true);
    factorize(*work.system);
    return work.system->r;
  }

  Eigen::VectorXd
  RodModel::solve_linearized(const Eigen::VectorXd &b) const
  {
    return substitute(*work.system, b);
  }

  Eigen::VectorXd
  RodModel::residual(const NodalTerms *extra)
  {
    System s;
    assemble(s, extra, false);
    return s.r;
  }

  ResidualParts
  RodModel::residual_parts(const std::vector<const NodalTerms *> &nodal)
  {
    const auto part = [&](const NodalTerms *extra, const unsigned mask) {
      System s;
      assemble(s, extra, false, mask);
      return s.r;
    };
    ResidualParts parts;
    parts.elastic       = part(nullptr, elastic_part);
    parts.self_contact  = part(nullptr, self_contact_part);
    parts.applied       = part(nullptr, applied_part);
    parts.element_terms = part(nullptr, element_terms_part);
    for (const NodalTerms *terms : nodal)
      parts.nodal.push_back(part(terms, nodal_part));
    return parts;
  }

  Eigen::MatrixXd
  RodModel::dense_jacobian(const NodalTerms *extra)
  {
    System s;
    assemble(s, extra, true);
    Eigen::MatrixXd J = s.J.dense();
    for (const auto &e : s.extra)
      J(e.row(), e.col()) += e.value();
    return J;
  }

  Eigen::VectorXd
  RodModel::newton_direction(const NodalTerms *extra)
  {
    assemble(*work.system, extra, true);
    return solve_linear(*work.system);
  }

  void
  RodModel::update(const Eigen::VectorXd &delta, const double step)
  {
    for (std::size_t i = 0; i < n_nodes(); ++i)
      {
        pos[i] += step * delta.segment<3>(6 * i);
        rot[i] = (quaternion_exp(step * delta.segment<3>(6 * i + 3)) * rot[i]).normalized();
      }
  }

  std::vector<ElementState>
  RodModel::element_states() const
  {
    std::vector<ElementState> states;
    for (std::size_t k = 0; k < n_elements(); ++k)
      states.push_back(cut_element[k] ? ElementState{Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero(),
                                                     Mat3::Identity(), 0.0}
                                      : element_state(pos[k], rot[k], pos[k + 1], rot[k + 1], reference[k], stiffness));
    return states;
  }

  double
  RodModel::free_norm(const Eigen::VectorXd &r) const
  {
    double sum = 0;
    for (Eigen::Index k = 0; k < r.size(); ++k)
      if (!fixed[k / 6][k % 6])
        sum += r[k] * r[k];
    return std::sqrt(sum);
  }

  double
  RodModel::capped_step(const Eigen::VectorXd &delta, const NewtonParameters &prm) const
  {
    // a quasi-static free end swings far on the first, large correction of a stiffly
    // held node: the step is capped in length and turn
    double step = 1;
    for (std::size_t i = 0; i < n_nodes(); ++i)
      {
        const double moved  = delta.segment<3>(6 * i).norm();
        const double turned = delta.segment<3>(6 * i + 3).norm();
        if (prm.max_displacement > 0 && step * moved > prm.max_displacement)
          step = prm.max_displacement / moved;
        if (prm.max_rotation > 0 && step * turned > prm.max_rotation)
          step = prm.max_rotation / turned;
      }
    return step;
  }

  Eigen::VectorXd
  RodModel::direction(System &s, const NewtonParameters &prm) const
  {
    Eigen::VectorXd newton = solve_linear(s);
    if (!prm.trust_region || prm.max_displacement <= 0 || prm.max_rotation <= 0 || !newton.allFinite() ||
        capped_step(newton, prm) >= 1)
      return newton;
    // σ at which the step becomes a gradient step of about the caps' length: the larger
    // of |r_x| Δx and |r_θ| Δθ over the nodes (N m)
    const std::size_t n  = n_nodes();
    const double      dx = prm.max_displacement, dq = prm.max_rotation;
    double            gradient = 0;
    for (std::size_t i = 0; i < n; ++i)
      for (unsigned c = 0; c < 6; ++c)
        if (!fixed[i][c])
          gradient = std::max(gradient, std::abs(s.r[6 * i + c]) * (c < 3 ? dx : dq));
    const auto shifted = [&](const double sigma) {
      const auto shift = [&](const double sign) {
        for (std::size_t i = 0; i < n; ++i)
          for (unsigned c = 0; c < 6; ++c)
            if (!fixed[i][c])
              s.J.diagonal(i)(c, c) += sign * sigma / (c < 3 ? dx * dx : dq * dq);
      };
      shift(1);
      Eigen::VectorXd delta = solve_linear(s);
      shift(-1);
      return delta;
    };
    const auto fits = [&](const Eigen::VectorXd &delta) {
      return delta.allFinite() && capped_step(delta, prm) >= 1 && delta.dot(s.r) < 0;
    };
    double          hi   = std::max(gradient, std::numeric_limits<double>::min());
    Eigen::VectorXd best = shifted(hi);
    for (unsigned k = 0; k < 30 && !fits(best); ++k)
      best = shifted(hi *= 4);
    if (!fits(best))
      return newton; // left to the caps
    // bisection on log σ between a σ too small (its step longer than the caps) and hi,
    // to a factor of 1.1
    double lo = 1e-8 * hi;
    while (hi > 1.1 * lo)
      {
        const double          mid   = std::sqrt(lo * hi);
        const Eigen::VectorXd delta = shifted(mid);
        if (fits(delta))
          {
            hi   = mid;
            best = delta;
          }
        else
          lo = mid;
      }
    return best;
  }

  bool
  RodModel::take_full_step(System &s, const Eigen::VectorXd &delta, double step, const NodalTerms *extra)
  {
    // the assembly at the new state serves the next iteration, so no trial residual is
    // evaluated; a step that would turn an element by π or more is halved
    const auto x0 = pos;
    const auto q0 = rot;
    for (unsigned k = 0; k <= 10; ++k, step *= 0.5)
      {
        update(delta, step);
        try
          {
            assemble(s, extra, true);
            return true;
          }
        catch (const std::domain_error &)
          {
            pos = x0;
            rot = q0;
          }
      }
    return false;
  }

  double
  RodModel::line_search(const System &s, const Eigen::VectorXd &delta, const unsigned trials, const double start,
                        const NodalTerms *extra)
  {
    // On the slope of the energy along the direction, s(α) = δ·r(x ⊕ αδ) (the energy
    // line search of FEBio and of Bathe's text): the full step is taken unless it
    // overshoots the minimum along δ by much, in which case α is moved to the secant
    // root of s. A residual-norm search would stall here: the stiff axial modes make
    // ‖r‖ grow at first order in the rotations of a linearised step even when Newton
    // converges. Returns the step, or infinity when every trial fails.
    const auto x0       = pos;
    const auto q0       = rot;
    const auto slope_at = [&](const double a, double &trial_norm) {
      update(delta, a);
      double slope;
      try
        {
          const Eigen::VectorXd r = residual(extra);
          trial_norm              = free_norm(r);
          slope                   = 0;
          for (Eigen::Index k = 0; k < r.size(); ++k)
            if (!fixed[k / 6][k % 6])
              slope += delta[k] * r[k];
        }
      catch (const std::domain_error &)
        {
          trial_norm = slope = std::numeric_limits<double>::infinity();
        }
      pos = x0;
      rot = q0;
      return slope;
    };
    const double s0        = delta.dot(s.r);
    double       best_step = start, trial_norm;
    double       slope     = slope_at(start, trial_norm);
    for (unsigned k = 0; k < 10 && !std::isfinite(trial_norm); ++k)
      slope = slope_at(best_step *= 0.5, trial_norm);
    for (unsigned ls = 0; ls < trials && s0 < 0 && !(std::abs(slope) <= 0.9 * std::abs(s0)); ++ls)
      {
        const double a = std::isfinite(slope) ? best_step * s0 / (s0 - slope) : 0.5 * best_step;
        best_step = std::clamp(std::isfinite(a) && a > 0 ? a : 0.5 * best_step, 0.05 * best_step, best_step);
        slope     = slope_at(best_step, trial_norm);
      }
    return std::isfinite(trial_norm) ? best_step : std::numeric_limits<double>::infinity();
  }

  NewtonResult
  RodModel::solve(const NewtonParameters &prm, const NodalTerms *extra)
  {
    NewtonResult result;
    const auto   observe = [&](const double norm, const Eigen::VectorXd *delta, const double step) {
      if (prm.observer)
        prm.observer(NewtonIterate{result.iterations, norm, delta, step});
    };
    try
      {
        System &s = *work.system;
        assemble(s, extra, true);
        double norm = free_norm(s.r);
        double load = 0;
        for (std::size_t i = 0; i < n_nodes(); ++i)
          load += force[i].squaredNorm() + moment[i].squaredNorm();
        // absolute floor: round-off of the largest section force
        const double floor = std::max(1e-13 * stiffness.force.maxCoeff(), prm.absolute_floor);
        const double scale = std::max({norm, std::sqrt(load), floor});
        double       least = norm; // for NewtonParameters::stall_window
        unsigned     since = 0;
        for (result.iterations = 0;; ++result.iterations)
          {
            result.residual = norm;
            if (norm <= prm.tolerance * scale || norm <= floor)
              {
                observe(norm, nullptr, 0);
                result.converged = true;
                return result;
              }
            if (result.iterations == prm.max_iterations)
              {
                observe(norm, nullptr, 0);
                result.reason = "no convergence in " + std::to_string(prm.max_iterations) +
                                " iterations (residual " + std::to_string(norm) + " N)";
                return result;
              }
            const Eigen::VectorXd delta = direction(s, prm);
            if (!delta.allFinite())
              {
                result.reason = "linear solve produced NaN";
                return result;
              }
            // a stall of full steps: the line search from here on
            if (prm.line_search_steps == 0 && prm.stall_window > 0 && result.line_search_from == 0)
              {
                if (norm < 0.99 * least)
                  {
                    least = norm;
                    since = 0;
                  }
                else if (++since >= prm.stall_window)
                  result.line_search_from = result.iterations;
              }
            if (prm.line_search_steps == 0 && result.line_search_from == 0)
              {
                const double step = capped_step(delta, prm);
                observe(norm, &delta, step);
                if (!take_full_step(s, delta, step, extra))
                  {
                    result.reason = "every step length turned an element by pi or more";
                    return result;
                  }
              }
            else
              {
                const double step = prm.line_search_steps > 0 ? line_search(s, delta, prm.line_search_steps, 1, extra)
                                                              : line_search(s, delta, 4, capped_step(delta, prm), extra);
                if (!std::isfinite(step))
                  {
                    result.reason = "every line-search trial failed";
                    return result;
                  }
                observe(norm, &delta, step);
                update(delta, step);
                assemble(s, extra, true);
              }
            // a change of the active set re-assembles the residual but does not restart
            // the stall window: a pierce point at a node can switch its carrier back and
            // forth every other iteration, and a window restarted at each switch never
            // closed (bite_spacing.prm at b = 6 mm, s = 3 mm: a failed solve of 500 full
            // steps and 257 switches, never the line search)
            if (prm.follow && prm.follow())
              assemble(s, extra, true);
            norm = free_norm(s.r);
          }
      }
    catch (const std::domain_error &e)
      {
        result.converged = false;
        result.reason    = e.what();
        return result;
      }
  }
} // namespace suturesim::rod
