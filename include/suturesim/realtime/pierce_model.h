#pragma once
/**
 * @file
 * How a realtime pierce point holds on to the thread and slips along it, registered by
 * name (`Realtime/Pierce model`), one self-contained file per model under
 * source/realtime/pierce_models/. The needle coupling (realtime/needle_coupling.h) owns
 * the points, their tie across the thread and their order; the model decides the rest:
 *  - "node-path" (seed 004; node_path.cc): the point's anchor is any thread coordinate
 *    ζ_a; the tie along the thread is an elastic stick with Coulomb's limit by return
 *    mapping (coupling/coulomb_friction.h), so the anchor slides continuously at |f| = μN;
 *  - "soft-constraint" (seed 002 §3–4; soft_constraint.cc): node-path on the needle;
 *    past the swage the model takes the point over from the tie: it becomes a soft
 *    constraint of a suture that takes them (FTL), pulled by the thread's quasi-spring
 *    tensions and slipping by seed 002's eq. (3) with a Coulomb threshold;
 *  - "node-slip" (seed 001 §4; node_slip.cc): the point is joined to a node of the
 *    thread (the suture's nodes, continued onto the needle at the same spacing from the
 *    swage: seed 001's needle is the suture's first nodes), held there by the full tie
 *    whatever the force, and moved to the next node when its pull exceeds μN
 *    (coupling/node_slip.h).
 * The base class is node-path's behaviour; a model overrides what differs.
 */

#include <suturesim/core/model_parameters.h>
#include <suturesim/core/registry.h>
#include <suturesim/coupling/coulomb_friction.h>
#include <suturesim/realtime/suture_model.h>

#include <memory>
#include <string>
#include <vector>

namespace suturesim::realtime
{
  /// A pierce point as the model sees it after an accepted step.
  struct PierceSlip
  {
    double anchor   = 0;     ///< ζ_a, m (in: last step's; out: the accepted one)
    double zeta     = 0;     ///< ζ, where the tissue point projects on the thread, m
    double normal   = 0;     ///< N, N
    bool   slipping = false; ///< out
    double friction = 0;     ///< out: tangential force on the tissue point along the thread, towards its far end, N
  };

  /// The thread's node spacing: node i at ζ = swage + i·link (i < 0 on the needle).
  struct ThreadNodes
  {
    double swage = 0, link = 0;
    long   first = 0, last = 0; ///< node indices of the tip side and the far end
  };

  /// A point the model has taken over from the tie, after an accepted step.
  struct TakenSlip
  {
    double slip     = 0; ///< how far its anchor moves along the suture, m
    bool   slipping = false;
    double normal   = 0; ///< N
    double friction = 0; ///< tangential force on the tissue point, towards the far end, N
  };

  class PierceModel
  {
  public:
    using Registry = BasicRegistry<PierceModel, ParameterDeclarations, const ParameterValues &>;

    virtual ~PierceModel() = default;

    /// The model "automatic" stands for: soft-constraint for a suture that takes soft
    /// constraints (FTL) under a force-based integrator, node-path otherwise.
    static std::string
    automatic(const SutureModel *suture, bool position_based);

    /// Called when the needle joins a world with @p suture (nullptr: none) under a
    /// position-based integrator or not; std::invalid_argument when the model cannot
    /// work with them.
    virtual void
    attach(SutureModel *, bool)
    {}
    /// Least distance kept between points along the thread, given the scene's spacing, m.
    virtual double
    order_gap(const double spacing) const
    {
      return spacing;
    }
    /// The anchor of a new point that projects on the thread at @p zeta.
    virtual double
    first_anchor(const double zeta, const ThreadNodes &) const
    {
      return zeta;
    }
    /// Whether the stick along the thread is capped at μ N within a step (the return
    /// mapping, or the XPBD multiplier's clamp); false: the joint holds whatever the
    /// force, and only settle() lets it go.
    virtual bool
    capped_stick() const
    {
      return true;
    }
    /// The tangential force on the tissue point within a step (penalty form).
    virtual coupling::FrictionResult
    tangential(const coupling::FrictionParameters &friction, double zeta, double anchor, double normal) const;
    /// Moves the anchors of @p points (thread order) after an accepted step.
    virtual void
    settle(std::vector<PierceSlip> &points, const coupling::FrictionParameters &friction,
           const ThreadNodes &nodes) const;

    // --- points a model takes over from the tie (seed 002's soft constraints) --------------

    /// Whether the model takes over a point on the suture (@p on_suture) in segment
    /// @p segment (nodes segment, segment + 1): the coupling then leaves its force and
    /// slip to taken_forces() and taken_slip().
    virtual bool
    takes_over(bool /*on_suture*/, std::uint32_t /*segment*/) const
    {
      return false;
    }
    /// The forces on the tissue points of @p points (ascending s; material coordinate
    /// along the suture from the swage, tissue point positions) with the suture's nodes
    /// at @p x.
    virtual void
    taken_forces(const System &, const Matrix3Xd &, const std::vector<SoftConstraint> &,
                 std::vector<Vector3d> &) const
    {}
    /// Their slip and state after an accepted step at @p x.
    virtual void
    taken_slip(const System &, const Matrix3Xd &, const std::vector<SoftConstraint> &,
               const coupling::FrictionParameters &, std::vector<TakenSlip> &) const
    {}
    /// The accepted points (after their slip), for the suture's next update.
    virtual void
    taken_accepted(const std::vector<SoftConstraint> &)
    {}
  };
} // namespace suturesim::realtime
