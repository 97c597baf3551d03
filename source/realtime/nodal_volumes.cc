#include <suturesim/realtime/nodal_volumes.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace suturesim::realtime
{
  namespace
  {
    constexpr std::uint32_t none  = std::numeric_limits<std::uint32_t>::max();
    constexpr double        sixth = 1.0 / 6;
  } // namespace

  void
  NodalVolumes::add_mesh(const mesh::SimplexMesh &mesh, const std::vector<std::uint32_t> &node,
                         const std::vector<double> &lambda)
  {
    const std::size_t n = mesh.tetrahedra.size();
    if (lambda.size() != n)
      throw std::invalid_argument("averaged nodal volumes: one lambda per tetrahedron");
    if (!tets.empty()) // the nodes' λ_a and V_a are final below
      throw std::logic_error("averaged nodal volumes: one mesh per family");
    std::vector<std::uint32_t> local_of; // system node → per-node index (or none)
    for (std::size_t t = 0; t < n; ++t)
      {
        if (!(lambda[t] >= 0))
          throw std::invalid_argument("averaged nodal volumes: lambda must be >= 0");
        const auto &v = mesh.tetrahedra[t];
        const double volume = tetrahedron_shape(mesh, t, "averaged nodal volumes").volume; // throws if degenerate
        Element      e{ mesh.volume(t) > 0 ? 1.0 : -1.0, {} };
        for (int k = 0; k < 4; ++k)
          {
            const std::uint32_t i = node[v[k]];
            if (i >= local_of.size())
              local_of.resize(i + 1, none);
            if (local_of[i] == none)
              {
                local_of[i] = static_cast<std::uint32_t>(rest_volume.size());
                rest_volume.push_back(0);
                modulus.push_back(0);
              }
            e.local[k] = local_of[i];
            rest_volume[e.local[k]] += volume / 4;
            modulus[e.local[k]] += lambda[t] * volume / 4;
          }
        elements.push_back(e);
        tets.push_back({ node[v[0]], node[v[1]], node[v[2]], node[v[3]] });
      }
    // λ_a so far holds Σ λ_e V_e/4; every node's V_a > 0 (it belongs to a tetrahedron)
    for (std::size_t a = 0; a < modulus.size(); ++a)
      {
        modulus[a] = modulus[a] / rest_volume[a];
        inverse_rest_volume.push_back(1 / rest_volume[a]);
      }
    volume_now.assign(tets.size(), 0);
    nodal_now.assign(rest_volume.size(), 0);
    work.assign(rest_volume.size(), 0);
    gradient.assign(rest_volume.size(), Vector3d::Zero());
    block_pending.assign(rest_volume.size(), 0);
    block_position.assign(rest_volume.size(), Vector3d::Zero());
    block_gradient.assign(4 * tets.size(), Vector3d::Zero());
  }

  double
  NodalVolumes::current_volume(const Matrix3Xd &x, const std::size_t t) const
  {
    const Corners p = corners(x, tets[t]);
    double        g[4][3];
    return elements[t].orientation * volume_gradients(p.p[0], p.p[1], p.p[2], p.p[3], g);
  }

  void
  NodalVolumes::nodal_volumes(const Matrix3Xd &x, std::vector<double> &v, std::vector<double> *element_volumes) const
  {
    std::fill(v.begin(), v.end(), 0.0);
    for (std::size_t t = 0; t < tets.size(); ++t)
      {
        const double volume = current_volume(x, t);
        if (element_volumes)
          (*element_volumes)[t] = volume;
        for (const auto a : elements[t].local)
          v[a] += volume / 4;
      }
  }

  double
  NodalVolumes::energy(const Matrix3Xd &x) const
  {
    nodal_volumes(x, work);
    double sum = 0;
    for (std::size_t a = 0; a < work.size(); ++a)
      {
        const double e = work[a] / rest_volume[a] - 1;
        sum += 0.5 * rest_volume[a] * modulus[a] * e * e;
      }
    return sum;
  }

  void
  NodalVolumes::nodal_pressures(const Matrix3Xd &x) const
  {
    nodal_volumes(x, work);
    for (std::size_t a = 0; a < work.size(); ++a) // v_a → the node's pressure λ_a (J_a − 1)
      work[a] = modulus[a] * (work[a] / rest_volume[a] - 1);
  }

  void
  NodalVolumes::add_element_forces(const Matrix3Xd &x, Matrix3Xd &f, const std::size_t t) const
  {
    const Element &e = elements[t];
    const double   p = (work[e.local[0]] + work[e.local[1]] + work[e.local[2]] + work[e.local[3]]) / 4;
    const Corners  c = corners(x, tets[t]);
    double         g[4][3]; // V_e cof(F_e) bᵢ = ±∇ᵢV
    volume_gradients(c.p[0], c.p[1], c.p[2], c.p[3], g);
    for (int i = 0; i < 4; ++i)
      f.col(tets[t][i]) -= p * e.orientation * Vector3d(g[i][0], g[i][1], g[i][2]);
  }

  void
  NodalVolumes::add_forces(const Matrix3Xd &x, Matrix3Xd &f) const
  {
    nodal_pressures(x);
    for (std::size_t t = 0; t < tets.size(); ++t)
      add_element_forces(x, f, t);
  }

  void
  NodalVolumes::add_forces_of(const Matrix3Xd &x, Matrix3Xd &f, const std::vector<std::uint32_t> &tetrahedra) const
  {
    nodal_pressures(x); // every element's volume: the listed ones' nodes have others
    for (const auto t : tetrahedra)
      add_element_forces(x, f, t);
  }

  void
  NodalVolumes::begin_sweep(const Matrix3Xd &x)
  {
    nodal_volumes(x, nodal_now, &volume_now);
  }

  void
  NodalVolumes::vertex_moved(const Matrix3Xd &x, const std::uint32_t i, const std::uint32_t *tetrahedra,
                             const std::size_t n)
  {
    if (n == 0)
      return;
    // after this vertex's own block (the descent's order), each v_e changes by
    // ∂v_e/∂xᵢ · Δxᵢ exactly, v_e being linear in each vertex; else recomputed
    const std::uint32_t own         = node_of(tetrahedra[0], i);
    const bool          after_block = block_pending[own] != 0;
    const Vector3d      step        = x.col(i) - block_position[own];
    block_pending[own]              = 0;
    for (std::size_t k = 0; k < n; ++k)
      {
        const auto   t = tetrahedra[k];
        const double v = after_block ? volume_now[t] + block_gradient[4 * t + local_index(tets[t], i)].dot(step)
                                     : current_volume(x, t);
        const double delta = (v - volume_now[t]) / 4;
        volume_now[t]      = v;
        for (const auto a : elements[t].local)
          nodal_now[a] += delta;
      }
  }

  void
  NodalVolumes::add_vertex_block(const Matrix3Xd &x, const std::uint32_t i, const std::uint32_t *tetrahedra,
                                 const std::size_t n, Vector3d &f, Eigen::Matrix3d &H) const
  {
    if (n == 0)
      return;
    // g_a = ∂v_a/∂xᵢ summed node by node over i's elements; f from the elements' mean
    // pressures. What a block writes is its own node's, its elements' or their nodes'
    // (gradient[a]), so blocks of nodes two elements apart can run at once.
    const std::uint32_t own = node_of(tetrahedra[0], i);
    block_pending[own]      = 1;
    block_position[own]     = x.col(i);
    for (std::size_t k = 0; k < n; ++k)
      {
        const auto     t     = tetrahedra[k];
        const Element &e     = elements[t];
        const int      local = local_index(tets[t], i);
        double         grad[3]; // ∂v_e/∂xᵢ = V_e cof(F_e) bᵢ = ±∇ᵢV = ±6 ∇ᵢV / 6
        six_vertex_volume_gradient(corners(x, tets[t]), local, grad);
        const Vector3d dv             = e.orientation * sixth * Vector3d(grad[0], grad[1], grad[2]);
        const Vector3d g              = dv / 4;
        block_gradient[4 * t + local] = dv;
        double p                      = 0;
        for (const auto a : e.local)
          {
            p += modulus[a] * (nodal_now[a] * inverse_rest_volume[a] - 1);
            gradient[a] += g;
          }
        f.noalias() -= p * g;
      }
    // each node's g_a once, where it is first met (a g_a of exactly zero adds nothing)
    for (std::size_t k = 0; k < n; ++k)
      for (const auto a : elements[tetrahedra[k]].local)
        if (!gradient[a].isZero(0))
          {
            H.noalias() += modulus[a] * inverse_rest_volume[a] * gradient[a] * gradient[a].transpose();
            gradient[a].setZero();
          }
  }

  double
  NodalVolumes::max_violation(const Matrix3Xd &x) const
  {
    nodal_volumes(x, work);
    double m = 0;
    for (std::size_t a = 0; a < work.size(); ++a)
      m = std::max(m, std::abs(work[a] / rest_volume[a] - 1));
    return m;
  }
} // namespace suturesim::realtime
