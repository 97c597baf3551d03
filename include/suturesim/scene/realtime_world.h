#pragma once
/**
 * @file
 * The realtime world of a scene (Model = realtime), built from the scene's shared
 * subsections:
 *  - Mesh: the same gmsh file as the accurate path, read as tetrahedra;
 *  - Tissue/Material: E and ν from the shear and bulk moduli of the small-strain limit
 *    (per region with Tissue/Region moduli), ρ from the density; Tissue/Boundary
 *    conditions: fixed and prescribed boundaries hold their surface nodes, tractions
 *    become nodal loads, gravity acts on every node; Tissue/Probes: interpolated
 *    displacements;
 *  - Suture: centreline, section (EA, EI, radius, density) and ends: an end whose frame
 *    is fixed (clamped, or prescribed with rotations) is a tool holding its two end
 *    nodes (a grasper fixes position and direction); a pinned end, or one prescribed by
 *    displacements only, a tool holding one; a grasper that closes later (Grasp time)
 *    holds nothing until then;
 *  - Needle (scene/realtime_needle.h), Closure (two probes per gap pair);
 *  - Realtime/Tearing: seed 003's tears at the needle's pierce points
 *    (realtime/ligament_tearing.h), through the Stitch evaluation's wound;
 *  - Knot: seed 002's planner (knot/planner.h) moves the grasper on the suture's last
 *    end, the first held; for a plan that moves both (the square knot), each in turn.
 *    In a stitch (a Needle holding the suture's first end at its swage) the planner
 *    takes over the needle and the last end's grasper once their motions are over, and
 *    moves the first end by translating the needle as the driver holds it; the
 *    projection plane is given, or the plane of the needle's last three pierce points.
 * It also gives each tool its pose at a time and measures the closure's gaps.
 */

#include <suturesim/knot/planner.h>
#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/realtime/ligament_tearing.h>
#include <suturesim/realtime/world.h>
#include <suturesim/scene/interrupted_series.h>
#include <suturesim/scene/needle_clearance.h>
#include <suturesim/scene/realtime_needle.h>
#include <suturesim/scene/realtime_settings.h>
#include <suturesim/scene/scene_parameters.h>

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace suturesim::scene
{
  class RealtimeWorld
  {
  public:
    /// Builds the world into its initialised state; @p directory receives gmsh's mesh.
    RealtimeWorld(SceneParameters &scene, const RealtimeSettings &settings, RealtimeModels models,
                  const std::string &directory);

    /// The poses of every tool at time @p t (a grasper closes on its end at its grasp
    /// time, where the end is then).
    void
    tool_poses(double t, std::vector<realtime::ToolPose> &poses);

    /// Why the run ends before its end time: a planned pass's needle driven back into the
    /// tissue (NeedleClearance::reason(), found by tool_poses()); "" while it goes on.
    const std::string &
    stop_reason() const;

    /// The closure gaps of the current state and the suture tension charged to them:
    /// what the grasper on the suture's far end feels, else the needle's pull.
    void
    measure_closure();

    /// The suture's tension, as the closure and the tears are charged to it (the accurate
    /// path's measure): the last end's grasper's pull once it holds the end, else the
    /// needle's pull, N; in an interrupted series the needle's pull, which draws each
    /// stitch tight.
    double
    closure_tension() const;

    /// An interrupted series (Needle/Pass/Series), between steps, stitch by stitch
    /// (scene/interrupted_series.h decides when and where): the other hand's tool takes
    /// the stitch's tail, and once the closure ties the stitch off a tool of its own holds
    /// the thread where it is on each strand and the thread is cut next to the needle
    /// strand's hold (SutureModel::cut); the rest, on the needle, is the next stitch's
    /// suture. A ParameterError naming Needle/Pass/Pull when the exit's hold would fall on
    /// the needle's swage (too little thread drawn through).
    void
    advance_series();
    /// metrics.interrupted_series: per stitch when its tail was taken (s) and whether its
    /// pull stopped for it (the tail short before the pull's end), the suture node its
    /// thread was cut at (null before its tie-off); nothing without a series.
    void
    write_series(nlohmann::json &metrics) const;

    struct Boundary
    {
      std::string                name;
      std::vector<std::uint32_t> nodes;
    };
    struct ToolEnd
    {
      std::string                name;
      const rod::EndCondition   *end;
      realtime::Vector3d         initial;
      std::vector<std::uint32_t> held;
      bool                       grasped = true; ///< false until its Grasp time
    };

    SceneParameters                                 &scene;
    mesh::SimplexMesh                                tissue_mesh;
    mesh::BoundarySurface                            surface;
    mesh::MeshInfo                                   mesh_info; ///< the tissue mesh's names
    tearing::Wound                                   wound; ///< the stitch evaluation's, reference
    std::unique_ptr<realtime::World>                 world;
    std::vector<Boundary>                            boundaries;
    std::optional<RealtimeNeedle>                    needle;
    /// a planned pass's needle out of the tissue after it; its reason() ends the run
    std::optional<NeedleClearance>                   clearance;
    std::optional<realtime::LigamentTearing>         tearing; ///< Realtime/Tearing, when on
    std::optional<knot::KnotPlanner>                 planner; ///< Knot, when one is tied
    std::size_t                                      first_end_tool = 0; ///< the suture ends' tools follow the needle's
    std::vector<ToolEnd>                             tool_ends;
    std::vector<std::pair<std::string, std::size_t>> probes;
    std::vector<std::string>                         access_names; ///< Realtime/Access points, in order
    std::optional<std::size_t>                       probe_tool; ///< Realtime/Probe's tool
    RealtimeSettings::Probe                          probe;
    std::optional<ClosureMonitor>                    closure;
    std::vector<std::pair<std::size_t, std::size_t>> gap_probes;
    std::vector<double>                              gaps; ///< of the last measure_closure()
    /// An interrupted series' state, and per stitch two tools (its tie, its tail's hand)
    /// from first_series_tool on.
    std::optional<InterruptedSeries> series;
    std::size_t                      first_series_tool = 0;
    /// per suture link: 0 where cut (the record's longest link leaves it out), else 1
    Eigen::RowVectorXd        uncut;

  private:
    void
    read_tissue(realtime::WorldSetup &setup, const std::string &directory);
    void
    place_suture(realtime::WorldSetup &setup);
    void
    hold_boundaries();
    /// The scene's tractions as nodal loads, each loaded triangle integrated over
    /// @p subdivision² sub-triangles (RealtimeSettings::traction_subdivision).
    void
    add_tractions(unsigned subdivision);
    /// Realtime/Face contact stiffness: the incision's faces (Closure/Face contact) kept
    /// apart, face A's nodes against face B's triangles.
    void
    add_face_contact(const RealtimeSettings &settings);
    void
    add_tools(const RealtimeSettings &settings);
    void
    add_probes();
    /// Realtime/Access points (seed 004's node access) on the suture.
    void
    add_access(const RealtimeSettings &settings);
    /// Realtime/Probe (seed 004's external stage), a tool after the others.
    void
    add_probe(const RealtimeSettings &settings);
    /// Knot: the planner and the checks of what it needs.
    void
    add_knot_planner();
    /// An interrupted series: its tools (a tie and a tail's hand per stitch) and checks.
    void
    add_series();
    /// The normal of the plane through the needle's last three pierce points at @p t
    /// (Knot/Projection plane = pierce points); a ParameterError naming the entry when
    /// there are fewer, or they lie on one line.
    Eigen::Vector3d
    pierce_plane_normal(double t) const;

    double planner_time = 0; ///< of the planner's last move, s
    /// A stitch tied off: the needle's pose and the suture's first node when the planner
    /// took the needle over; the planner's moves of that end translate the needle.
    std::optional<std::pair<tools::Pose, Eigen::Vector3d>> needle_taken;
  };
} // namespace suturesim::scene
