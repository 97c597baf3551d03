#include <suturesim/realtime/hot_kernel.h>
#include <suturesim/realtime/independent_order.h>
#include <suturesim/realtime/spring_set.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace suturesim::realtime
{
  void
  SpringSet::add(const std::uint32_t i, const std::uint32_t j, const double rest_length,
                 const double k)
  {
    if (i == j)
      throw std::invalid_argument(label + ": spring from a node to itself");
    if (!(rest_length >= 0) || !(k > 0))
      throw std::invalid_argument(label + ": spring with negative rest length or stiffness <= 0");
    first.push_back(std::min(i, j));
    second.push_back(std::max(i, j));
    rest.push_back(rest_length);
    stiffness.push_back(k);
    lambda.push_back(0);
    alpha_tilde.push_back(0);
    prepared_dt = 0;
    parallel.clear(); // the blocks hold for the springs partition() ordered
    ++changes;
  }

  void
  SpringSet::set(const std::size_t s, const std::uint32_t i, const std::uint32_t j, const double rest_length,
                 const double k)
  {
    if (s >= first.size())
      throw std::out_of_range(label + ": no spring " + std::to_string(s));
    if (i == j || !(rest_length >= 0) || !(k > 0))
      throw std::invalid_argument(label + ": spring from a node to itself, or with negative rest length or "
                                          "stiffness <= 0");
    first[s]     = std::min(i, j);
    second[s]    = std::max(i, j);
    rest[s]      = rest_length;
    stiffness[s] = k;
    lambda[s]    = 0;
    prepared_dt  = 0; // α̃ of the new stiffness at the next prepare_projection()
    parallel.clear(); // the new ends may span blocks
    ++changes;
  }

  void
  SpringSet::set_stiffness(const std::size_t s, const double k)
  {
    if (s >= first.size())
      throw std::out_of_range(label + ": no spring " + std::to_string(s));
    if (!(k >= 0))
      throw std::invalid_argument(label + ": spring stiffness must be >= 0 (∞: rigid)");
    stiffness[s] = k;
    lambda[s]    = 0;
    prepared_dt  = 0; // α̃ of the new stiffness at the next prepare_projection()
  }

  std::size_t
  SpringSet::find(const std::uint32_t i, const std::uint32_t j) const
  {
    const std::uint32_t a = std::min(i, j), b = std::max(i, j);
    for (std::size_t s = 0; s < first.size(); ++s)
      if (first[s] == a && second[s] == b)
        return s;
    return first.size();
  }

  void
  SpringSet::sort()
  {
    std::uint32_t n_nodes = 0;
    for (const auto j : second)
      n_nodes = std::max(n_nodes, j + 1);
    reorder(independent_order(ends(), n_nodes));
    parallel.clear();
  }

  std::size_t
  SpringSet::remove_if(const std::function<bool(std::uint32_t, std::uint32_t)> &cut)
  {
    std::vector<std::size_t> kept;
    for (std::size_t s = 0; s < first.size(); ++s)
      if (!cut(first[s], second[s]))
        kept.push_back(s);
    const std::size_t removed = first.size() - kept.size();
    if (removed == 0)
      return 0;
    reorder(kept);
    for (auto *v : {&rest, &stiffness, &lambda, &alpha_tilde})
      v->resize(kept.size());
    first.resize(kept.size());
    second.resize(kept.size());
    prepared_dt = 0;
    sort(); // consecutive springs share no node again
    return removed;
  }

  std::vector<std::array<std::uint32_t, 2>>
  SpringSet::ends() const
  {
    std::vector<std::array<std::uint32_t, 2>> e(first.size());
    for (std::size_t s = 0; s < first.size(); ++s)
      e[s] = {first[s], second[s]};
    return e;
  }

  bool
  SpringSet::partition(const std::vector<std::uint32_t> &node_part, const std::vector<std::uint32_t> &local,
                       const unsigned parts)
  {
    const auto blocked = block_order(ends(), node_part, parts);
    reorder(blocked.order);
    parallel = blocked.blocks;
    const std::size_t interface = parallel[parts];
    local_first.resize(interface);
    local_second.resize(interface);
    for (std::size_t s = 0; s < interface; ++s)
      {
        local_first[s]  = local[first[s]];
        local_second[s] = local[second[s]];
      }
    return true;
  }

  void
  SpringSet::reorder(const std::vector<std::size_t> &order)
  {
    permute(first, order);
    permute(second, order);
    permute(rest, order);
    permute(stiffness, order);
    permute(lambda, order);
    permute(alpha_tilde, order);
    ++changes;
  }

  double
  SpringSet::energy(const Matrix3Xd &x) const
  {
    double e = 0;
    for (std::size_t s = 0; s < first.size(); ++s)
      {
        const double d = (x.col(second[s]) - x.col(first[s])).norm() - rest[s];
        e += 0.5 * stiffness[s] * d * d;
      }
    return e;
  }

  namespace
  {
    /// The identity: every spring, in storage order.
    constexpr auto every = [](const std::size_t k) { return k; };
    /// The springs of a list, in its order.
    auto
    listed(const std::vector<std::uint32_t> &springs)
    {
      return [S = springs.data()](const std::size_t k) { return std::size_t(S[k]); };
    }
    /// The springs of storage positions begin, begin + 1, … (a block or the interface).
    auto
    from(const std::size_t begin)
    {
      return [begin](const std::size_t k) { return begin + k; };
    }
    /// The elastic tension k (L − L₀).
    auto
    elastic(const double *K, const double *R)
    {
      return [K, R](const std::size_t s, const double L) { return K[s] * (L - R[s]); };
    }
    /// The tension the XPBD solve applied: C = L − l with ∇_b C = (x_b − x_a)/L, so −λ/dt².
    auto
    applied(const double *Lambda, const double dt)
    {
      return [Lambda, scale = -1 / (dt * dt)](const std::size_t s, double) { return scale * Lambda[s]; };
    }
  } // namespace

  void
  SpringSet::add_forces(const Matrix3Xd &x, Matrix3Xd &f) const
  {
    add_tension_forces(x, f, elastic(stiffness.data(), rest.data()), every, first.size(), first.data(), second.data());
  }

  void
  SpringSet::add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, const double dt) const
  {
    add_tension_forces(x, f, applied(lambda.data(), dt), every, first.size(), first.data(), second.data());
  }

  bool
  SpringSet::elements_touching(const std::vector<char> &touched, std::vector<std::uint32_t> &springs) const
  {
    springs.clear();
    const auto flagged = [&](const std::uint32_t i) { return i < touched.size() && touched[i] != 0; };
    for (std::size_t s = 0; s < first.size(); ++s)
      if (flagged(first[s]) || flagged(second[s]))
        springs.push_back(static_cast<std::uint32_t>(s));
    return true;
  }

  void
  SpringSet::add_forces_of(const Matrix3Xd &x, Matrix3Xd &f, const std::vector<std::uint32_t> &springs) const
  {
    add_tension_forces(x, f, elastic(stiffness.data(), rest.data()), listed(springs), springs.size(), first.data(),
                       second.data());
  }

  void
  SpringSet::add_constraint_forces_of(const Matrix3Xd &x, Matrix3Xd &f, const double dt,
                                      const std::vector<std::uint32_t> &springs) const
  {
    add_tension_forces(x, f, applied(lambda.data(), dt), listed(springs), springs.size(), first.data(), second.data());
  }

  bool
  SpringSet::add_forces_on(const Matrix3Xd &x, const std::vector<std::uint32_t> &springs,
                           const std::vector<char> &touched, Vector3d &sum) const
  {
    sum += tension_force_on(x, elastic(stiffness.data(), rest.data()), springs, touched);
    return true;
  }

  bool
  SpringSet::add_constraint_forces_on(const Matrix3Xd &x, const double dt, const std::vector<std::uint32_t> &springs,
                                      const std::vector<char> &touched, Vector3d &sum) const
  {
    sum += tension_force_on(x, applied(lambda.data(), dt), springs, touched);
    return true;
  }

  template <typename Tension>
  SUTURESIM_HOT_KERNEL Vector3d
  SpringSet::tension_force_on(const Matrix3Xd &x, const Tension &tension, const std::vector<std::uint32_t> &springs,
                              const std::vector<char> &touched) const
  {
    const double        *X = x.data();
    const std::uint32_t *I = first.data(), *J = second.data();
    const auto flagged = [T = touched.data(), m = touched.size()](const std::uint32_t i) { return i < m && T[i] != 0; };
    double               sum[3] = {0, 0, 0};
    for (const std::uint32_t s : springs)
      {
        // a on the boundary: +t d; b: −t d; both: nothing
        const bool on_a = flagged(I[s]);
        if (on_a == flagged(J[s]))
          continue;
        const std::size_t a = 3 * std::size_t(I[s]), b = 3 * std::size_t(J[s]);
        const double      dx = X[b] - X[a], dy = X[b + 1] - X[a + 1], dz = X[b + 2] - X[a + 2];
        const double      L  = std::sqrt(dx * dx + dy * dy + dz * dz);
        const double      t  = L > 0 ? (on_a ? 1.0 : -1.0) * tension(s, L) / L : 0.0;
        sum[0] += t * dx;
        sum[1] += t * dy;
        sum[2] += t * dz;
      }
    return {sum[0], sum[1], sum[2]};
  }

  template <typename Tension, typename Spring>
  SUTURESIM_HOT_KERNEL void
  SpringSet::add_tension_forces(const Matrix3Xd &x, Matrix3Xd &f, const Tension &tension, const Spring &spring,
                                const std::size_t n, const std::uint32_t *I, const std::uint32_t *J) const
  {
    // the hot kernel: raw pointers into the column-major 3 x n arrays
    const double *X = x.data();
    double       *F = f.data();
    for (std::size_t k = 0; k < n; ++k)
      {
        const std::size_t s = spring(k);
        const std::size_t a = 3 * std::size_t(I[s]), b = 3 * std::size_t(J[s]);
        const double      dx = X[b] - X[a], dy = X[b + 1] - X[a + 1], dz = X[b + 2] - X[a + 2];
        const double      L  = std::sqrt(dx * dx + dy * dy + dz * dz);
        // tension / length; a spring of zero length has no direction and pushes nowhere
        const double t = L > 0 ? tension(s, L) / L : 0.0;
        F[a] += t * dx;
        F[a + 1] += t * dy;
        F[a + 2] += t * dz;
        F[b] -= t * dx;
        F[b + 1] -= t * dy;
        F[b + 2] -= t * dz;
      }
  }

  bool
  SpringSet::element_nodes(std::vector<std::uint32_t> &nodes, unsigned &per_element) const
  {
    per_element = 2;
    nodes.clear();
    for (std::size_t s = 0; s < first.size(); ++s)
      nodes.insert(nodes.end(), {first[s], second[s]});
    return true;
  }

  void
  SpringSet::add_vertex_block(const Matrix3Xd &x, const std::uint32_t i, const std::uint32_t *springs,
                              const std::size_t n, Vector3d &f, Eigen::Matrix3d &H) const
  {
    for (std::size_t k = 0; k < n; ++k)
      {
        const auto     s  = springs[k];
        const Vector3d d  = x.col(second[s]) - x.col(first[s]);
        const double   L2 = d.squaredNorm();
        if (!(L2 > 0))
          continue; // no direction: neither force nor a defined stiffness
        const double L = std::sqrt(L2), k_s = stiffness[s], c = std::max(0.0, 1 - rest[s] / L);
        // −∂E/∂x_first = k (L − L₀) d/L; the other end the opposite; with u = d/L,
        // H = k [u uᵀ + c (I − u uᵀ)] = k c I + k (1 − c) d dᵀ/L²
        f += ((i == first[s] ? k_s : -k_s) * (L - rest[s]) / L) * d;
        H.noalias() += (k_s * (1 - c) / L2) * d * d.transpose();
        H.diagonal().array() += k_s * c;
      }
  }

  void
  SpringSet::reset_multipliers()
  {
    std::fill(lambda.begin(), lambda.end(), 0.0);
  }

  void
  SpringSet::prepare_projection(const double dt)
  {
    if (dt == prepared_dt)
      return;
    prepared_dt          = dt;
    const double inv_dt2 = 1 / (dt * dt);
    for (std::size_t s = 0; s < first.size(); ++s)
      // α̃ = α/dt², α = 1/k; a spring left out (k = 0) gets the largest finite α̃, which
      // with λ = 0 makes its correction vanish where ∞ would give ∞·0 = NaN
      alpha_tilde[s] = stiffness[s] > 0 ? inv_dt2 / stiffness[s] : std::numeric_limits<double>::max();
  }

  namespace
  {
    /// x_a −= w_a d, x_b += w_b d: a spring's correction along d (inline into the
    /// multi-versioned kernels).
    [[gnu::always_inline]] inline void
    move_ends(double *xa, double *xb, const double wa, const double wb, const double dx, const double dy,
              const double dz)
    {
      xa[0] -= wa * dx;
      xa[1] -= wa * dy;
      xa[2] -= wa * dz;
      xb[0] += wb * dx;
      xb[1] += wb * dy;
      xb[2] += wb * dz;
    }

    /// One Gauss–Seidel sweep over n distance constraints (the hot kernel: one square
    /// root and one division per spring). A free function: GCC multi-versions no
    /// virtual function.
    SUTURESIM_HOT_KERNEL void
    project_distances(double *X, const double *W, const std::uint32_t *I, const std::uint32_t *J,
                      const double *R, const double *A, double *Lambda, const std::size_t n)
    {
      for (std::size_t s = 0; s < n; ++s)
        {
          const std::size_t a = 3 * std::size_t(I[s]), b = 3 * std::size_t(J[s]);
          const double      dx = X[b] - X[a], dy = X[b + 1] - X[a + 1], dz = X[b + 2] - X[a + 2];
          const double      L  = std::sqrt(dx * dx + dy * dy + dz * dz);
          const double      w_a = W[I[s]], w_b = W[J[s]];
          // both ends held and rigid, or no direction: nothing moves
          const double den = (w_a + w_b + A[s]) * L;
          if (!(den > 0))
            continue;
          // Δλ = (−C − α̃λ)/(w_a + w_b + α̃), applied along the unit direction d/L: the
          // two divisions folded into one
          const double g = (-(L - R[s]) - A[s] * Lambda[s]) / den;
          Lambda[s] += g * L;
          const double wa = w_a * g, wb = w_b * g;
          move_ends(X + a, X + b, wa, wb, dx, dy, dz);
        }
    }
  } // namespace

  void
  SpringSet::warm_multipliers(const VectorXd &, const double scale)
  {
    for (auto &l : lambda)
      l *= scale;
  }

  void
  SpringSet::project(Matrix3Xd &x, const VectorXd &w, const double dt)
  {
    project_range(x, w, dt, 0, first.size());
  }

  void
  SpringSet::project_block(const unsigned p, Matrix3Xd &x, const VectorXd &w, double)
  {
    const std::size_t b = parallel[p];
    project_distances(x.data(), w.data(), local_first.data() + b, local_second.data() + b, rest.data() + b,
                      alpha_tilde.data() + b, lambda.data() + b, parallel[p + 1] - b);
  }

  void
  SpringSet::add_constraint_forces_block(const unsigned p, const Matrix3Xd &x, Matrix3Xd &f, const double dt) const
  {
    const std::size_t b = parallel.at(p);
    add_tension_forces(x, f, applied(lambda.data(), dt), from(b), parallel[p + 1] - b,
                       local_first.data(), local_second.data());
  }

  void
  SpringSet::add_constraint_forces_range(const Matrix3Xd &x, Matrix3Xd &f, const double dt, const std::size_t begin,
                                         const std::size_t end) const
  {
    add_tension_forces(x, f, applied(lambda.data(), dt), from(begin),
                       end - begin, first.data(), second.data());
  }

  void
  SpringSet::project_range(Matrix3Xd &x, const VectorXd &w, double, const std::size_t begin,
                           const std::size_t end)
  {
    project_distances(x.data(), w.data(), first.data() + begin, second.data() + begin, rest.data() + begin,
                      alpha_tilde.data() + begin, lambda.data() + begin, end - begin);
  }



  double
  SpringSet::max_violation(const Matrix3Xd &x) const
  {
    double m = 0;
    for (std::size_t s = 0; s < first.size(); ++s)
      if (rest[s] > 0)
        m = std::max(m, std::abs((x.col(second[s]) - x.col(first[s])).norm() - rest[s]) / rest[s]);
    return m;
  }

  std::size_t
  SpringSet::limit_strain(Matrix3Xd &x, const VectorXd &w, const double limit,
                          const unsigned sweeps) const
  {
    std::size_t corrected = 0;
    for (unsigned sweep = 0; sweep < sweeps; ++sweep)
      {
        corrected = 0;
        for (std::size_t s = 0; s < first.size(); ++s)
          {
            const double wa = w[first[s]], wb = w[second[s]];
            if (wa + wb == 0)
              continue;
            const Vector3d d = x.col(second[s]) - x.col(first[s]);
            const double   L = d.norm();
            const double   target =
              std::clamp(L, (1 - limit) * rest[s], (1 + limit) * rest[s]);
            if (L == target || !(L > 0))
              continue;
            const Vector3d correction = (L - target) / (L * (wa + wb)) * d;
            x.col(first[s]) += wa * correction;
            x.col(second[s]) -= wb * correction;
            ++corrected;
          }
        if (corrected == 0)
          break;
      }
    return corrected;
  }

  namespace
  {
    std::uint64_t
    edge_key(const std::uint32_t a, const std::uint32_t b)
    {
      return std::uint64_t(std::min(a, b)) << 32 | std::max(a, b);
    }
  } // namespace

  void
  add_volume_springs(SpringSet &springs, const mesh::SimplexMesh &mesh,
                     const std::vector<std::uint32_t> &node, const double E)
  {
    add_volume_springs(springs, mesh, node, std::vector<double>(mesh.tetrahedra.size(), E));
  }

  void
  add_tetrahedron_edge_springs(SpringSet &springs, const mesh::SimplexMesh &mesh,
                               const std::vector<std::uint32_t>                         &node,
                               const std::function<double(std::size_t, unsigned, unsigned)> &share,
                               const std::function<double(double, double)>                &stiffness)
  {
    // Σ_{T∋e} share per edge, in the order edges are first met (deterministic)
    std::unordered_map<std::uint64_t, std::size_t> index;
    std::vector<std::pair<std::uint64_t, double>>  edges;
    for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
      {
        const auto &v = mesh.tetrahedra[t];
        for (unsigned a = 0; a < 4; ++a)
          for (unsigned b = a + 1; b < 4; ++b)
            {
              const auto [it, inserted] = index.try_emplace(edge_key(v[a], v[b]), edges.size());
              if (inserted)
                edges.emplace_back(edge_key(v[a], v[b]), 0.0);
              edges[it->second].second += share(t, a, b);
            }
      }
    for (const auto &[key, sum] : edges)
      {
        const std::uint32_t a = key >> 32, b = key & 0xffffffffu;
        const double        L = (mesh.vertices.col(a) - mesh.vertices.col(b)).norm();
        if (const double k = stiffness(sum, L); k > 0) // an edge given no stiffness has no spring
          springs.add(node[a], node[b], L, k);
      }
  }

  void
  add_volume_springs(SpringSet &springs, const mesh::SimplexMesh &mesh,
                     const std::vector<std::uint32_t> &node, const std::vector<double> &E)
  {
    if (E.size() != mesh.tetrahedra.size())
      throw std::invalid_argument("add_volume_springs: one Young's modulus per tetrahedron");
    // Σ_{T∋e} E_T V_T per edge, divided by L_e² once
    add_tetrahedron_edge_springs(
      springs, mesh, node, [&](const std::size_t t, unsigned, unsigned) { return E[t] * mesh.volume(t); },
      [](const double EV, const double L) { return EV / (L * L); });
  }

  void
  add_membrane_springs(SpringSet &springs, const Matrix3Xd &vertices,
                       const std::vector<mesh::Triangle> &triangles,
                       const std::vector<std::uint32_t> &node, const double E,
                       const double nu, const double t)
  {
    std::unordered_map<std::uint64_t, std::size_t> index;
    std::vector<std::pair<std::uint64_t, double>>  edges;
    for (const auto &tri : triangles)
      {
        const double area =
          0.5 * (vertices.col(tri[1]) - vertices.col(tri[0]))
                  .cross(vertices.col(tri[2]) - vertices.col(tri[0]))
                  .norm();
        if (!(area > 0))
          throw std::invalid_argument("membrane springs: a degenerate triangle");
        for (unsigned k = 0; k < 3; ++k)
          {
            // edge (a, b) opposite vertex o
            const std::uint32_t o = tri[k], a = tri[(k + 1) % 3], b = tri[(k + 2) % 3];
            const Vector3d      e1 = vertices.col(a) - vertices.col(o);
            const Vector3d      e2 = vertices.col(b) - vertices.col(o);
            const double        cot = e1.dot(e2) / e1.cross(e2).norm();
            const double        L2  = (vertices.col(a) - vertices.col(b)).squaredNorm();
            const double k_edge = E * t * L2 * (2 * cot * cot + 1 - nu) / (8 * (1 - nu * nu) * area);
            const auto [it, inserted] = index.try_emplace(edge_key(a, b), edges.size());
            if (inserted)
              edges.emplace_back(edge_key(a, b), 0.0);
            edges[it->second].second += k_edge;
          }
      }
    for (const auto &[key, k] : edges)
      {
        const std::uint32_t a = key >> 32, b = key & 0xffffffffu;
        springs.add(node[a], node[b], (vertices.col(a) - vertices.col(b)).norm(), k);
      }
  }
} // namespace suturesim::realtime
