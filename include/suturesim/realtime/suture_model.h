#pragma once
/**
 * @file
 * Realtime suture models, registered by name (Realtime/Suture model):
 *  - "mass-spring": a linear chain of masses and springs (seed 001 §3), no bending;
 *  - "ftl": follow-the-leader links of fixed length with two-sided constraint averaging
 *    and quasi-spring tension (seed 002 §3, seed 000 §III), moved geometrically;
 *  - "xpbd-rod": stretch and bending (curvature) constraints, natural under XPBD.
 * Each adds its nodes after the tissue's and its interactions to the System, so any
 * integrator can run it; the FTL suture holds its nodes (they are positioned by the
 * model, not integrated) and reports its own tension.
 */

#include <suturesim/core/registry.h>
#include <suturesim/core/model_parameters.h>
#include <suturesim/realtime/system.h>

#include <vector>

namespace suturesim::realtime
{
  /// The suture as the scene describes it: initial centreline and section.
  struct SutureGeometry
  {
    std::vector<Vector3d> points;      ///< N + 1 nodes, m
    double                radius  = 0; ///< m
    double                EA      = 0; ///< axial stiffness, N
    double                EI      = 0; ///< bending stiffness, N m²
    double                density = 0; ///< kg/m³

    double
    mass_per_length() const;
  };

  /// Seed 002's soft constraint: the suture passes through a pierced tissue point. It
  /// sits at material coordinate @p s (m from the suture's first node), between nodes,
  /// and slides along the suture as the coupling decides (seed 002 §3: "soft constraints
  /// exist at any point between nodes, and slide smoothly as the suture is pulled").
  struct SoftConstraint
  {
    double   s        = 0;
    Vector3d position = Vector3d::Zero(); ///< of the tissue point, m
  };

  /// What the suture does at a soft constraint: the quasi-spring tension of the section
  /// on each side, the direction in which it pulls the tissue point, and how fast each
  /// tension falls per unit of material slid into its section (the slip rule needs it).
  struct SoftConstraintLoad
  {
    double   before = 0, after = 0; ///< towards the first / the last node, N
    Vector3d to_before = Vector3d::Zero(), to_after = Vector3d::Zero(); ///< unit
    double   stiffness_before = 0, stiffness_after = 0; ///< −∂T/∂(material length), N/m
  };

  class SutureModel
  {
  public:
    using Registry = BasicRegistry<SutureModel, ParameterDeclarations, const ParameterValues &>;
    virtual ~SutureModel() = default;

    /// Adds the suture's nodes (after the tissue's) and interactions.
    void
    build(System &system, const SutureGeometry &geometry);

    /// Work before the integrator's step (the FTL update).
    virtual void
    before_step(System &, double)
    {}

    /// True when the model positions its nodes itself (they are held for integrators).
    virtual bool
    geometric() const
    {
      return false;
    }

    /// Force the suture exerts on a tool holding node @p node (N), for models that know
    /// it better than the nodal force balance (FTL's quasi-spring tension); false if
    /// the generic reaction is to be used.
    virtual bool
    holding_force(const System &, std::uint32_t, Vector3d &) const
    {
      return false;
    }

    /// A bound of the stiffness of that force with respect to the held node's position
    /// (N/m): a link's axial stiffness EA/l (the bending springs, ~EI/l³, are far
    /// softer); FTL's quasi-spring constant k_q. A free needle's step (free_needle.h).
    virtual double
    holding_stiffness() const
    {
      return axial_stiffness;
    }

    /// True for models that pass through pierce points as soft constraints (FTL); the
    /// others are coupled to the tissue by forces or constraints.
    virtual bool
    takes_soft_constraints() const
    {
      return false;
    }

    /// The soft constraints for the coming steps, in ascending s.
    virtual void
    set_soft_constraints(const std::vector<SoftConstraint> &)
    {}

    /// The load of each of @p constraints (ascending s; positions as given) with the
    /// suture's nodes at their positions in @p x.
    virtual void
    soft_constraint_loads(const System &, const Matrix3Xd &, const std::vector<SoftConstraint> &,
                          std::vector<SoftConstraintLoad> &) const
    {}

    /// Axial force of each segment (N) at the current state, for output.
    virtual void
    segment_tension(const System &system, std::vector<double> &tension) const;

    /// Leaves the link from local node @p segment to @p segment + 1 out of the suture's
    /// springs (@p out) or gives it its stiffness back, while a constraint stands in for
    /// it (seed 004's node access, realtime/node_access.h). Models whose links are the
    /// "suture springs" (mass-spring, xpbd-rod) can; std::invalid_argument for the others.
    void
    leave_out_link(System &system, std::uint32_t segment, bool out);
    /// The stiffness of that link's spring (also while left out), N/m; the same
    /// std::invalid_argument.
    double
    link_stiffness(const System &system, std::uint32_t segment) const;

    /// Cuts the thread for good between local nodes @p segment and @p segment + 1 (a
    /// surgeon cutting the thread after a knot): each piece then moves and pulls on its
    /// own. Models whose links are springs leave the link's spring out (leave_out_link);
    /// FTL overrides it.
    virtual void
    cut(System &system, std::uint32_t segment)
    {
      leave_out_link(system, segment, true);
    }

    /// Link length l (m).
    double
    link_length() const
    {
      return link;
    }

    const SutureGeometry &
    geometry() const
    {
      return shape;
    }

  protected:
    /// Adds interactions once the nodes exist (first node @p first).
    virtual void
    add_interactions(System &system, std::uint32_t first) = 0;

    SutureGeometry shape;
    /// the stiffness of each link left out (leave_out_link), N/m; 0: in
    std::vector<double> left_out;
    double         link        = 0;
    double         axial_stiffness = 0; ///< k of one link, N/m
  };
} // namespace suturesim::realtime
