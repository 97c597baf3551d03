#include <suturesim/realtime/volume_constraints.h>

#include <Eigen/Geometry>

#include <stdexcept>

namespace suturesim::realtime
{
  void
  VolumeConstraints::add_mesh(const mesh::SimplexMesh &mesh, const std::vector<std::uint32_t> &node,
                              const double K)
  {
    if (!(K > 0))
      throw std::invalid_argument("volume constraints with bulk stiffness <= 0");
    for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
      {
        const auto &v = mesh.tetrahedra[t];
        tets.push_back({node[v[0]], node[v[1]], node[v[2]], node[v[3]]});
        const double V0 = mesh.volume(t);
        rest.push_back(V0);
        stiffness.push_back(K / V0);
        lambda.push_back(0);
      }
  }

  double
  VolumeConstraints::volume(const Matrix3Xd &x, const std::size_t t,
                            std::array<Vector3d, 4> &g) const
  {
    const auto    &v  = tets[t];
    const Vector3d e1 = x.col(v[1]) - x.col(v[0]);
    const Vector3d e2 = x.col(v[2]) - x.col(v[0]);
    const Vector3d e3 = x.col(v[3]) - x.col(v[0]);
    g[1]              = e2.cross(e3) / 6;
    g[2]              = e3.cross(e1) / 6;
    g[3]              = e1.cross(e2) / 6;
    g[0]              = -(g[1] + g[2] + g[3]);
    return e1.dot(g[1]);
  }

  double
  VolumeConstraints::energy(const Matrix3Xd &x) const
  {
    std::array<Vector3d, 4> g;
    double                  e = 0;
    for (std::size_t t = 0; t < tets.size(); ++t)
      {
        const double c = volume(x, t, g) - rest[t];
        e += 0.5 * stiffness[t] * c * c;
      }
    return e;
  }

  void
  VolumeConstraints::add_forces(const Matrix3Xd &x, Matrix3Xd &f) const
  {
    std::array<Vector3d, 4> g;
    for (std::size_t t = 0; t < tets.size(); ++t)
      {
        const double p = -stiffness[t] * (volume(x, t, g) - rest[t]);
        for (unsigned k = 0; k < 4; ++k)
          f.col(tets[t][k]) += p * g[k];
      }
  }

  void
  VolumeConstraints::reset_multipliers()
  {
    std::fill(lambda.begin(), lambda.end(), 0.0);
  }

  void
  VolumeConstraints::project(Matrix3Xd &x, const VectorXd &w, const double dt)
  {
    std::array<Vector3d, 4> g;
    const double            inv_dt2 = 1 / (dt * dt);
    for (std::size_t t = 0; t < tets.size(); ++t)
      {
        const auto  &v     = tets[t];
        const double c     = volume(x, t, g) - rest[t];
        const double alpha = inv_dt2 / stiffness[t];
        double       denominator = alpha;
        for (unsigned k = 0; k < 4; ++k)
          denominator += w[v[k]] * g[k].squaredNorm();
        if (denominator == 0)
          continue;
        const double d_lambda = (-c - alpha * lambda[t]) / denominator;
        lambda[t] += d_lambda;
        for (unsigned k = 0; k < 4; ++k)
          x.col(v[k]) += w[v[k]] * d_lambda * g[k];
      }
  }

  double
  VolumeConstraints::max_violation(const Matrix3Xd &x) const
  {
    std::array<Vector3d, 4> g;
    double                  m = 0;
    for (std::size_t t = 0; t < tets.size(); ++t)
      m = std::max(m, std::abs(volume(x, t, g) - rest[t]) / rest[t]);
    return m;
  }
} // namespace suturesim::realtime
