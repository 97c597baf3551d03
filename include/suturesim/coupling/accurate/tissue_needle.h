#pragma once
/**
 * @file
 * The needle against the accurate (FE) tissue: the loads the tip's touch and the pierce
 * points put on embedded material points (tissue::PointLoads), with the same puncture
 * rule (coupling/needle_puncture.h) and friction law (coupling/coulomb_friction.h) as
 * the realtime path.
 *
 * Pierce point at material point X (reference coordinates in its cell, no remeshing),
 * current position x, anchor ζ_a on the needle (fixed within a load step; history
 * updated when a step is accepted). ζ is where x projects on the curve (closest point,
 * the convected coordinate of sliding contact: Wriggers 2006, "Computational Contact
 * Mechanics", §4.3), c = c(ζ), t the tangent there, d = x − c:
 *  - transverse: f⊥ = −P⊥ (λ + k⊥ d), P⊥ = I − t tᵀ. Penalty: λ = 0, the tie leaves
 *    a gap |P⊥ d| = |f⊥| / k⊥. Lagrange multipliers: λ is the constraint force, found by
 *    the augmented-Lagrangian (Uzawa) update λ ← P⊥ (λ + k⊥ d) between solves until
 *    the gap is below a tolerance (Simo & Laursen 1992, Comput. Struct. 42:97–116;
 *    Wriggers 2006, §6.3.3): the limit satisfies P⊥ d = 0 exactly whatever k⊥, which
 *    then only sets the rate (update_multipliers());
 *  - along the needle: the return mapping at ζ against ζ_a with N = N₀ + |f⊥|:
 *    f_t = k_t (ζ − ζ_a) t in stick (tangent −k_t t tᵀ), ±μN t in slip (tangent left
 *    out: its ∂N/∂x part would make the tangent non-symmetric; the residual stays exact).
 * Why the projection and not the anchor's point c(ζ_a): on the needle's circle (radius R)
 * a point that sticks Δ behind its anchor lies Δ²/(2R) off the anchor's tangent line, so
 * measuring across that line turns stick into normal force, N into a larger stick
 * capacity μN and Δ into more normal force: with k⊥ Δ/(2R) > k_t/μ the point locks on
 * the needle and is dragged through the tissue (measured at k⊥ = 5e4 N/m before this
 * change: N = 86 N, the point 4.5 mm off). On a thread element, a straight line, both
 * measures agree.
 * Touch: f = −F n_push with F = k_c max(0, penetration) (tangent −k_c n nᵀ while pressed).
 * The needle carries the opposite of all of these.
 *
 * The thread (set_thread(): the Cosserat suture's nodes and rotations, node 0 at the
 * swage) continues the needle's curve: ζ = L + s at the suture's reference arc length s.
 * The pierce point is measured against a C¹ centreline, not the elements' polyline: on
 * element e (nodes a, b, reference length l₀) the cubic Hermite curve c(u) through both
 * nodes with the rod's tangent directors d₁ = R e₁ there, so that its tangent is
 * continuous along the thread (coupling/accurate/thread_curve.h has the curve, its
 * source, and the chord a thread without rotations gets). The point's projection u on it
 * solves (x − c(u))·c′(u) = 0 (HermiteSegment::closest()); ζ = L + s_e + u l₀, the
 * tangent t = −c′/|c′| (the way the needle advances). Why: on the polyline a taut thread bent round its hole puts the
 * point at the bend's inside, where the distance to the polyline has a kink and the
 * carrier element flips between the two that meet there; each flip jumped the tie's
 * force and the stitch's tightening stalled at any step size (docs/interrupted_stitch.md).
 * Pierce points pass onto the thread at the swage and are released at its far end. A
 * point on the thread puts −f on the thread where the curve is, at c(u): its element's
 * nodes take the forces and moments conjugate to c(u) (HermiteSegment::reaction(), u
 * as projected; thread_terms(); the tissue side takes f at x). A point within the tenth
 * of an element past its carrier's end that the carrier's dead zone allows is measured
 * and loaded on the neighbour's curve, where the thread is (measured_on()). The loads' resultant
 * is f and their moment c(u) × f, and for the penalty tie they are the gradient of its
 * energy ½ k⊥ |P⊥ d|² with respect to the nodes (the closest point's own variation
 * drops out), so that the tie's part of the suture's tangent is symmetric.
 * Before 2026-12-05 the nodes took the chord's weights (1 − u) f and u f, u clamped to
 * [0, 1]: a kink in the residual at u = 0 and 1, and no moment for the curve's bulge.
 * A point sitting at a node then crossed the kink at every iterate (bite_spacing.prm at
 * b = s = 3 mm: u = 0.987 and 1.014 by turns, the residual cycling at 8 mN with
 * period 2 and, with the line search, 3), and 96 steps of that run failed; with the
 * curve's loads none (docs/tearing.md).
 * The element is the one that carries the point's projection (AccuratePiercePoint::
 * carrier), not the anchor's: a thread that slides by more than an element within a
 * step would otherwise hold the point on its anchor element's curve extended, and a solve
 * can then meet the tie with that curve turned through the point millimetres away from
 * the thread (seen at the stitch's tightening: the thread left its hole by 3 mm). The
 * carrier is fixed within a Newton step of the suture's solve and follows the thread
 * after each step (follow_thread(), through rod::NewtonParameters::follow;
 * coupling/accurate/condensed_suture.h also repeats the solve until the carriers stay),
 * as contact active sets do.
 */

#include <suturesim/coupling/accurate/thread_curve.h>
#include <suturesim/coupling/coulomb_friction.h>
#include <suturesim/coupling/needle_puncture.h>
#include <suturesim/rod/rod_model.h>
#include <suturesim/tissue/point_loads.h>
#include <suturesim/tools/curved_needle.h>

#include <algorithm>
#include <functional>
#include <optional>
#include <string>
#include <vector>

namespace suturesim::coupling
{
  struct TissueNeedleParameters
  {
    PunctureParameters puncture;
    FrictionParameters friction;
    double             transverse_stiffness = 500; ///< k⊥, N/m
    bool               lagrange             = false; ///< Uzawa multipliers on the tie
    double             spacing              = 1e-4; ///< m
    /// ε of the normal force's smoothing at a vanishing tie force (normal_force() in
    /// coupling/coulomb_friction.h), N; the scene sets the force the tie carries at the
    /// coupling tolerance, k⊥ × tolerance, which the coupled solve does not resolve anyway
    double             normal_smoothing     = 0;
    /// ρ of the tissue that carries a pierce point's force (tissue/point_loads.h), m;
    /// 0: a point load. The tip's touch has its own, puncture.touch_radius.
    double             load_radius          = 0;
  };

  struct AccuratePiercePoint
  {
    dealii::Point<3>     X;
    double               anchor = 0;
    /// On the thread: the thread coordinate whose element carries the point (its last
    /// projection), m. The tie and the friction are measured on that element's curve,
    /// which is fixed within a Newton step of the suture's solve and follows the point
    /// after it (TissueNeedle::follow_thread()).
    double               carrier = 0;
    bool                 exit   = false;
    dealii::Tensor<1, 3> multiplier; ///< λ, N (zero with penalty enforcement)
    // of the last accepted state, for the record
    double zeta = 0, normal = 0, friction = 0, slip_speed = 0;
    bool   slipping = false;
    /// Set while a tangent is differenced: the friction law stays on this branch
    /// (coulomb_friction()'s one-sided derivative at the stick–slip kink).
    std::optional<FrictionBranch> branch;
  };

  class TissueNeedle : public tissue::PointLoads
  {
  public:
    TissueNeedle(const tools::CurvedNeedle &needle, const TissueNeedleParameters &parameters,
                 const std::vector<mesh::Triangle> &triangles, const Eigen::Matrix3Xd &reference);

    /// The step to time @p t with the needle at @p pose: the tip's touch starts or ends
    /// against the surface at @p surface (the last accepted state). Returns true when the
    /// set of points changed (the tissue must locate them again).
    bool
    begin_step(double t, const tools::Pose &pose, const Eigen::Matrix3Xd &surface);

    /// The suture beyond the swage: its current node positions and rotations (kept by
    /// the caller and read at every evaluation; node 0 at the swage; @p rotations may be
    /// nullptr, the thread is then its polyline) and the reference length of each
    /// element (m). Without it points are released at the swage.
    void
    set_thread(const std::vector<rod::Vec3> *nodes, std::vector<double> element_lengths,
               const std::vector<rod::Quat> *rotations = nullptr);
    /// The thread is cut at its element @p element (rod::RodModel::cut): a pierce point
    /// following the thread stops at the cut instead of passing onto the other piece.
    void
    cut_thread(std::size_t element)
    {
      thread_cut.resize(std::max(thread_cut.size(), element + 1), 0);
      thread_cut[element] = 1;
    }

    /// Residual and Jacobian the pierce points on the thread add to suture element
    /// @p element (its two nodes) with the tissue points at @p x (one per points(), held
    /// fixed): the reaction of the point's force f (tie and friction) at the curve's
    /// point c(u) (HermiteSegment::reaction()). The Jacobian (positions and rotations of
    /// both nodes) is the central difference of that residual (steps 1e-8 m, 1e-7 rad):
    /// f goes through the projection on the Hermite curve, the return mapping and the
    /// smoothed normal force, whose exact chain would be long, and the tests check its
    /// convergence.
    /// @p jacobian may be nullptr (the residual alone: 1 evaluation a point, not 25).
    void
    thread_terms(const std::vector<dealii::Point<3>> &x, std::size_t element,
                 Eigen::Matrix<double, 12, 1> &residual, Eigen::Matrix<double, 12, 12> *jacobian) const;

    /// Moves each thread point's carrier element to the one its projection at tissue
    /// positions @p x (one per points()) falls on, walking along the thread from the
    /// current one (a point at a bend's inside, between two elements, stays). Returns
    /// true when a carrier changed element.
    bool
    follow_thread(const std::vector<dealii::Point<3>> &x);

    /// On the thread ∂f/∂x is a central difference of the whole law (pierce_force()):
    /// in slip it has the part μ t ⊗ ∂N/∂x, and with Lagrange multipliers the turn of
    /// P⊥ λ, neither of them symmetric. On the needle alone it is symmetric (the slip's
    /// ∂N/∂x is left out there).
    bool
    symmetric_tangent() const override
    {
      return !thread.attached() || (prm.friction.mu == 0 && !prm.lagrange);
    }
    /// The touch and the points on the needle are symmetric, those on the thread as
    /// symmetric_tangent() says.
    bool
    symmetric_at(std::size_t k) const override;

    /// Keeps each thread point's friction on the branch it takes at tissue positions
    /// @p x (one per points()) until release_friction_branches(): a body condensing its
    /// response by finite differences (CondensedSuture) then differences one branch of
    /// the law at the stick–slip kink, as thread_terms() does.
    void
    hold_friction_branches(const std::vector<dealii::Point<3>> &x);
    void
    release_friction_branches();

    /// Largest gap |P⊥ d| of the pierce points at tissue positions @p x (one per
    /// points()), m.
    double
    constraint_gap(const std::vector<dealii::Point<3>> &x) const;

    /// The Uzawa update of every pierce point's multiplier at @p x: λ ← P⊥ (λ + k⊥ d),
    /// the force the tie carries now. Returns the largest gap before the update, m.
    double
    update_multipliers(const std::vector<dealii::Point<3>> &x);

    /// Adds a pierce point at material point @p X anchored at thread coordinate
    /// @p anchor (m), as if punctured there: a start that is already pierced.
    void
    add_pierce_point(const dealii::Point<3> &X, double anchor);

    /// The suture elements that hold pierce points now (their carriers).
    std::vector<std::size_t>
    thread_elements() const;
    /// The elements a pierce point's force may load: each carrier and its neighbours
    /// (not across a cut), where a point in its carrier's dead zone is measured
    /// (measured_on()). thread_terms() adds to each only the points measured on it.
    std::vector<std::size_t>
    loaded_elements() const;

    /// Total length of needle and thread, m.
    double
    curve_length() const;

    /// Keeps the state before begin_step() / restores it (a step cut back).
    void
    save();
    void
    restore();

    // --- PointLoads ---------------------------------------------------------------------
    const std::vector<dealii::Point<3>> &
    points() const override
    {
      return X;
    }
    void
    force(std::size_t k, const dealii::Point<3> &x, dealii::Tensor<1, 3> &f,
          dealii::Tensor<2, 3> &df_dx) const override;
    double
    spread_radius(std::size_t k) const override
    {
      return is_touch(k) ? prm.puncture.touch_radius : prm.load_radius;
    }
    bool
    cut_off(std::size_t k, const dealii::Point<3> &Y) const override
    {
      return cut && cut(X[k], Y);
    }

    /// Whether the second reference point is out of the first's sight across a cut (the
    /// wound's faces: tearing::Wound::hides()): what a spread point takes of the tissue
    /// stops there (PointLoads::cut_off()). Empty (the default): no cut.
    using Cut = std::function<bool(const dealii::Point<3> &, const dealii::Point<3> &)>;
    void
    set_cut(Cut c)
    {
      cut = std::move(c);
    }

    /// Index of the touch among points() (−1 when not pressing) and of pierce point j.
    int
    touch_index() const
    {
      return puncture->pressing() ? 0 : -1;
    }
    /// The index among points() of pierce point 0: 1 while the tip presses (the touch
    /// is point 0), else 0.
    std::size_t
    first_pierce_index() const
    {
      return puncture->pressing() ? 1 : 0;
    }
    /// Whether point @p k of points() is the tip's touch.
    bool
    is_touch(std::size_t k) const
    {
      return puncture->pressing() && k == 0;
    }

    /// The touch force at the converged positions @p x (one per point), N.
    double
    touch_force(const std::vector<dealii::Point<3>> &x) const;

    /// Accepts the converged step at positions @p x: puncture, friction anchors, order,
    /// release at the swage (no suture in the accurate path yet). Returns true when the
    /// set of points changed.
    bool
    accept_step(const std::vector<dealii::Point<3>> &x);

    /// Force and moment (about the needle's pose position) the tissue exerts on the
    /// needle at positions @p x, plus @p swage_pull (force, N, and moment, N m, the
    /// suture puts on the swage), N and N m.
    std::pair<dealii::Tensor<1, 3>, dealii::Tensor<1, 3>>
    needle_load(const std::vector<dealii::Point<3>> &x, const rod::Vec6 &swage_pull = rod::Vec6::Zero()) const;

    const std::vector<AccuratePiercePoint> &
    pierce_points() const
    {
      return pierce;
    }
    /// Indices among points() of the pierce points on the thread (what couples the
    /// tissue to the suture), in thread order.
    std::vector<std::size_t>
    thread_points() const;
    /// A pierce point on the thread as thread_terms() sees it (diagnostics: why a suture
    /// solve stalls, scene/suture_newton_trace.h).
    struct ThreadPointState
    {
      std::size_t point   = 0; ///< index among points()
      std::size_t element = 0; ///< the element it is measured on (its carrier, or a neighbour)
      double      u       = 0; ///< the projection's Hermite parameter (beyond [0, 1]: past a node)
      double      slip    = 0; ///< ζ − ζ_a, m
      bool        slipping = false;
      double      normal = 0, friction = 0; ///< N and the friction along the thread, N
      double      across = 0;               ///< |x − c(u)| across the curve, m
    };
    /// Each pierce point on the thread with the tissue points at @p x (one per points())
    /// and the thread where it is.
    std::vector<ThreadPointState>
    thread_point_states(const std::vector<dealii::Point<3>> &x) const;
    /// Per suture node: whether it lies in a stitch's tract, between an exit pierce point
    /// and the next entry point along the thread (within one element either side),
    /// where the thread is meant to run inside the tissue.
    std::vector<char>
    thread_nodes_in_tracts() const;
    /// The state of the last accepted step (the touch, the pierce points with their
    /// anchors, multipliers and record, the events, the pose), for a checkpoint
    /// (io/checkpoint.h); restore() takes it back, the points rebuilt from it.
    nlohmann::json
    snapshot() const;
    void
    restore(const nlohmann::json &snapshot);

    /// Touches, punctures and releases so far, in time order.
    std::vector<PunctureEvent>
    all_events() const;
    const tools::Pose &
    pose() const
    {
      return current;
    }
    double
    last_touch_force() const
    {
      return touch_value;
    }

  private:
    /// Whether @p p sits on the thread (beyond the swage).
    bool
    on_thread(const AccuratePiercePoint &p) const
    {
      return thread.attached() && p.anchor > needle.length();
    }
    /// Point and advancing tangent of the curve (needle, then thread) at ζ.
    std::pair<dealii::Tensor<1, 3>, dealii::Tensor<1, 3>>
    curve(double zeta) const;
    /// The carrier of @p p after following the thread to @p x (see follow_thread()).
    double
    carried_to(const AccuratePiercePoint &p, const dealii::Point<3> &x) const;
    /// Where pierce point @p p at @p x projects on the curve, ζ (m): on the needle, the
    /// nearest point of its circle (straight on past the tip and the swage); on the
    /// thread, of its carrier element's curve (extended).
    double
    projection(const AccuratePiercePoint &p, const dealii::Point<3> &x) const;
    /// Point and tangent of the needle's circle at ζ, continued straight past its ends.
    std::pair<dealii::Tensor<1, 3>, dealii::Tensor<1, 3>>
    projected_curve(double zeta) const;
    /// Pierce point @p p at @p x against the curve: its projection ζ (m), the tangent
    /// there, the part of x − c(ζ) across it (m) and, on the thread, the projection's
    /// Hermite parameter u on the element it is measured on (measured_on()).
    struct Offset
    {
      double               zeta = 0;
      dealii::Tensor<1, 3> tangent, across;
      double               u = 0;
    };
    Offset
    across_curve(const AccuratePiercePoint &p, const dealii::Point<3> &x) const;
    /// The same on the thread's element @p e with its curve @p h (its nodes where they
    /// are, or moved for a finite difference), the projection's Newton iteration started
    /// at @p u0.
    Offset
    across_element(std::size_t e, const Eigen::Vector3d &x, const HermiteSegment &h, double u0) const;
    /// A thread point at @p x carried by element @p carrier (Hermite parameter @p u0
    /// there), measured where the thread is: across the carrier's curve, or, where its
    /// projection falls past the carrier's end (the carrier's dead zone, carried_to()),
    /// across the neighbour's curve if it falls on that. The carrier's curve continued
    /// past its node leaves the thread at second order (the two cubics share the node's
    /// position and tangent, not its curvature), so a point sliding along it saw the
    /// thread move across it and its normal force change with the slip: a friction that
    /// softened as it slid, whose stick and slip branches each led Newton to the other
    /// (docs/tearing.md, "A point past its carrier's end"). At the node both curves give
    /// the same foot (the same tangent), so the measure is continuous. @p element: the
    /// element measured on.
    Offset
    measured_on(std::size_t carrier, double u0, const Eigen::Vector3d &x, std::size_t &element) const;
    /// Whether thread element @p k is cut (cut_thread()).
    bool
    thread_cut_at(const std::size_t k) const
    {
      return k < thread_cut.size() && thread_cut[k] != 0;
    }
    /// The friction branch of @p p at offset @p o: its held one, else the return
    /// mapping's choice there.
    FrictionBranch
    branch_at(const AccuratePiercePoint &p, const Offset &o) const;
    /// Rebuilds X (touch first, then the pierce points).
    void
    rebuild_points();
    /// Pierce point @p p's force at offset @p o, with its friction result and normal force.
    dealii::Tensor<1, 3>
    pierce_force(const AccuratePiercePoint &p, const Offset &o, FrictionResult *r, double *N) const;
    /// Its force at x, with the tangent ∂f/∂x when @p df_dx is given: on the needle
    /// without the curvature's part (|d⊥|/R against 1); on the thread the central
    /// difference (the Hermite curve bends at every node).
    dealii::Tensor<1, 3>
    pierce_force(const AccuratePiercePoint &p, const dealii::Point<3> &x, FrictionResult *r,
                 double *N, dealii::Tensor<2, 3> *df_dx) const;

    tools::CurvedNeedle                needle;
    TissueNeedleParameters             prm;
    const std::vector<mesh::Triangle> &triangles;
    Eigen::Matrix3Xd                   reference;
    std::optional<NeedlePuncture>      puncture, saved_puncture;
    std::vector<AccuratePiercePoint>   pierce, saved_pierce;
    std::vector<PunctureEvent>         log;
    std::size_t                        saved_log = 0;
    std::vector<dealii::Point<3>>      X;
    ThreadCurve                        thread; ///< the suture beyond the swage
    std::vector<char>                  thread_cut; ///< per thread element, 1 where cut (cut_thread())
    tools::Pose                        current, saved_pose;
    double                             time = 0, last_time = 0, saved_time = 0, saved_last_time = 0;
    double                             touch_value = 0;
    Cut                                cut;
  };
} // namespace suturesim::coupling
