#pragma once
/**
 * @file
 * How a realtime pierce point holds on to the thread and slips along it, registered by
 * name (`Realtime/Pierce model`). The needle coupling (realtime/needle_coupling.h) owns
 * the points, their tie across the thread and their order; the model decides the rest:
 *  - "node-path" (seed 004): the point's anchor is any thread coordinate ζ_a; the tie
 *    along the thread is an elastic stick with Coulomb's limit by return mapping
 *    (coupling/coulomb_friction.h), so the anchor slides continuously at |f| = μ N;
 *  - "soft-constraint" (seed 002 §3–4): as node-path on the needle (the return mapping is
 *    seed 002 eq. 2 with a = 1/k_t and a Coulomb threshold); past the swage the point is
 *    a soft constraint of a suture that takes them (FTL), pulled by the thread's
 *    quasi-spring tensions, slipping by eq. (3) (see needle_coupling.h);
 *  - "node-slip" (seed 001 §4): the point is joined to a node of the thread (the
 *    suture's nodes, continued onto the needle at the same spacing from the swage: seed
 *    001's needle is the suture's first nodes), held there by the full tie whatever the
 *    force, and moved to the next node when its pull exceeds μ N (coupling/node_slip.h).
 */

#include <suturesim/coupling/coulomb_friction.h>
#include <suturesim/core/registry.h>
#include <suturesim/core/model_parameters.h>

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
    double friction = 0;     ///< out: tangential force on the tissue point along the tangent, N
  };

  /// The thread's node spacing: node i at ζ = swage + i·link (i < 0 on the needle).
  struct ThreadNodes
  {
    double swage = 0, link = 0;
    long   first = 0, last = 0; ///< node indices of the tip side and the far end
  };

  class PierceModel
  {
  public:
    using Registry = BasicRegistry<PierceModel, ParameterDeclarations, const ParameterValues &>;

    virtual ~PierceModel() = default;

    /// Points past the swage become the suture model's soft constraints (seed 002).
    virtual bool
    soft_on_suture() const
    {
      return false;
    }
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
    tangential(const coupling::FrictionParameters &friction, double zeta, double anchor,
               double normal) const;
    /// Moves the anchors of @p points (thread order) after an accepted step.
    virtual void
    settle(std::vector<PierceSlip> &points, const coupling::FrictionParameters &friction,
           const ThreadNodes &nodes) const;
  };
} // namespace suturesim::realtime
