#pragma once
/**
 * @file
 * What the families with one element per tetrahedron (volume constraints, neo-Hookean
 * elements, averaged nodal volumes) share: their nodes for vertex block descent, the
 * interface of those solved by forces and vertex blocks only (TetrahedralElements), and
 * the kinematics of a linear tetrahedron, F = Σᵢ xᵢ bᵢᵀ with b₁…b₃ the rows of D_m⁻¹
 * (D_m = [X₁ − X₀, X₂ − X₀, X₃ − X₀]) and b₀ = −(b₁ + b₂ + b₃), and its cofactor.
 */

#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/realtime/system.h>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace suturesim::realtime
{
  /// @p nodes ← the nodes of @p tets, four per element; @p per_element ← 4.
  inline bool
  tetrahedron_element_nodes(const std::vector<mesh::Tetrahedron> &tets, std::vector<std::uint32_t> &nodes,
                            unsigned &per_element)
  {
    per_element = 4;
    nodes.clear();
    nodes.reserve(4 * tets.size());
    for (const auto &t : tets)
      nodes.insert(nodes.end(), t.begin(), t.end());
    return true;
  }

  /// @p touching ← the indices of @p tets with a node flagged in @p touched (for
  /// Interaction::elements_touching).
  inline bool
  tetrahedra_touching(const std::vector<mesh::Tetrahedron> &tets, const std::vector<char> &touched,
                      std::vector<std::uint32_t> &touching)
  {
    touching.clear();
    for (std::size_t t = 0; t < tets.size(); ++t)
      for (const auto i : tets[t])
        if (i < touched.size() && touched[i] != 0)
          {
            touching.push_back(static_cast<std::uint32_t>(t));
            break;
          }
    return true;
  }

  /// A linear tetrahedron's rest shape: ∂F/∂xᵢ = (·) bᵢᵀ and its rest volume V₀.
  struct TetrahedronShape
  {
    std::array<Vector3d, 4> b;
    double                  volume;
  };

  /// The rest shape of tetrahedron @p t of @p mesh; throws naming @p family for a
  /// degenerate one.
  inline TetrahedronShape
  tetrahedron_shape(const mesh::SimplexMesh &mesh, const std::size_t t, const std::string &family)
  {
    const auto     &v = mesh.tetrahedra[t];
    Eigen::Matrix3d Dm;
    for (int k = 0; k < 3; ++k)
      Dm.col(k) = mesh.vertices.col(v[k + 1]) - mesh.vertices.col(v[0]);
    const double V0 = Dm.determinant() / 6;
    if (!(std::abs(V0) > 0))
      throw std::invalid_argument(family + ": tetrahedron " + std::to_string(t) + " is degenerate");
    const Eigen::Matrix3d inverse = Dm.inverse();
    TetrahedronShape      s;
    for (int k = 0; k < 3; ++k)
      s.b[k + 1] = inverse.row(k).transpose();
    s.b[0]   = -(s.b[1] + s.b[2] + s.b[3]);
    s.volume = std::abs(V0);
    return s;
  }

  /// F = Σᵢ xᵢ bᵢᵀ of the tetrahedron of nodes @p nodes at @p x.
  inline Eigen::Matrix3d
  deformation_gradient(const Matrix3Xd &x, const mesh::Tetrahedron &nodes, const std::array<Vector3d, 4> &b)
  {
    Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
    for (int i = 0; i < 4; ++i)
      F.noalias() += x.col(nodes[i]) * b[i].transpose();
    return F;
  }

  /// cof F = J F⁻ᵀ = ∂J/∂F, column by column: (f₂ × f₃, f₃ × f₁, f₁ × f₂) of F's columns
  /// fₖ; defined for singular F too. ∂J/∂xᵢ = cof(F) bᵢ.
  inline Eigen::Matrix3d
  cofactor(const Eigen::Matrix3d &F)
  {
    Eigen::Matrix3d C;
    C.col(0) = F.col(1).cross(F.col(2));
    C.col(1) = F.col(2).cross(F.col(0));
    C.col(2) = F.col(0).cross(F.col(1));
    return C;
  }

  /// The position of node @p i among @p nodes (0–3; 3 if it is none of the first three).
  inline int
  local_index(const mesh::Tetrahedron &nodes, const std::uint32_t i)
  {
    return nodes[0] == i ? 0 : nodes[1] == i ? 1 : nodes[2] == i ? 2 : 3;
  }

  /// Pointers to the positions of the four @p nodes in the column-major 3 × n @p x.
  struct Corners
  {
    const double *p[4];
  };
  inline Corners
  corners(const Matrix3Xd &x, const mesh::Tetrahedron &nodes)
  {
    return { { x.col(nodes[0]).data(), x.col(nodes[1]).data(), x.col(nodes[2]).data(), x.col(nodes[3]).data() } };
  }

  /// ∂V/∂x_k of the tetrahedron (p0, p1, p2, p3) into g[k]: with e_k = p_k − p0,
  /// g1 = e2 × e3 / 6, g2 = e3 × e1 / 6, g3 = e1 × e2 / 6, g0 = −(g1 + g2 + g3);
  /// returns the signed volume V = e1 · g1. V₀ cof(F) bₖ = ±gₖ (F = Σ xₖ bₖᵀ; the sign
  /// is the rest volume's), so a tetrahedron's J and its gradients need no F.
  /// Inline into the multi-versioned kernels (a call would not inherit their target).
  [[gnu::always_inline]] inline double
  volume_gradients(const double *p0, const double *p1, const double *p2, const double *p3, double (&g)[4][3])
  {
    const double     e1[3] = { p1[0] - p0[0], p1[1] - p0[1], p1[2] - p0[2] };
    const double     e2[3] = { p2[0] - p0[0], p2[1] - p0[1], p2[2] - p0[2] };
    const double     e3[3] = { p3[0] - p0[0], p3[1] - p0[1], p3[2] - p0[2] };
    constexpr double sixth = 1.0 / 6;
    g[1][0]                = sixth * (e2[1] * e3[2] - e2[2] * e3[1]);
    g[1][1]                = sixth * (e2[2] * e3[0] - e2[0] * e3[2]);
    g[1][2]                = sixth * (e2[0] * e3[1] - e2[1] * e3[0]);
    g[2][0]                = sixth * (e3[1] * e1[2] - e3[2] * e1[1]);
    g[2][1]                = sixth * (e3[2] * e1[0] - e3[0] * e1[2]);
    g[2][2]                = sixth * (e3[0] * e1[1] - e3[1] * e1[0]);
    g[3][0]                = sixth * (e1[1] * e2[2] - e1[2] * e2[1]);
    g[3][1]                = sixth * (e1[2] * e2[0] - e1[0] * e2[2]);
    g[3][2]                = sixth * (e1[0] * e2[1] - e1[1] * e2[0]);
    for (int d = 0; d < 3; ++d)
      g[0][d] = -(g[1][d] + g[2][d] + g[3][d]);
    return e1[0] * g[1][0] + e1[1] * g[1][1] + e1[2] * g[1][2];
  }

  /// Six times the signed volume V of the tetrahedron (p[0], …, p[3]) and six times its
  /// gradient, @p c, at vertex @p local alone, for a vertex block: V is linear in each
  /// vertex, so V = ∇V · (p_local − p_o) for a vertex p_o of the opposite face, and 6 ∇V
  /// is ± that face's cross product (the terms of volume_gradients() that hold the
  /// vertex). The caller scales (a division in the inner loop costs more than the rest).
  [[gnu::always_inline]] inline double
  six_vertex_volume_gradient(const Corners &corners, const int local, double (&c)[3])
  {
    // the opposite face's origin o and edges o→u, o→w: 6 ∇V = ±(u − o) × (w − o)
    static constexpr int    face[4][3] = { { 1, 2, 3 }, { 0, 2, 3 }, { 0, 3, 1 }, { 0, 1, 2 } };
    static constexpr double sign[4]    = { -1, 1, 1, 1 };
    const auto             &p = corners.p;
    const double           *o = p[face[local][0]], *u = p[face[local][1]], *w = p[face[local][2]];
    const double            a[3] = { u[0] - o[0], u[1] - o[1], u[2] - o[2] };
    const double            b[3] = { w[0] - o[0], w[1] - o[1], w[2] - o[2] };
    c[0]                         = sign[local] * (a[1] * b[2] - a[2] * b[1]);
    c[1]                         = sign[local] * (a[2] * b[0] - a[0] * b[2]);
    c[2]                         = sign[local] * (a[0] * b[1] - a[1] * b[0]);
    const double *q              = p[local];
    return c[0] * (q[0] - o[0]) + c[1] * (q[1] - o[1]) + c[2] * (q[2] - o[2]);
  }

  /// six_vertex_volume_gradient() as V and ∇V, @p g, divided by 6 and V dotted again:
  /// the volume constraints' block's arithmetic, which it keeps bit for bit.
  [[gnu::always_inline]] inline double
  vertex_volume_gradient(const Corners &corners, const int local, double (&g)[3])
  {
    six_vertex_volume_gradient(corners, local, g);
    for (double &c : g)
      c /= 6;
    const double *o = corners.p[local == 0 ? 1 : 0], *q = corners.p[local];
    return g[0] * (q[0] - o[0]) + g[1] * (q[1] - o[1]) + g[2] * (q[2] - o[2]);
  }

  /// A primal family of one element per tetrahedron, solved by forces or vertex blocks
  /// only: its constraint forces are its elastic ones, it has no multipliers, and XPBD,
  /// which would project it, is refused (World, projectable()).
  class TetrahedralElements : public Interaction
  {
  public:
    std::size_t
    size() const override
    {
      return tets.size();
    }
    void
    add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, double) const override
    {
      add_forces(x, f);
    }
    bool
    projectable() const override
    {
      return false;
    }
    bool
    element_nodes(std::vector<std::uint32_t> &nodes, unsigned &per_element) const override
    {
      return tetrahedron_element_nodes(tets, nodes, per_element);
    }
    void
    reset_multipliers() override
    {
    }
    /// Throws: there is no projection (projectable()).
    void
    project(Matrix3Xd &, const VectorXd &, double) override
    {
      throw std::logic_error(name() + " have no XPBD projection (World refuses XPBD with them)");
    }

  protected:
    std::vector<mesh::Tetrahedron> tets; ///< the system nodes of each element
  };
} // namespace suturesim::realtime
