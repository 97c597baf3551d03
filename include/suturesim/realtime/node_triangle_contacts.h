#pragma once
/**
 * @file
 * Contacts of nodes with points of triangles, each pushed apart along a normal n frozen
 * where it was found: with the point's weights b over the triangle's corners and an
 * offset r (a suture's radius; 0 for two surfaces),
 *
 *     g = (p − Σ bₖ xₖ)·n − r,
 *
 * and the response
 *  - force-based integrators: the penalty f = −k min(g, 0) n on the node, −bₖ f on the
 *    corners, the forces of E = Σ ½ k min(g, 0)² with what detection fixed held;
 *  - XPBD: the inequality g ≥ 0 with compliance 1/k (λ ≥ 0; Macklin, Müller & Chentanez
 *    2016, eqs. 17–18).
 * What differs between the sets is what they detect: the suture's (or a tool's) nodes
 * against the tissue's surface (surface_contact.h), one wound face's nodes against the
 * other face (wound_face_contact.h).
 */

#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/realtime/system.h>

#include <vector>

namespace suturesim::realtime
{
  class NodeTriangleContacts : public ContactSet
  {
  public:
    struct Contact
    {
      std::uint32_t  node;
      mesh::Triangle triangle; ///< node indices
      Vector3d       bary;
      Vector3d       normal;
      double         lambda = 0;
    };

    /// Penalty @p k (N/m), offset @p r (m), XPBD projection when @p project.
    NodeTriangleContacts(const double k, const double r, const bool project)
      : penalty(k)
      , offset(r)
      , projected(project)
    {}

    void
    add_forces(const Matrix3Xd &x, Matrix3Xd &f) const override;
    /// E = Σ ½ k min(g, 0)² over the contacts found, their normals and weights held: the
    /// penalty forces are −∂E/∂x at any @p x.
    std::optional<double>
    energy(const Matrix3Xd &x) const override;
    void
    add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, double dt) const override;
    bool
    has_projection() const override
    {
      return projected;
    }
    void
    reset_multipliers() override;
    void
    project(Matrix3Xd &x, const VectorXd &w, double dt) override;
    std::size_t
    active() const override
    {
      return contacts.size();
    }
    const std::vector<Contact> &
    list() const
    {
      return contacts;
    }
    /// Signed gap of contact @p c at @p x (m): negative when the node is closer than r.
    double
    gap(const Contact &c, const Matrix3Xd &x) const;

  protected:
    double               penalty; ///< k, N/m
    double               offset;  ///< r, m
    bool                 projected;
    std::vector<Contact> contacts; ///< what detect() found
  };
} // namespace suturesim::realtime
