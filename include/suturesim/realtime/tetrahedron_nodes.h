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
