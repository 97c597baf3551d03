#include <suturesim/realtime/hot_kernel.h>
#include <suturesim/realtime/independent_order.h>
#include <suturesim/realtime/tetrahedron_nodes.h>
#include <suturesim/realtime/volume_constraints.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <stdexcept>

namespace suturesim::realtime
{
  void
  VolumeConstraints::add_mesh(const mesh::SimplexMesh &mesh, const std::vector<std::uint32_t> &node,
                              const double K)
  {
    add_mesh(mesh, node, std::vector<double>(mesh.tetrahedra.size(), K));
  }

  void
  VolumeConstraints::add_mesh(const mesh::SimplexMesh &mesh, const std::vector<std::uint32_t> &node,
                              const std::vector<double> &bulk)
  {
    if (bulk.size() != mesh.tetrahedra.size())
      throw std::invalid_argument("volume constraints: one bulk stiffness per tetrahedron");
    for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
      {
        const double K = bulk[t];
        if (!(K > 0))
          throw std::invalid_argument("volume constraints with bulk stiffness <= 0");
        const auto &v = mesh.tetrahedra[t];
        tets.push_back({node[v[0]], node[v[1]], node[v[2]], node[v[3]]});
        const double V0 = mesh.volume(t);
        rest.push_back(V0);
        stiffness.push_back(K / V0);
        lambda.push_back(0);
        alpha_tilde.push_back(0);
      }
    prepared_dt = 0;
    // consecutive tetrahedra share no vertex (independent_order.h)
    std::uint32_t n_nodes = 0;
    for (const auto &v : tets)
      n_nodes = std::max(n_nodes, *std::max_element(v.begin(), v.end()) + 1);
    reorder(independent_order(tets, n_nodes));
    parallel.clear();
  }

  bool
  VolumeConstraints::partition(const std::vector<std::uint32_t> &node_part, const std::vector<std::uint32_t> &local,
                               const unsigned parts)
  {
    const auto blocked = block_order(tets, node_part, parts);
    reorder(blocked.order);
    parallel = blocked.blocks;
    local_tets.resize(parallel[parts]);
    for (std::size_t t = 0; t < local_tets.size(); ++t)
      for (int k = 0; k < 4; ++k)
        local_tets[t][k] = local[tets[t][k]];
    return true;
  }

  void
  VolumeConstraints::reorder(const std::vector<std::size_t> &order)
  {
    permute(tets, order);
    permute(rest, order);
    permute(stiffness, order);
    permute(lambda, order);
    permute(alpha_tilde, order);
    ++changes;
  }

  double
  VolumeConstraints::volume(const Matrix3Xd &x, const std::size_t t) const
  {
    const auto &v = tets[t];
    double      g[4][3];
    return volume_gradients(x.col(v[0]).data(), x.col(v[1]).data(), x.col(v[2]).data(), x.col(v[3]).data(), g);
  }

  double
  VolumeConstraints::energy(const Matrix3Xd &x) const
  {
    double e = 0;
    for (std::size_t t = 0; t < tets.size(); ++t)
      {
        const double c = volume(x, t) - rest[t];
        e += 0.5 * stiffness[t] * c * c;
      }
    return e;
  }

  namespace
  {
    /// The identity: every tetrahedron, in storage order.
    constexpr auto every = [](const std::size_t k) { return k; };
    /// The tetrahedra of a list, in its order.
    auto
    listed(const std::vector<std::uint32_t> &tetrahedra)
    {
      return [T = tetrahedra.data()](const std::size_t k) { return std::size_t(T[k]); };
    }
    /// The tetrahedra of storage positions begin, begin + 1, … (a block or the interface).
    auto
    from(const std::size_t begin)
    {
      return [begin](const std::size_t k) { return begin + k; };
    }
    /// The elastic pressure −(K_v/V₀)(V − V₀).
    auto
    elastic(const double *K, const double *V0)
    {
      return [K, V0](const std::size_t t, const double V) { return -K[t] * (V - V0[t]); };
    }
    /// The pressure the XPBD solve applied, λ/dt².
    auto
    applied(const double *Lambda, const double dt)
    {
      return [Lambda, dt](const std::size_t t, double) { return Lambda[t] / (dt * dt); };
    }
  } // namespace

  template <typename Pressure, typename Tet>
  SUTURESIM_HOT_KERNEL void
  VolumeConstraints::add_pressure_forces(const Matrix3Xd &x, Matrix3Xd &f, const Pressure &pressure, const Tet &tet,
                                         const std::size_t n, const mesh::Tetrahedron *vertices) const
  {
    // a hot kernel as well (XPBD's reactions every tick, the warm start's refresh): raw
    // pointers into the column-major 3 x n arrays, the gradient inline
    const double *X = x.data();
    double       *F = f.data();
    for (std::size_t k = 0; k < n; ++k)
      {
        const std::size_t t = tet(k);
        const auto       &v = vertices[t];
        double            g[4][3];
        const double      p = pressure(t, volume_gradients(X + 3 * std::size_t(v[0]), X + 3 * std::size_t(v[1]),
                                                            X + 3 * std::size_t(v[2]), X + 3 * std::size_t(v[3]), g));
        for (int j = 0; j < 4; ++j)
          for (int c = 0; c < 3; ++c)
            F[3 * std::size_t(v[j]) + c] += p * g[j][c];
      }
  }

  void
  VolumeConstraints::add_forces(const Matrix3Xd &x, Matrix3Xd &f) const
  {
    add_pressure_forces(x, f, elastic(stiffness.data(), rest.data()), every, tets.size(), tets.data());
  }

  void
  VolumeConstraints::add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, const double dt) const
  {
    add_pressure_forces(x, f, applied(lambda.data(), dt), every, tets.size(), tets.data());
  }

  bool
  VolumeConstraints::elements_touching(const std::vector<char> &touched, std::vector<std::uint32_t> &tetrahedra) const
  {
    return tetrahedra_touching(tets, touched, tetrahedra);
  }

  void
  VolumeConstraints::add_forces_of(const Matrix3Xd &x, Matrix3Xd &f, const std::vector<std::uint32_t> &tetrahedra) const
  {
    add_pressure_forces(x, f, elastic(stiffness.data(), rest.data()), listed(tetrahedra), tetrahedra.size(), tets.data());
  }

  void
  VolumeConstraints::add_constraint_forces_of(const Matrix3Xd &x, Matrix3Xd &f, const double dt,
                                              const std::vector<std::uint32_t> &tetrahedra) const
  {
    add_pressure_forces(x, f, applied(lambda.data(), dt), listed(tetrahedra), tetrahedra.size(), tets.data());
  }

  template <typename Pressure>
  SUTURESIM_HOT_KERNEL Vector3d
  VolumeConstraints::pressure_force_on(const Matrix3Xd &x, const Pressure &pressure,
                                       const std::vector<std::uint32_t> &tetrahedra,
                                       const std::vector<char> &touched) const
  {
    const double     *X = x.data();
    const char       *T = touched.data();
    const std::size_t m = touched.size();
    double            sum[3] = {0, 0, 0};
    for (const std::uint32_t t : tetrahedra)
      {
        const auto &v = tets[t];
        double      g[4][3];
        const double p = pressure(t, volume_gradients(X + 3 * std::size_t(v[0]), X + 3 * std::size_t(v[1]),
                                                      X + 3 * std::size_t(v[2]), X + 3 * std::size_t(v[3]), g));
        for (int j = 0; j < 4; ++j)
          if (v[j] < m && T[v[j]] != 0)
            for (int c = 0; c < 3; ++c)
              sum[c] += p * g[j][c];
      }
    return {sum[0], sum[1], sum[2]};
  }

  bool
  VolumeConstraints::add_forces_on(const Matrix3Xd &x, const std::vector<std::uint32_t> &tetrahedra,
                                   const std::vector<char> &touched, Vector3d &sum) const
  {
    sum += pressure_force_on(x, elastic(stiffness.data(), rest.data()), tetrahedra, touched);
    return true;
  }

  bool
  VolumeConstraints::add_constraint_forces_on(const Matrix3Xd &x, const double dt,
                                              const std::vector<std::uint32_t> &tetrahedra,
                                              const std::vector<char> &touched, Vector3d &sum) const
  {
    sum += pressure_force_on(x, applied(lambda.data(), dt), tetrahedra, touched);
    return true;
  }

  bool
  VolumeConstraints::element_nodes(std::vector<std::uint32_t> &nodes, unsigned &per_element) const
  {
    return tetrahedron_element_nodes(tets, nodes, per_element);
  }

  void
  VolumeConstraints::add_vertex_block(const Matrix3Xd &x, const std::uint32_t i, const std::uint32_t *tetrahedra,
                                      const std::size_t n, Vector3d &f, Eigen::Matrix3d &H) const
  {
    for (std::size_t k = 0; k < n; ++k)
      {
        const auto     t = tetrahedra[k];
        double         gradient[3];
        const double   V = vertex_volume_gradient(corners(x, tets[t]), local_index(tets[t], i), gradient);
        const Vector3d g(gradient[0], gradient[1], gradient[2]);
        const double   p = stiffness[t] * (V - rest[t]);
        f -= p * g;
        H.noalias() += stiffness[t] * g * g.transpose();
      }
  }

  void
  VolumeConstraints::reset_multipliers()
  {
    std::fill(lambda.begin(), lambda.end(), 0.0);
  }

  void
  VolumeConstraints::prepare_projection(const double dt)
  {
    if (dt == prepared_dt)
      return;
    prepared_dt = dt;
    for (std::size_t t = 0; t < tets.size(); ++t)
      alpha_tilde[t] = 1 / (stiffness[t] * dt * dt);
  }

  namespace
  {
    /// p_k += s_k g_k for the four vertices.
    [[gnu::always_inline]] inline void
    move_vertices(double *const (&p)[4], const double (&s)[4], const double (&g)[4][3])
    {
      for (int k = 0; k < 4; ++k)
        for (int d = 0; d < 3; ++d)
          p[k][d] += s[k] * g[k][d];
    }

    /// One Gauss–Seidel sweep over n volume constraints (the hot kernel: the gradient
    /// ∂V/∂x_k inline, one division). A free function: GCC multi-versions no virtual
    /// function.
    SUTURESIM_HOT_KERNEL void
    project_volumes(double *X, const double *W, const mesh::Tetrahedron *tets,
                    const double *rest, const double *alpha, double *lambda, const std::size_t n)
    {
      for (std::size_t t = 0; t < n; ++t)
        {
          const auto  &v    = tets[t];
          double *const p[4] = {X + 3 * std::size_t(v[0]), X + 3 * std::size_t(v[1]),
                                X + 3 * std::size_t(v[2]), X + 3 * std::size_t(v[3])};
          double       g[4][3];
          const double c = volume_gradients(p[0], p[1], p[2], p[3], g) - rest[t];
          const double w[4] = {W[v[0]], W[v[1]], W[v[2]], W[v[3]]};
          double       denominator = alpha[t];
          for (int k = 0; k < 4; ++k)
            denominator += w[k] * (g[k][0] * g[k][0] + g[k][1] * g[k][1] + g[k][2] * g[k][2]);
          if (denominator == 0)
            continue;
          const double d_lambda = (-c - alpha[t] * lambda[t]) / denominator;
          lambda[t] += d_lambda;
          move_vertices(p, {w[0] * d_lambda, w[1] * d_lambda, w[2] * d_lambda, w[3] * d_lambda}, g);
        }
    }
  } // namespace

  void
  VolumeConstraints::warm_multipliers(const VectorXd &, const double scale)
  {
    for (auto &l : lambda)
      l *= scale;
  }

  void
  VolumeConstraints::project(Matrix3Xd &x, const VectorXd &w, const double dt)
  {
    project_range(x, w, dt, 0, tets.size());
  }

  void
  VolumeConstraints::project_block(const unsigned p, Matrix3Xd &x, const VectorXd &w, double)
  {
    const std::size_t b = parallel[p];
    project_volumes(x.data(), w.data(), local_tets.data() + b, rest.data() + b, alpha_tilde.data() + b,
                    lambda.data() + b, parallel[p + 1] - b);
  }

  void
  VolumeConstraints::add_constraint_forces_block(const unsigned p, const Matrix3Xd &x, Matrix3Xd &f,
                                                 const double dt) const
  {
    const std::size_t b = parallel.at(p);
    add_pressure_forces(x, f, applied(lambda.data(), dt), from(b),
                        parallel[p + 1] - b, local_tets.data());
  }

  void
  VolumeConstraints::add_constraint_forces_range(const Matrix3Xd &x, Matrix3Xd &f, const double dt,
                                                 const std::size_t begin, const std::size_t end) const
  {
    add_pressure_forces(x, f, applied(lambda.data(), dt), from(begin),
                        end - begin, tets.data());
  }

  void
  VolumeConstraints::project_range(Matrix3Xd &x, const VectorXd &w, double, const std::size_t begin,
                                   const std::size_t end)
  {
    project_volumes(x.data(), w.data(), tets.data() + begin, rest.data() + begin,
                    alpha_tilde.data() + begin, lambda.data() + begin, end - begin);
  }



  double
  VolumeConstraints::max_violation(const Matrix3Xd &x) const
  {
    double m = 0;
    for (std::size_t t = 0; t < tets.size(); ++t)
      m = std::max(m, std::abs(volume(x, t) - rest[t]) / rest[t]);
    return m;
  }
} // namespace suturesim::realtime
