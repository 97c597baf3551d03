#include <suturesim/realtime/spring_identification.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace suturesim::realtime
{
  namespace
  {
    using Matrix12 = Eigen::Matrix<double, 12, 12>;

    /// The volume of the tetrahedron @p X, either orientation.
    double
    volume(const std::array<Eigen::Vector3d, 4> &X)
    {
      return std::abs((X[1] - X[0]).cross(X[2] - X[0]).dot(X[3] - X[0])) / 6;
    }

    /// G_e of the edge (a, b) (header): ±n nᵀ in the blocks of its two vertices.
    Matrix12
    edge_matrix(const std::array<Eigen::Vector3d, 4> &X, const unsigned a, const unsigned b)
    {
      const Eigen::Vector3d n   = (X[b] - X[a]).normalized();
      const Eigen::Matrix3d nnT = n * n.transpose();
      Matrix12              G   = Matrix12::Zero();
      G.block<3, 3>(3 * a, 3 * a) = nnT;
      G.block<3, 3>(3 * b, 3 * b) = nnT;
      G.block<3, 3>(3 * a, 3 * b) = -nnT;
      G.block<3, 3>(3 * b, 3 * a) = -nnT;
      return G;
    }
  } // namespace

  Matrix12
  tetrahedron_stiffness(const std::array<Eigen::Vector3d, 4> &X, const double mu, const double lambda)
  {
    Eigen::Matrix3d Dm;
    for (int c = 0; c < 3; ++c)
      Dm.col(c) = X[c + 1] - X[0];
    double longest = 0;
    for (const auto &[a, b] : tetrahedron_edges)
      longest = std::max(longest, (X[b] - X[a]).norm());
    const double V = volume(X);
    if (!(V > 1e-12 * longest * longest * longest))
      throw std::invalid_argument("tetrahedron_stiffness: a flat tetrahedron");
    // ∇N_1..3 are the rows of Dm⁻¹; ∇N_0 = −their sum
    const Eigen::Matrix3d          inverse = Dm.inverse();
    std::array<Eigen::Vector3d, 4> g;
    for (int a = 1; a < 4; ++a)
      g[a] = inverse.row(a - 1).transpose();
    g[0] = -(g[1] + g[2] + g[3]);
    Matrix12 K;
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        K.block<3, 3>(3 * a, 3 * b) = V * (lambda * g[a] * g[b].transpose() + mu * g[b] * g[a].transpose() +
                                           mu * g[a].dot(g[b]) * Eigen::Matrix3d::Identity());
    return K;
  }

  Matrix12
  spring_stiffness(const std::array<Eigen::Vector3d, 4> &X, const std::array<double, 6> &k)
  {
    Matrix12 K = Matrix12::Zero();
    for (unsigned e = 0; e < 6; ++e)
      K += k[e] * edge_matrix(X, tetrahedron_edges[e][0], tetrahedron_edges[e][1]);
    return K;
  }

  std::array<double, 6>
  least_squares_springs(const std::array<Eigen::Vector3d, 4> &X, const double mu)
  {
    const Matrix12          K = tetrahedron_stiffness(X, mu, mu);
    std::array<Matrix12, 6> G;
    for (unsigned e = 0; e < 6; ++e)
      G[e] = edge_matrix(X, tetrahedron_edges[e][0], tetrahedron_edges[e][1]);
    // normal equations of min ‖Σ k_e G_e − K‖_F: ⟨G_e, G_f⟩ k = ⟨G_e, K⟩
    Eigen::Matrix<double, 6, 6> A;
    Eigen::Matrix<double, 6, 1> rhs;
    for (unsigned e = 0; e < 6; ++e)
      {
        rhs[e] = G[e].cwiseProduct(K).sum();
        for (unsigned f = 0; f < 6; ++f)
          A(e, f) = G[e].cwiseProduct(G[f]).sum();
      }
    const Eigen::Matrix<double, 6, 1> solution = A.ldlt().solve(rhs);
    std::array<double, 6>             k;
    for (unsigned e = 0; e < 6; ++e)
      k[e] = std::max(solution[e], 0.0);
    return k;
  }

  std::array<double, 6>
  lloyd_springs(const std::array<Eigen::Vector3d, 4> &X, const double mu)
  {
    const double l = std::cbrt(12 * volume(X) / std::sqrt(2.0)); // the regular tetrahedron of volume V
    std::array<double, 6> k;
    k.fill(std::sqrt(2.0) / 5 * mu * l);
    return k;
  }

  double
  network_bulk_modulus(const std::array<Eigen::Vector3d, 4> &X, const std::array<double, 6> &k)
  {
    double sum = 0;
    for (unsigned e = 0; e < 6; ++e)
      sum += k[e] * (X[tetrahedron_edges[e][1]] - X[tetrahedron_edges[e][0]]).squaredNorm();
    return sum / (9 * volume(X));
  }

  std::vector<double>
  add_identified_volume_springs(SpringSet &springs, const mesh::SimplexMesh &mesh,
                                const std::vector<std::uint32_t> &node, const std::string &law,
                                const std::vector<double> &shear_modulus, const double scale)
  {
    if (shear_modulus.size() != mesh.tetrahedra.size())
      throw std::invalid_argument("add_identified_volume_springs: one shear modulus per tetrahedron");
    if (law != "lloyd" && law != "least squares")
      throw std::invalid_argument("add_identified_volume_springs: no spring law '" + law + "'");
    std::vector<std::array<double, 6>> k(mesh.tetrahedra.size());
    std::vector<double>                bulk(k.size());
    for (std::size_t t = 0; t < k.size(); ++t)
      {
        std::array<Eigen::Vector3d, 4> X;
        for (unsigned a = 0; a < 4; ++a)
          X[a] = mesh.vertices.col(mesh.tetrahedra[t][a]);
        k[t]    = law == "lloyd" ? lloyd_springs(X, shear_modulus[t]) : least_squares_springs(X, shear_modulus[t]);
        bulk[t] = network_bulk_modulus(X, k[t]);
      }
    // the edge (a, b), a < b, of the local numbering is tetrahedron_edges' index
    const auto edge_index = [](const unsigned a, const unsigned b) { return a == 0 ? b - 1 : a + b; };
    add_tetrahedron_edge_springs(
      springs, mesh, node,
      [&](const std::size_t t, const unsigned a, const unsigned b) { return scale * k[t][edge_index(a, b)]; },
      [](const double sum, double) { return sum; });
    return bulk;
  }
} // namespace suturesim::realtime
