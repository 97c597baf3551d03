#pragma once
/**
 * @file
 * A realtime scene: tissue and suture models in one System, an integrator, suture–tissue
 * contact and suture self-collision, held boundaries and tools, advanced one haptic step
 * at a time: step(tool poses) → tool forces. A haptic step of h = 1/rate is split into
 * substeps dt = h/n; tool poses are interpolated across them (positions linearly,
 * orientations by slerp). Each step ends with the divergence guard; a diverged step
 * throws DivergenceError and leaves the world at its last good state.
 *
 * Order within a substep (after seed 002 §6.A, "the needle/suture interactions need to
 * occur in a particular order for stability"): held targets; the suture model's own
 * update (FTL); the integrator's step (forces or constraints, contacts detected inside);
 * release of last substep's collision constraints; post-step responses (seed 002's
 * collision constraints, FTL nodes pushed out of the tissue).
 */

#include <suturesim/realtime/divergence_guard.h>
#include <suturesim/realtime/free_needle.h>
#include <suturesim/realtime/integrator.h>
#include <suturesim/realtime/needle_coupling.h>
#include <suturesim/realtime/node_access.h>
#include <suturesim/realtime/self_collision.h>
#include <suturesim/realtime/suture_model.h>
#include <suturesim/realtime/surface_contact.h>
#include <suturesim/realtime/wound_face_contact.h>
#include <suturesim/realtime/tissue_model.h>
#include <suturesim/tools/trajectory.h>

#include <Eigen/Geometry>

#include <chrono>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace suturesim::realtime
{
  /// Where a tool is: position and orientation (tools/trajectory.h).
  using ToolPose = tools::Pose;

  /// What the simulated bodies exert on a tool: the force and moment (about the tool's
  /// position) to render on a haptic device.
  struct ToolForce
  {
    Vector3d force  = Vector3d::Zero(); ///< N
    Vector3d torque = Vector3d::Zero(); ///< N m
  };

  struct WorldSetup
  {
    const mesh::SimplexMesh     *mesh = nullptr; ///< the tissue's mesh; nullptr: no tissue
    TissueMaterial               material;
    std::unique_ptr<TissueModel> tissue;

    std::unique_ptr<SutureModel> suture; ///< nullptr: no suture
    SutureGeometry               suture_geometry;
    std::string                  self_collision = "off";
    ParameterValues              self_collision_parameters;
    bool                         contact = true;
    double                       contact_stiffness = 0; ///< N/m
    double                       contact_depth     = 0; ///< m
    /// the ftl thread's pull into the surface at its resting nodes loads the tissue
    /// (SurfaceContact::carry_thread); a geometric suture and a force-based integrator
    bool                         contact_load      = false;

    std::unique_ptr<Integrator> integrator;
    Vector3d                    gravity  = Vector3d::Zero();
    double                      rate     = 1000; ///< haptic steps per second, Hz
    unsigned                    substeps = 1;
    bool                        refuse_above_limit = false; ///< else warn
  };

  class World
  {
  public:
    explicit World(WorldSetup setup);
    // the needle's subdivision hook holds this world's address
    World(const World &) = delete;
    World &
    operator=(const World &) = delete;

    // --- what is held, set before initialize() -----------------------------------------

    /// Holds the tissue nodes of mesh vertices @p vertices at their rest positions.
    void
    fix_vertices(const std::vector<std::uint32_t> &vertices);

    /// target = motion(t) of the nodes (system indices) it is given, from their rest
    /// positions.
    using Motion = std::function<void(double t, const std::vector<std::uint32_t> &nodes,
                                      const Matrix3Xd &reference, Matrix3Xd &target)>;
    /// Holds the tissue nodes of mesh vertices @p vertices on @p motion; returns their
    /// system nodes.
    std::vector<std::uint32_t>
    prescribe_vertices(const std::vector<std::uint32_t> &vertices, Motion motion);

    /// A tool holding system nodes @p nodes rigidly at its pose (their offsets in the
    /// tool's frame are those of @p initial). Returns the tool's index.
    std::size_t
    add_tool(const std::string &name, const std::vector<std::uint32_t> &nodes,
             const ToolPose &initial);

    /// Tool @p tool closes on system nodes @p nodes during the run (a grasper taking the
    /// suture's end): from the next step they are held at their present offsets from
    /// the tool's present pose @p pose.
    void
    grasp(std::size_t tool, const std::vector<std::uint32_t> &nodes, const ToolPose &pose);

    /// A rigid curved needle moved as tool (the returned index) with pose @p initial at
    /// t = 0: its tip punctures the tissue surface and its pierce points slide along
    /// it and on along the suture (needle_coupling.h). With @p hold_suture the needle
    /// holds the suture's first two nodes (a hard constraint in position and tangent at
    /// the swage, seed 002); they must lie at the swage and on the line leaving it. A
    /// double-pointed needle holds the first node only: the Endo Stitch's suture is
    /// fixed in a hole at the needle's middle, free to swing whichever point leads.
    std::size_t
    /// parameters.pierce_model "automatic": seed 002's soft constraints when the suture
    /// takes them under a force-based integrator, else seed 004's node-path.
    add_needle(const tools::CurvedNeedle &needle, const NeedleCouplingParameters &parameters,
               const ToolPose &initial, bool hold_suture);

    const NeedleCoupling *
    needle() const
    {
      return needle_coupling;
    }
    /// The needle's coupling, to release or move its pierce points (a tear).
    NeedleCoupling *
    needle()
    {
      return needle_coupling;
    }

    /// Seed 001 §5–6: the needle driver lets go. From the next step the needle is a free
    /// rigid body of wire density @p density (kg/m³) and drag @p drag (N s/m),
    /// moved by what the bodies exert on it and by gravity (free_needle.h); its tool goes
    /// on moving and feels nothing. std::invalid_argument without a needle, when it is
    /// free already, or under an integrator that carries momentum (the law is the
    /// quasi-static one).
    void
    release_needle(double density, double drag);
    /// The jaws close on the needle again: from the next step it is held at its present
    /// pose relative to the tool's pose @p tool_pose. std::invalid_argument unless free.
    void
    grasp_needle(const ToolPose &tool_pose);
    /// A handover: another grasper, at pose @p holder, takes the needle a tool holds
    /// (the first lets go at once, so the needle is never free). From the next step the
    /// needle keeps its present pose relative to @p holder, and the poses step() gets
    /// for the needle's tool are the new holder's. std::invalid_argument when free.
    void
    hand_needle_over(const ToolPose &holder);
    /// Cuts the suture for good between its local nodes @p segment and @p segment + 1
    /// (SutureModel::cut), between steps: a thread cut after a knot.
    /// std::invalid_argument without a suture or past its last link.
    void
    cut_suture(std::uint32_t segment);
    /// The Endo Stitch passes its double-pointed needle to the other jaw (seed 001 §5):
    /// from the next step the other point leads. The needle turns half a turn about the
    /// z axis of its frame, about its middle where the suture is pinned
    /// (tools::CurvedNeedle::double_pointed, add_needle). The tip's last position is
    /// forgotten: it moved without sweeping the space between.
    /// std::invalid_argument when the needle is not double-pointed or is free, when either
    /// point touches or is in the tissue, or a hole is still on the needle (not yet on the
    /// suture).
    void
    reverse_needle();
    /// The free needle, nullptr while a tool holds it.
    const FreeNeedle *
    free_needle() const
    {
      return free_body ? &*free_body : nullptr;
    }

    /// A tear (tearing/ligament_tear.h): removes the tissue's springs whose rest segment
    /// (X_i, X_j) @p crosses the tear's surface, between steps. Returns how many went.
    /// The tear's faces do not join the tissue's surface: the suture's contact and the
    /// needle's punctures do not see them.
    std::size_t
    cut_tissue(const std::function<bool(const Vector3d &, const Vector3d &)> &crosses);
    /// The name of the first of the tissue's families a cut cannot part (its elements
    /// couple more than the two ends of an edge: volume constraints, finite elements);
    /// empty when springs (and one-node home springs and angle springs at chosen points)
    /// are all it has.
    std::string
    uncuttable_tissue() const;

    /// Seed 004's node-access constraints (node_access.h): the suture passes through the
    /// fixed points @p points (m), each starting on the suture link nearest it. While an
    /// access is on a link the constraint stands in for that link's spring (left out of
    /// the suture, SutureModel::leave_out_link), and the pair moves on as the thread
    /// slides. @p stiffness N/m (0: that of the suture's links; ∞, rigid, only under a
    /// position-based integrator).
    /// Call once, before initialize(). std::invalid_argument without a suture whose
    /// links are springs.
    void
    add_access(const std::vector<Vector3d> &points, double stiffness);

    /// A blunt probe (seed 004's external stage: a tool that may not penetrate the
    /// tissue): the last @p length (m) of a rod of radius @p radius (m) from its tip
    /// @p tip (m) along @p axis (towards the handle), as a chain of nodes at most a
    /// radius apart held by a tool (the returned index; pose: position at the tip,
    /// orientation identity at t = 0). Each node keeps a radius from the tissue surface:
    /// the node–triangle constraint of surface_contact.h, penalty @p stiffness (N/m) or
    /// its XPBD compliance. Before initialize(); std::invalid_argument without tissue or
    /// with a size or stiffness that is not positive.
    std::size_t
    add_probe(const std::string &name, const Vector3d &tip, const Vector3d &axis, double length, double radius,
              double stiffness);

    /// The probes' contacts with the tissue, in the order added.
    const std::vector<SurfaceContact *> &
    probe_contact() const
    {
      return probe_contacts;
    }

    /// The incision's faces kept apart (wound_face_contact.h): the nodes @p face_a
    /// (system indices) against the triangles @p face_b (outward from their lip), penalty
    /// @p stiffness (N/m) or its XPBD compliance, pairs listed within @p margin (m).
    /// Before initialize(); std::invalid_argument without tissue, with an empty face or a
    /// stiffness that is not positive.
    void
    add_wound_face_contact(const std::vector<std::uint32_t> &face_a, const std::vector<mesh::Triangle> &face_b,
                           double stiffness, double margin);
    const NodeAccess *
    access() const
    {
      return access_set;
    }

    /// External loads (tractions) at time t into the given 3 × n array (zeroed before).
    using Loads = std::function<void(double t, Matrix3Xd &external)>;
    void
    set_loads(Loads loads);

    /// Sets up the integrator, the stability limit and the guard; call once, after the
    /// holds. Throws ParameterError("Substeps", …) when dt exceeds the limit and the
    /// setup refuses that.
    void
    initialize();

    // --- stepping ------------------------------------------------------------------------

    /// Advances one haptic step with the tools moving to @p poses (one per tool);
    /// returns what the bodies exert on each tool. Does not allocate.
    const std::vector<ToolForce> &
    step(const std::vector<ToolPose> &poses);

    // --- state and measurements -----------------------------------------------------------

    const System &
    system() const
    {
      return sys;
    }
    System &
    system()
    {
      return sys;
    }
    const TissueModel *
    tissue() const
    {
      return tissue_model.get();
    }
    const SutureModel *
    suture() const
    {
      return suture_model.get();
    }
    const Integrator &
    integrator() const
    {
      return *time_integrator;
    }
    const SurfaceContact *
    surface_contact() const
    {
      return contact;
    }
    /// The suture's self-collision response with its counts; nullptr when "off".
    const SelfCollision *
    self_collision() const
    {
      return self_collision_set;
    }
    double
    time() const
    {
      return t;
    }
    std::size_t
    steps() const
    {
      return n_steps;
    }
    /// The substep dt (s).
    double
    dt() const
    {
      return h / n_substeps;
    }
    /// The stability limit of the integrator (s), ∞ when none: at set-up, and again after
    /// every change of the tissue's topology.
    double
    stability_limit() const
    {
      return dt_limit;
    }
    const std::string &
    stability_description() const
    {
      return limit_text;
    }
    /// Non-empty when dt exceeded the stability limit at set-up or at a later assessment.
    const std::string &
    warning() const
    {
      return warning_text;
    }
    const std::vector<ToolForce> &
    tool_forces() const
    {
      return forces;
    }

    /// Where the last step's time went, besides the solve: contact detection and the
    /// post-step collision responses (collision), and the tools, prescribed motions,
    /// loads, SutureModel::before_step and the forces on the tools (coupling). The solve is the step's time less
    /// these (HapticLoop).
    struct StepPhases
    {
      std::chrono::steady_clock::duration collision{0}, coupling{0};
    };
    const StepPhases &
    phases() const
    {
      return step_phases;
    }

    /// The nodes of a boundary and, per interaction, the elements that touch them
    /// (Interaction::elements_touching): the reaction sums the forces of those alone.
    class ReactionSet
    {
      friend class World;
      std::vector<std::uint32_t>              nodes;
      std::vector<char>                       touched;   ///< per system node
      std::vector<std::vector<std::uint32_t>> elements;  ///< per interaction
      std::vector<char>                       listed;    ///< per interaction: elements holds its list
      std::vector<std::size_t>                revisions; ///< per interaction, of the list
      Matrix3Xd                               force;     ///< scratch, 3 x nodes
    };

    /// The reaction set of @p nodes (system indices), built once: renewing its lists
    /// allocates, and happens again only after a change of topology.
    ReactionSet
    reaction_set(const std::vector<std::uint32_t> &nodes) const;

    /// The force the holders of the set's nodes exert on the bodies (N): the reaction of
    /// a fixed or prescribed boundary, in the accurate path's sign. Bit for bit the sum
    /// over all interactions (each node's additions in the same order), at the cost of
    /// the elements touching the boundary; contacts are evaluated whole.
    Vector3d
    reaction(ReactionSet &set) const;

    /// Interpolation of the tissue displacement at rest point @p X (m): the containing
    /// tetrahedron of the volume model, the nearest surface triangle of the surface
    /// model. Returns the probe's index. Throws ParameterError("Probes", …) when X is
    /// farther than 1e-6 of the scene size from the tissue.
    std::size_t
    add_probe(const Vector3d &X);
    Vector3d
    probe_displacement(std::size_t probe) const;

    /// System nodes of mesh vertices (−1 entries dropped).
    std::vector<std::uint32_t>
    nodes_of_vertices(const std::vector<std::uint32_t> &vertices) const;

  private:
    struct Tool
    {
      std::string                name;
      std::vector<std::uint32_t> nodes;
      Matrix3Xd                  offsets; ///< in the tool's frame, m
      ToolPose                   pose;
    };
    struct Prescribed
    {
      std::vector<std::uint32_t> nodes;
      Motion                     motion;
    };
    struct Probe
    {
      std::array<std::uint32_t, 4> nodes;
      Eigen::Vector4d              weights;
    };

    /// Holds @p nodes by @p tool at their present offsets from @p pose.
    void
    hold(Tool &tool, const std::vector<std::uint32_t> &nodes, const ToolPose &pose);

    /// What the bodies exert on the needle and the nodes tool @p j holds, about @p origin,
    /// from nodes.force (evaluate_forces) and the needle's load with substep @p dt
    /// (NeedleCoupling::needle_load, of a @p free needle).
    ToolForce
    load_on_tool(std::size_t j, const Vector3d &origin, double dt, bool free = false) const;
    /// The free needle's step of length @p dt at the state the integrator left.
    void
    move_free_needle(double dt);

    /// Forces the bodies exert on every node at the current state (nodes.force), from
    /// the interactions from @p first_interaction on (0: all; nodes untouched by the
    /// skipped ones get their exact force).
    void
    evaluate_forces(std::size_t first_interaction = 0);

    System                       sys;
    const mesh::SimplexMesh     *mesh = nullptr;
    std::unique_ptr<TissueModel> tissue_model;
    std::unique_ptr<SutureModel> suture_model;
    std::unique_ptr<Integrator>  time_integrator;
    SurfaceContact              *contact = nullptr;
    SelfCollision               *self_collision_set = nullptr;
    NeedleCoupling              *needle_coupling = nullptr;
    NodeAccess                  *access_set      = nullptr;
    std::vector<SurfaceContact *> probe_contacts; ///< one per probe
    double                        probe_stiffness = 0; ///< the stiffest probe's, N/m
    WoundFaceContact             *face_contact    = nullptr;
    std::vector<unsigned>        accesses_on_link; ///< how many accesses each suture link holds
    std::size_t                  needle_tool     = 0;
    std::optional<FreeNeedle>    free_body;       ///< the needle while let go
    ToolPose                     grip;            ///< the needle's pose in its tool's frame
    double                       contact_stiffness = 0;
    bool                         refuse_above_limit = false;

    std::vector<Tool>       tools;
    std::vector<Prescribed> prescribed;
    Loads                   loads;
    std::vector<Probe>      probes;

    /// The stability limit of the step, the warning above it and the guard's diagnosis
    /// (at set-up, or again after a change of topology: seed 002's subdivision). Throws
    /// when above the limit at set-up and asked to refuse.
    void
    assess_stability(bool at_setup);

    double      h = 1e-3, t = 0, dt_limit = 0;
    unsigned    n_substeps = 1;
    std::size_t n_steps    = 0;
    std::string limit_text, warning_text;
    bool        initialized = false;
    std::size_t tissue_interactions = 0; ///< the tissue's interactions come first
    bool        tools_on_suture     = false;

    StepPhases              step_phases;
    DivergenceGuard         guard;
    Matrix3Xd               good_x, good_v;
    std::vector<ToolForce>  forces;
    std::vector<ToolPose>   start_poses;
    std::vector<std::uint32_t> transient_nodes;
  };
} // namespace suturesim::realtime
