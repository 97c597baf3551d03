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
    for (std::size_t k = 0; k < n; ++k)
      {
        const auto            t     = tetrahedra[k];
        const Element        &e     = elements[t];
        const int             local = static_cast<int>(std::find(tets[t].begin(), tets[t].end(), i) - tets[t].begin());
        const Vector3d       &b     = e.b[local];
        const Eigen::Matrix3d F     = realtime::deformation_gradient(x, tets[t], e.b);
        const Eigen::Matrix3d C     = cofactor(F);
        const Vector3d        g     = C * b;
        f.noalias() -= e.volume * (e.mu * F * b + e.lambda * (F.col(0).dot(C.col(0)) - e.gamma) * g);
        H.noalias() += e.volume * (e.mu * b.squaredNorm() * Eigen::Matrix3d::Identity() + e.lambda * g * g.transpose());
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
