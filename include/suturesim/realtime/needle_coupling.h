#pragma once
/**
 * @file
 * A rigid curved needle in the realtime world, with the suture attached at its swage:
 * puncture of the tissue surface by the tip (coupling/needle_puncture.h) and the pierce
 * points it leaves, which slide along the thread — the needle's arc, then the suture's
 * polyline — held by friction.
 *
 * Pierce point (seed 004's node–path constraint): a tissue material point
 * p = Σ wᵢ xᵢ (the surface triangle it was born on) tied to the thread at its anchor
 * coordinate ζ_a (tools/curved_needle.h: 0 at the tip, L at the swage, L + material arc
 * length along the suture beyond it). The anchor is a material point of the thread and
 * moves only by slip, so a pierce point never jumps between strands of a folded
 * suture. With c = c(ζ_a), t the tangent there (towards the tip), d = p − c and the
 * point's own coordinate ζ = ζ_a − d·t:
 *  - transverse: C⊥ = |P⊥ (p − c)|, P⊥ = I − t tᵀ, compliance 1/k⊥ (seed 004:
 *    (p − q) × t = 0);
 *  - along the thread: stick to the anchor ζ_a, C_t = ζ − ζ_a, compliance 1/k_t, with
 *    the Coulomb limit |f_t| ≤ μ N, N = N₀ + |f⊥| (coupling/coulomb_friction.h; seed 000
 *    eq. 2). Under XPBD the stick multiplier is clamped to the limit (static friction as
 *    a position constraint, Müller et al. 2020, "Detailed rigid body simulation with
 *    extended position based dynamics", §3.5); the force-based integrators use the
 *    return mapping's penalty forces.
 * On the suture part the constraint moves the two suture nodes of c's segment too
 * (weights 1 − s, s). Pierce points keep their order along the thread and stay on it
 * (coupling/pierce_order.h): the anchors are projected after every step.
 * Spread (load radius ρ > 0, as in the accurate path: tissue/point_loads.h): the point
 * stands for the tissue within ρ of its reference position X, p = X + Σ_I W_I (x_I − X_I)
 * over the tissue nodes with W_I = φ(|X_I − X|/ρ) m_I / Σ_J φ(|X_J − X|/ρ) m_J, φ the
 * kernel of mesh/spread_kernel.h and m_I the lumped masses (the nodal quadrature of the
 * accurate path's ∫ φ N_I dV / ∫ φ dV). Its force is spread with the same weights, so
 * the tie does the work of one point; a point load's displacement grows like F/(μ h)
 * under refinement (Kelvin's solution), a spread one's has a mesh limit.
 * The needle is kinematic: what the tissue exerts on it (the reaction of the touch and
 * of the pierce points on its arc) is reported as its tool force with the suture's
 * pull at the swage.
 *
 * The pierce model (realtime/pierce_model.h, Realtime/Pierce model) decides how the
 * points slip along the thread, and may take points over from the tie altogether
 * (seed 002's soft constraints past the swage: their forces and slip are then the
 * model's).
 */

#include <suturesim/coupling/coulomb_friction.h>
#include <suturesim/coupling/needle_puncture.h>
#include <suturesim/realtime/free_needle.h>
#include <suturesim/realtime/pierce_model.h>
#include <suturesim/realtime/suture_model.h>
#include <suturesim/realtime/system.h>
#include <suturesim/tools/curved_needle.h>

#include <functional>
#include <vector>

namespace suturesim::realtime
{
  struct NeedleCouplingParameters
  {
    coupling::PunctureParameters puncture;
    coupling::FrictionParameters friction;
    double transverse_stiffness = 100;  ///< k⊥, N/m
    /// ρ of the spread kernel (0: the point of the surface triangle it was born on), m
    double load_radius = 0;
    /// Whether the tissue at the second reference point is out of the first's sight
    /// across the wound (tearing::Wound::hides); empty: no wound. A spread point's share
    /// of weight on such nodes is recorded (PiercePointState::across_wound), and with
    /// load_across_wound false they are left out of its spread.
    std::function<bool(const Vector3d &, const Vector3d &)> hidden;
    bool load_across_wound = true; ///< Pierce points/Load across the wound
    double spacing              = 1e-4; ///< least distance between pierce points along the thread, m
    /// XPBD: the suture nodes' inverse masses within a pierce constraint are capped at
    /// this multiple of the tissue point's (mass scaling against jitter), 1
    double mass_ratio = 10;
    bool   project              = false; ///< XPBD constraints instead of penalty forces
    /// The suture is moved geometrically (follow-the-leader): inextensible and held by
    /// the needle, it passes what the tissue exerts on it at its pierce points straight
    /// to the needle (otherwise its springs carry it to the nodes the needle holds).
    bool   geometric_suture     = false;
    /// How the points hold on to the thread and slip (realtime/pierce_model.h), by its
    /// registered name
    std::string pierce_model = "node-path";
  };

  /// One pierce point as recorded per step.
  struct PiercePointState
  {
    double   zeta       = 0;     ///< thread coordinate now, m
    double   anchor     = 0;     ///< ζ_a, m
    bool     slipping   = false;
    bool     on_suture  = false;
    bool     exit       = false; ///< born where the tip came out
    double   slip_speed = 0;     ///< dζ_a/dt of the last step, m/s
    double   normal     = 0;     ///< N, N
    double   friction   = 0;     ///< tangential force on the tissue point along −t, N
    Vector3d position   = Vector3d::Zero(); ///< of the tissue point, m
    Vector3d reference  = Vector3d::Zero(); ///< of the tissue point at rest (X), m
    /// the surface's outward normal where the point was born (at the touch)
    Vector3d surface_normal = Vector3d::Zero();
    /// share of the point's weights on tissue beyond the wound's faces (the parameters'
    /// `hidden`) as carried, 1: 0 without a wound or a load radius, or when the load
    /// stops at the wound
    double across_wound = 0;
  };

  class NeedleCoupling : public ContactSet
  {
  public:
    /// @p surface: the tissue's surface triangles (system node indices); the suture is
    /// the system's suture range, its first node at the swage, moved by
    /// @p suture_model (nullptr: no suture). std::invalid_argument for a load radius not
    /// above the surface's longest edge, an unknown pierce model or one that cannot work
    /// with the suture and integrator.
    NeedleCoupling(const System &system, const std::vector<mesh::Triangle> &surface,
                   const tools::CurvedNeedle &needle, const NeedleCouplingParameters &parameters,
                   SutureModel *suture_model);

    std::string
    name() const override
    {
      return "needle and pierce points";
    }

    /// Makes a surface point a vertex of its own (triangle, barycentric weights) and
    /// returns its node, or −1 (TissueModel::subdivide(), with whatever else must follow
    /// the surface's new triangles).
    using Subdivide = std::function<std::int64_t(std::uint32_t triangle, const Vector3d &weights)>;
    /// Seed 002 §4.A: a touch makes its point a vertex of its own through @p subdivide
    /// after the step it began in, so that the needle presses, and the pierce point
    /// holds, that vertex (event "subdivision").
    void
    subdivide_at_touch(Subdivide subdivide)
    {
      subdivision = std::move(subdivide);
    }

    /// The needle's pose and the time at the end of the coming (sub)step.
    void
    set_pose(const tools::Pose &pose, double time);

    void
    detect(const Matrix3Xd &x) override;
    void
    add_forces(const Matrix3Xd &x, Matrix3Xd &f) const override;
    /// The penalty forms' energy: the touch ½ k_c max(0, (x_m − x_tip)·n)², each tie
    /// ½ k⊥ |P⊥ (p − c)|² (c on the suture moves with its segment's nodes, the tangent
    /// and the closest point's place held as located) and, while it sticks,
    /// ½ k_t (ζ − ζ_a)². std::nullopt when a point slips at μN > 0 or is a soft
    /// constraint (seed 002): their forces have no potential.
    std::optional<double>
    energy(const Matrix3Xd &x) const override;
    bool
    has_projection() const override
    {
      return prm.project;
    }
    void
    add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, double dt) const override;
    void
    reset_multipliers() override;
    void
    project(Matrix3Xd &x, const VectorXd &w, double dt) override;
    void
    after_step(Nodes &nodes) override;
    std::size_t
    active() const override
    {
      return points.size() + (puncture.pressing() ? 1 : 0);
    }

    /// Force and moment (about @p origin) the tissue exerts on the needle at the state of
    /// the last detect(), N and N m (penalty forces, or the multipliers of the last solve
    /// under XPBD with @p dt).
    /// The needle held by a tool feels the whole force of the points on a geometric
    /// suture (FTL passes it straight on); a @p free needle only its part along the
    /// thread, as the tension it adds at the swage: a thread without bending stiffness
    /// carries no transverse force to a body free to move.
    std::pair<Vector3d, Vector3d>
    needle_load(const Matrix3Xd &x, const Vector3d &origin, double dt, bool free = false) const;

    /// Adds the Gauss–Newton stiffness of that load with respect to the needle's rigid
    /// motion about @p centre to @p K (free_needle.h, add_point_stiffness): a point
    /// spring where each acts, k_c for the touch and k⊥ + k_t for a tie (at least
    /// k⊥ P⊥ + k_t t tᵀ); a point on a geometric suture pulls through the thread, k_t
    /// at the swage (needle_load's free needle). A free needle's step.
    void
    add_stiffness(Matrix6d &K, const Vector3d &centre) const;

    const coupling::NeedlePuncture &
    puncture_state() const
    {
      return puncture;
    }
    /// The other point leads from the next pose on (World::reverse_needle).
    void
    forget_tip_path()
    {
      puncture.forget_path();
    }
    /// The normal force of the touch at the last accepted step, N.
    double
    touch_force() const
    {
      return last_touch_force;
    }
    const std::vector<PiercePointState> &
    pierce_points() const
    {
      return states;
    }
    /// Pierce-point events: "on_suture" (passed the swage), "released" (the thread left
    /// the hole), with the tissue point's position and the normal force.
    const std::vector<coupling::PunctureEvent> &
    thread_events() const
    {
      return events_on_thread;
    }
    /// What the tie of pierce point @p k exerts on its tissue point at the accepted state
    /// (the system's positions), N: found when asked, not every step (a tear's check).
    Vector3d
    tissue_force(std::size_t k) const;

    /// A tear (tearing/ligament_tear.h) between steps: pierce point @p k lets go of the
    /// thread (event "torn_free").
    void
    tear_free(std::size_t k);
    /// A tear that joined two holes: pierce point @p k holds the tissue point of point
    /// @p onto from now on (event "torn_into_hole").
    void
    move_into(std::size_t k, std::size_t onto);

    /// Suture nodes (local index) between two pierce points, inside the tissue: the
    /// suture–surface contact leaves them alone.
    const std::vector<char> &
    suture_inside() const
    {
      return inside;
    }
    const tools::CurvedNeedle &
    geometry() const
    {
      return needle;
    }
    const std::string &
    pierce_model() const
    {
      return prm.pierce_model;
    }
    const tools::Pose &
    pose() const
    {
      return current_pose;
    }

  private:
    /// Where a tissue point sits on the thread.
    struct ThreadPoint
    {
      double        zeta = 0;
      Vector3d      c = Vector3d::Zero(), t = Vector3d::UnitX();
      bool          on_suture = false;
      std::uint32_t k         = 0;   ///< suture segment (nodes k, k + 1) on the suture
      double        s         = 0;   ///< position in it
    };
    struct PiercePoint
    {
      /// p = offset + Σ_j weights[j] x(nodes[j]): a triangle's barycentric weights
      /// (offset 0), or the spread weights with offset X − Σ_j weights[j] X(nodes[j])
      std::vector<std::uint32_t> nodes;
      std::vector<double>        weights;
      Vector3d                   offset = Vector3d::Zero();
      double         anchor = 0;
      ThreadPoint    at;
      double         lambda_n = 0, lambda_t = 0; ///< XPBD multipliers of the step
      Vector3d       normal_direction = Vector3d::Zero();
      bool           exit = false; ///< born where the tip came out of the tissue
      Vector3d       surface_normal = Vector3d::Zero(); ///< outward, at the touch
      double         across_wound   = 0;                  ///< PiercePointState's
      bool           passed_swage = false;
    };

    Vector3d
    tissue_point(const PiercePoint &p, const Matrix3Xd &x) const;
    /// The tissue nodes that carry a point born at surface point @p at: its triangle's,
    /// or, with a load radius, the spread weights about its reference position (without
    /// the nodes beyond the wound, unless the load goes across it).
    void
    carry(PiercePoint &p, const coupling::SurfacePoint &at) const;
    /// After a step: the touch's force decides the puncture (a new pierce point), and
    /// seed 002's subdivision makes a new touch's point a vertex.
    void
    accept_touch(const Matrix3Xd &x);
    /// After a step of length @p step: the anchors of the accepted state (the model's
    /// slip), the points' states, the points the thread has left released; returns the
    /// thread's end coordinate.
    double
    settle_anchors(const Matrix3Xd &x, double step);
    /// The recorded states and the suture nodes inside the tissue, at @p x.
    void
    record_states(const Matrix3Xd &x);
    /// Whether the pierce model has taken @p p over from the tie.
    bool
    taken(const PiercePoint &p) const
    {
      return model->takes_over(p.at.on_suture, p.at.k);
    }
    /// The points the model has taken over at @p x into taken_work (material coordinate
    /// along the suture, tissue point); taken_index maps each pierce point to its entry
    /// there (−1: none).
    void
    gather_taken(const Matrix3Xd &x) const;
    /// The thread's point and tangent at coordinate @p zeta (the needle's arc up to L,
    /// the suture's polyline at material coordinate ζ − L beyond).
    ThreadPoint
    thread_at(double zeta, const Matrix3Xd &x) const;
    /// Penalty forces of pierce point @p p on its tissue point (total) and the friction
    /// return mapping.
    Vector3d
    pierce_force(const PiercePoint &p, const Matrix3Xd &x, coupling::FrictionResult *friction,
                 double *normal) const;
    /// Seed 002's subdivision at surface point @p point, which then names the new vertex
    /// (weights (1, 0, 0)); false when there is none to make (no subdivision, a vertex
    /// already, no spare node left).
    bool
    make_vertex(coupling::SurfacePoint &point, const Matrix3Xd &x);
    /// Adds @p force on the tissue point of @p p to @p f, and its reaction on the suture
    /// nodes when on the suture.
    void
    distribute(const PiercePoint &p, const Vector3d &force, Matrix3Xd &f) const;
    /// XPBD correction of constraint gradient direction @p n (unit, on the tissue point)
    /// with violation @p C, compliance @p alpha_tilde and multiplier @p lambda; the
    /// multiplier's increment is limited to keep λ within ±@p limit (∞: none).
    double
    correct(PiercePoint &p, const Vector3d &n, double C, double alpha_tilde, double &lambda,
            double limit, Matrix3Xd &x, const VectorXd &w) const;

    NeedleCouplingParameters           prm;
    std::unique_ptr<PierceModel>       model;
    ThreadNodes                        thread_nodes;
    std::vector<PierceSlip>            slip_work;
    const std::vector<mesh::Triangle> &triangles;
    NodeRange                          suture;
    double                             link = 0; ///< rest length of a suture segment, m
    tools::CurvedNeedle                needle;
    tools::Pose                        current_pose;
    double                             time = 0, last_time = 0, last_dt = 0;
    coupling::NeedlePuncture           puncture;
    double                             last_touch_force = 0;
    double                             touch_lambda     = 0;
    std::vector<PiercePoint>           points; ///< in thread order: ζ ascending
    std::vector<PiercePointState>      states;
    std::vector<char>                  inside;
    std::vector<double>                zeta_work;
    std::vector<coupling::PunctureEvent> events_on_thread;
    Subdivide                            subdivision;
    const System                        &sys;
    mutable std::vector<SoftConstraint>  taken_work;
    mutable std::vector<Vector3d>        taken_force;
    mutable std::vector<std::int64_t>    taken_index;
    std::vector<TakenSlip>               taken_slips;
  };
} // namespace suturesim::realtime
