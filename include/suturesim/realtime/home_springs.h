#pragma once
/**
 * @file
 * Home springs (seed 001 §2.1): zero-rest-length springs from a node to its home H,
 * F = K_h (H − P), energy ½ K_h |P − H|². They keep a surface model's shape and restore
 * it after a load is removed (seed 001, Fig. 1). Under XPBD: C = P − H (three
 * components, each with gradient eᵢ), compliance 1/K_h, solved in closed form per node.
 *
 * The stiffness rule for a tissue surface on a deep body (surface_tissue.cc): the
 * Winkler foundation of a layer of depth H_f bonded to a rigid base, K_h = A_i E_oed/H_f
 * with A_i the node's share of the surface area and E_oed = E(1 − ν)/((1 + ν)(1 − 2ν))
 * the constrained (oedometric) modulus — exact for a uniform normal load on a thin layer
 * (Kerr 1964, "Elastic and viscoelastic foundation models", J. Appl. Mech. 31:491).
 */

#include <suturesim/realtime/system.h>

#include <vector>

namespace suturesim::realtime
{
  class HomeSprings : public Interaction
  {
  public:
    std::string
    name() const override
    {
      return "home springs";
    }
    std::size_t
    size() const override
    {
      return nodes.size();
    }

    /// A home spring of stiffness @p k (N/m) from node @p i to @p home (m).
    void
    add(std::uint32_t i, const Vector3d &home, double k);

    /// Index of node @p i's home spring, or size() if it has none.
    std::size_t
    find(std::uint32_t i) const;
    /// Home spring @p s gets home @p home (m) and stiffness @p k (N/m): a node whose share of
    /// the surface changed (seed 002's subdivision), or a spare node taken into use.
    void
    set(std::size_t s, const Vector3d &home, double k);
    double
    stiffness_of(std::size_t s) const
    {
      return stiffness[s];
    }

    double
    energy(const Matrix3Xd &x) const override;
    void
    add_forces(const Matrix3Xd &x, Matrix3Xd &f) const override;
    void
    add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, double dt) const override;
    bool
    element_nodes(std::vector<std::uint32_t> &nodes, unsigned &per_element) const override;
    /// f = k (H − P), H = k I
    void
    add_vertex_block(const Matrix3Xd &x, std::uint32_t i, const std::uint32_t *springs, std::size_t n, Vector3d &f,
                     Eigen::Matrix3d &H) const override;
    void
    reset_multipliers() override;
    void
    warm_multipliers(const VectorXd &w, double scale) override;
    void
    project(Matrix3Xd &x, const VectorXd &w, double dt) override;
    /// max |P − H| (m): a home spring has no natural length scale
    double
    max_violation(const Matrix3Xd &x) const override;

  private:
    std::vector<std::uint32_t> nodes;
    Matrix3Xd                  home;
    std::vector<double>        stiffness;
    Matrix3Xd                  lambda;
  };
} // namespace suturesim::realtime
