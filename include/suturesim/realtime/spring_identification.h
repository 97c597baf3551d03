#pragma once
/**
 * @file
 * Spring constants identified from the linear finite element: the springs of a
 * tetrahedron are given the stiffness matrix of its linear FE model as nearly as a
 * spring network can (Lloyd, Székely & Harders 2007, "Identification of spring
 * parameters for deformable object simulation", IEEE TVCG 13(5):1081–1094).
 *
 * Per tetrahedron T with vertices X_a, the six edge springs e = (a, b) of rest direction
 * n_e, linearised at rest, have the stiffness matrix
 *   K_S(k) = Σ_e k_e G_e,   G_e = (δ_a − δ_b)(δ_a − δ_b)ᵀ ⊗ n_e n_eᵀ   (12 × 12),
 * and the constant-strain (P1) element of an isotropic material (μ, λ)
 *   K_FE[a i, b j] = V_T (λ g_ai g_bj + μ g_aj g_bi + μ δ_ij g_a·g_b),   g_a = ∇N_a.
 * A central-force network obeys the Cauchy relation λ = μ (ν = 1/4), so the springs are
 * matched to K_FE(μ, λ = μ), μ the material's shear modulus, and volume constraints
 * (volume_constraints.h) add the bulk stiffness the network lacks (Golec et al. 2020,
 * "Hybrid 3D mass-spring system for soft tissue simulation", Vis. Comput. 36:809, who
 * give K − 5μ/3; here K minus the network's own bulk modulus, network_bulk_modulus(), so
 * that a uniform dilatation is exact on any mesh).
 *
 * Two rules:
 *  - least_squares_springs(): the six k minimising the Frobenius norm ‖K_S(k) − K_FE‖,
 *    a 6 × 6 linear least-squares problem per tetrahedron (Lloyd et al.'s criterion,
 *    solved for each tetrahedron's own shape). On the regular tetrahedron of edge l it
 *    gives k = (√2/5) μ l on every edge, 2√2 E l/25 at ν = 1/4 (tested), the paper's
 *    value; no k matches that element exactly (the residual is 20 % of ‖K_FE‖), since
 *    the six edge directions are not an isotropic set. A constant the fit makes
 *    negative, possible on a flat tetrahedron, is set to zero.
 *  - lloyd_springs(): the paper's closed form for irregular meshes, each tetrahedron
 *    treated as the regular one of its volume: k = (√2/5) μ l̃ on each of its edges,
 *    l̃ = (12 V/√2)^(1/3) (as restated by Golec et al. 2020).
 */

#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/realtime/spring_set.h>

#include <Eigen/Core>

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace suturesim::realtime
{
  /// The edges of a tetrahedron in the order of the constants below: (0,1), (0,2),
  /// (0,3), (1,2), (1,3), (2,3).
  inline constexpr std::array<std::array<unsigned, 2>, 6> tetrahedron_edges{
    {{0, 1}, {0, 2}, {0, 3}, {1, 2}, {1, 3}, {2, 3}}};

  /// The P1 element stiffness matrix (above) of the tetrahedron @p X for Lamé
  /// parameters @p mu, @p lambda (Pa); rows and columns 3a + i; either orientation.
  /// std::invalid_argument for a flat tetrahedron (volume below 10⁻¹² of its longest
  /// edge cubed).
  Eigen::Matrix<double, 12, 12>
  tetrahedron_stiffness(const std::array<Eigen::Vector3d, 4> &X, double mu, double lambda);

  /// K_S(k) (above) for the edge constants @p k (N/m).
  Eigen::Matrix<double, 12, 12>
  spring_stiffness(const std::array<Eigen::Vector3d, 4> &X, const std::array<double, 6> &k);

  /// The six edge constants (N/m) for shear modulus @p mu (Pa) by least squares (above).
  std::array<double, 6>
  least_squares_springs(const std::array<Eigen::Vector3d, 4> &X, double mu);

  /// The six edge constants (N/m) for shear modulus @p mu (Pa) by Lloyd et al.'s closed
  /// form (above).
  std::array<double, 6>
  lloyd_springs(const std::array<Eigen::Vector3d, 4> &X, double mu);

  /// The bulk modulus (Pa) of the tetrahedron's springs @p k: under x = (1 + e) X each
  /// edge stretches by e L_e, so they store Σ ½ k_e L_e² e² = ½ 9 K V e², K = Σ k_e L_e²/(9V).
  double
  network_bulk_modulus(const std::array<Eigen::Vector3d, 4> &X, const std::array<double, 6> &k);

  /// One spring per tetrahedron edge of @p mesh by the rule @p law ("lloyd" or "least
  /// squares"), k_e the sum over the tetrahedra around the edge of their constants for
  /// @p shear_modulus (one μ per tetrahedron, Pa), times @p scale; @p node maps mesh
  /// vertices to system nodes. Returns each tetrahedron's network_bulk_modulus() at
  /// scale 1. std::invalid_argument for another law or a wrong count.
  std::vector<double>
  add_identified_volume_springs(SpringSet &springs, const mesh::SimplexMesh &mesh,
                                const std::vector<std::uint32_t> &node, const std::string &law,
                                const std::vector<double> &shear_modulus, double scale);
} // namespace suturesim::realtime
