#include <suturesim/realtime/hot_kernel.h>
#include <suturesim/realtime/neo_hookean_tetrahedra.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace suturesim::realtime
{
  void
  NeoHookeanTetrahedra::add_mesh(const mesh::SimplexMesh &mesh, const std::vector<std::uint32_t> &node,
                                 const std::vector<double> &mu, const std::vector<double> &lambda)
  {
    const std::size_t n = mesh.tetrahedra.size();
    if (mu.size() != n || lambda.size() != n)
      throw std::invalid_argument("neo-Hookean tetrahedra: one mu and one lambda per tetrahedron");
    for (std::size_t t = 0; t < n; ++t)
      {
        if (!(mu[t] > 0) || !(lambda[t] >= 0))
          throw std::invalid_argument("neo-Hookean tetrahedra: mu must be > 0 and lambda >= 0");
        const auto &v = mesh.tetrahedra[t];
        Element     e{ tetrahedron_shape(mesh, t, "neo-Hookean tetrahedra"), 0, 0, 0 };
        e.mu     = mu[t];
        e.lambda = lambda[t] + mu[t];
        e.gamma  = 1 + e.mu / e.lambda; // the rest state's J − γ balances μ F = μ I
        elements.push_back(e);
        tets.push_back({ node[v[0]], node[v[1]], node[v[2]], node[v[3]] });
        double       g[4][3];
        const double V0 = volume_gradients(mesh.vertices.col(v[0]).data(), mesh.vertices.col(v[1]).data(),
                                           mesh.vertices.col(v[2]).data(), mesh.vertices.col(v[3]).data(), g);
        BlockElement b{ e.volume, e.mu, e.lambda, e.gamma, 1 / (6 * V0), {} };
        for (int i = 0; i < 4; ++i)
          for (int j = 0; j < 4; ++j)
            b.gram[i][j] = e.b[i].dot(e.b[j]);
        block_elements.push_back(b);
      }
  }

  Eigen::Matrix3d
  NeoHookeanTetrahedra::deformation_gradient(const Matrix3Xd &x, const std::size_t t) const
  {
    return realtime::deformation_gradient(x, tets[t], elements[t].b);
  }

  double
  NeoHookeanTetrahedra::energy(const Matrix3Xd &x) const
  {
    double sum = 0;
    for (std::size_t t = 0; t < tets.size(); ++t)
      {
        const Element        &e = elements[t];
        const Eigen::Matrix3d F = realtime::deformation_gradient(x, tets[t], e.b);
        const double          J = F.determinant();
        sum += e.volume
               * (0.5 * e.mu * (F.squaredNorm() - 3)
                  + 0.5 * e.lambda * ((J - e.gamma) * (J - e.gamma) - (1 - e.gamma) * (1 - e.gamma)));
      }
    return sum;
  }

  void
  NeoHookeanTetrahedra::add_element_forces(const Matrix3Xd &x, Matrix3Xd &f, const std::size_t t) const
  {
    const Element        &e = elements[t];
    const Eigen::Matrix3d F = realtime::deformation_gradient(x, tets[t], e.b);
    const Eigen::Matrix3d C = cofactor(F);
    // J = f₁ · (f₂ × f₃), from the cofactor's first column
    const Eigen::Matrix3d P = e.mu * F + e.lambda * (F.col(0).dot(C.col(0)) - e.gamma) * C;
    for (int i = 0; i < 4; ++i)
      f.col(tets[t][i]).noalias() -= e.volume * P * e.b[i];
  }

  void
  NeoHookeanTetrahedra::add_forces(const Matrix3Xd &x, Matrix3Xd &f) const
  {
    for (std::size_t t = 0; t < tets.size(); ++t)
      add_element_forces(x, f, t);
  }

  void
  NeoHookeanTetrahedra::add_forces_of(const Matrix3Xd &x, Matrix3Xd &f,
                                      const std::vector<std::uint32_t> &tetrahedra) const
  {
    for (const auto t : tetrahedra)
      add_element_forces(x, f, t);
  }

  void
  NeoHookeanTetrahedra::add_vertex_block(const Matrix3Xd &x, const std::uint32_t i, const std::uint32_t *tetrahedra,
                                         const std::size_t n, Vector3d &f, Eigen::Matrix3d &H) const
  {
    double fi[3] = { 0, 0, 0 }, Hi[6] = { 0, 0, 0, 0, 0, 0 };
    vertex_block(x, i, tetrahedra, n, fi, Hi);
    f += Vector3d(fi[0], fi[1], fi[2]);
    H += (Eigen::Matrix3d() << Hi[0], Hi[1], Hi[2], Hi[1], Hi[3], Hi[4], Hi[2], Hi[4], Hi[5]).finished();
  }

  SUTURESIM_HOT_KERNEL void
  NeoHookeanTetrahedra::vertex_block(const Matrix3Xd &x, const std::uint32_t i, const std::uint32_t *tetrahedra,
                                     const std::size_t n, double (&f)[3], double (&H)[6]) const
  {
    for (std::size_t k = 0; k < n; ++k)
      {
        const auto          t     = tetrahedra[k];
        const BlockElement &e     = block_elements[t];
        const int           local = local_index(tets[t], i);
        const Corners       p     = corners(x, tets[t]);
        double              g[3]; // 6 ∇ᵢV, then gᵢ = cof(F) bᵢ = ∇ᵢV/V₀
        const double        J = six_vertex_volume_gradient(p, local, g) * e.inverse_six_volume;
        for (double &c : g)
          c *= e.inverse_six_volume;
        const double *G = e.gram[local];
        const double  s = e.lambda * (J - e.gamma);
        for (int d = 0; d < 3; ++d) // F bᵢ = Σⱼ xⱼ (bⱼ · bᵢ)
          f[d] -= e.volume * (e.mu * (p.p[0][d] * G[0] + p.p[1][d] * G[1] + p.p[2][d] * G[2] + p.p[3][d] * G[3]) +
                              s * g[d]);
        const double a = e.volume * e.mu * G[local], b = e.volume * e.lambda;
        H[0] += a + b * g[0] * g[0];
        H[1] += b * g[0] * g[1];
        H[2] += b * g[0] * g[2];
        H[3] += a + b * g[1] * g[1];
        H[4] += b * g[1] * g[2];
        H[5] += a + b * g[2] * g[2];
      }
  }

  double
  NeoHookeanTetrahedra::max_violation(const Matrix3Xd &x) const
  {
    double m = 0;
    for (std::size_t t = 0; t < tets.size(); ++t)
      m = std::max(m, std::abs(deformation_gradient(x, t).determinant() - 1));
    return m;
  }
} // namespace suturesim::realtime
