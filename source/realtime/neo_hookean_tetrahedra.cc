#include <suturesim/realtime/neo_hookean_tetrahedra.h>
#include <suturesim/realtime/tetrahedron_nodes.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace suturesim::realtime
{
  namespace
  {
    /// cof F = J F⁻ᵀ, column by column: (f₂ × f₃, f₃ × f₁, f₁ × f₂) of F's columns fₖ;
    /// defined for singular F too.
    Eigen::Matrix3d
    cofactor(const Eigen::Matrix3d &F)
    {
      Eigen::Matrix3d C;
      C.col(0) = F.col(1).cross(F.col(2));
      C.col(1) = F.col(2).cross(F.col(0));
      C.col(2) = F.col(0).cross(F.col(1));
      return C;
    }
  } // namespace

  void
  NeoHookeanTetrahedra::add_mesh(const mesh::SimplexMesh &mesh, const std::vector<std::uint32_t> &node,
                                 const std::vector<double> &mu, const std::vector<double> &lambda)
  {
    const std::size_t n = mesh.tetrahedra.size();
    if (mu.size() != n || lambda.size() != n)
      throw std::invalid_argument("neo-Hookean tetrahedra: one mu and one lambda per tetrahedron");
    for (std::size_t t = 0; t < n; ++t)
      {
        if (!(mu[t] > 0) || !(lambda[t] > 0))
          throw std::invalid_argument("neo-Hookean tetrahedra: mu and lambda must be > 0 (nu in (0, 1/2))");
        const auto     &v = mesh.tetrahedra[t];
        Eigen::Matrix3d Dm;
        for (int k = 0; k < 3; ++k)
          Dm.col(k) = mesh.vertices.col(v[k + 1]) - mesh.vertices.col(v[0]);
        const double V0 = Dm.determinant() / 6;
        if (!(std::abs(V0) > 0))
          throw std::invalid_argument("neo-Hookean tetrahedra: tetrahedron " + std::to_string(t) + " is degenerate");
        const Eigen::Matrix3d inverse = Dm.inverse();
        Element               e;
        for (int k = 0; k < 3; ++k)
          e.b[k + 1] = inverse.row(k).transpose();
        e.b[0]   = -(e.b[1] + e.b[2] + e.b[3]);
        e.volume = std::abs(V0);
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
    Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
    for (int i = 0; i < 4; ++i)
      F.noalias() += x.col(tets[t][i]) * elements[t].b[i].transpose();
    return F;
  }

  double
  NeoHookeanTetrahedra::energy(const Matrix3Xd &x) const
  {
    double sum = 0;
    for (std::size_t t = 0; t < tets.size(); ++t)
      {
        const Element        &e = elements[t];
        const Eigen::Matrix3d F = deformation_gradient(x, t);
        const double          J = F.determinant();
        sum += e.volume
               * (0.5 * e.mu * (F.squaredNorm() - 3)
                  + 0.5 * e.lambda * ((J - e.gamma) * (J - e.gamma) - (1 - e.gamma) * (1 - e.gamma)));
      }
    return sum;
  }

  void
  NeoHookeanTetrahedra::project(Matrix3Xd &, const VectorXd &, double)
  {
    throw std::logic_error("neo-Hookean tetrahedra have no XPBD projection (World refuses XPBD with them)");
  }

  void
  NeoHookeanTetrahedra::add_forces(const Matrix3Xd &x, Matrix3Xd &f) const
  {
    for (std::size_t t = 0; t < tets.size(); ++t)
      {
        const Element        &e = elements[t];
        const Eigen::Matrix3d F = deformation_gradient(x, t);
        const Eigen::Matrix3d C = cofactor(F);
        // J = f₁ · (f₂ × f₃), from the cofactor's first column
        const Eigen::Matrix3d P = e.mu * F + e.lambda * (F.col(0).dot(C.col(0)) - e.gamma) * C;
        for (int i = 0; i < 4; ++i)
          f.col(tets[t][i]).noalias() -= e.volume * P * e.b[i];
      }
  }

  bool
  NeoHookeanTetrahedra::element_nodes(std::vector<std::uint32_t> &nodes, unsigned &per_element) const
  {
    return tetrahedron_element_nodes(tets, nodes, per_element);
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
        const Eigen::Matrix3d F     = deformation_gradient(x, t);
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
