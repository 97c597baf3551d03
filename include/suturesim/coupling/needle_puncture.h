#pragma once
/**
 * @file
 * Puncture by a needle tip, shared by both model paths (each supplies the tissue
 * surface as triangles over its own points and turns the forces into its own loads).
 *
 * The tip is a point. While it is outside the tissue, the first step that finds it
 * behind the surface (negative signed distance to the nearest surface triangle) starts a
 * touch: the surface material point under the tip (closest point, as a triangle and
 * barycentric weights) is pressed by penalty along the surface's outward normal n
 * captured at the touch, F = k_c max(0, (x_m − x_tip)·n) — the tissue dimples. When F
 * reaches the tissue's puncture threshold the surface gives way: a pierce point is born
 * at that material point (seed 000 §VI: "the tension increases continuously and exceeds
 * the threshold at last. Then, the tension is released and the needle will pierce
 * through the surface"; seed 002 §4.A). Inside, the tip cuts freely until it reaches the
 * surface from within; the exit works the same way with the tip pushing the surface
 * outward (tenting), F = k_c max(0, (x_tip − x_m)·n). A tip that backs off a touch ends
 * it. Every touch and puncture is an event (kind, time, position, force).
 *
 * A tip that moves farther in one step than the tissue's gaps are wide (an implicit
 * step of the accurate path: 0.6 mm against a wound gaping 0.17 mm at the stitch's
 * depth) can pass out of one surface and into the next between two looks, and the
 * nearest-point test then sees it inside the second body, as if nothing happened; in
 * the gap it sees the next body's face from the front and takes that for an exit. So
 * the tip's path since the last look, a segment, is tested against the surface first:
 * the first triangle it crosses the right way (inwards from outside, outwards from
 * inside) starts the touch at the crossing point. The nearest-point test remains for
 * the first look and for a path that crossed nothing (a tip that started the step on
 * the surface).
 */

#include <suturesim/collision/triangle_sphere_tree.h>
#include <suturesim/core/model_parameters.h>
#include <suturesim/mesh/simplex_mesh.h>

#include <Eigen/Core>

#include <nlohmann/json_fwd.hpp>

#include <string>
#include <vector>

namespace suturesim::coupling
{
  using Eigen::Matrix3Xd;
  using Eigen::Vector3d;

  /// A material point of the surface: triangle index and barycentric weights.
  struct SurfacePoint
  {
    std::uint32_t triangle = 0;
    Vector3d      weights  = Vector3d::Zero();
  };

  /// Declared and parsed by the law (the scene's "Puncture" subsection, both paths).
  /// Default threshold 0.7 N: the force to puncture with 3-0 to 5-0 taper and
  /// reverse-cutting suture needles measured 0.61–0.90 N (Maloney et al. 2025, Ann.
  /// Plast. Surg. 95:423, rabbit ear cartilage); sheepskin shows the entry and exit
  /// peaks (Frick et al. 2001, J. Biomech. 34:1335). Scenes set their own.
  struct PunctureParameters
  {
    double threshold = 0.7;  ///< puncture force, N
    double stiffness = 2000; ///< penalty k_c of the tip on the surface, N/m
    double reach     = 1e-3; ///< how far from the surface the tip is looked for, m
    /// ρ of the tissue that carries the tip's touch (the accurate path's point loads,
    /// tissue/point_loads.h), m; 0: a point load, whose dimple, and with it where the tip
    /// punctures, grows without bound as the mesh is refined (Kelvin's solution)
    double touch_radius = 0;

    /// "Threshold", "Tip stiffness", "Reach", "Touch radius", with these defaults.
    static void
    declare(ParameterDeclarations &declarations);
    /// The values of declare()'s entries; ParameterError for a bad one.
    static PunctureParameters
    parse(const ParameterValues &values);
  };

  struct PunctureEvent
  {
    std::string kind; ///< touch_entry, puncture_entry, touch_exit, puncture_exit, release
    double      time  = 0;
    Vector3d    position = Vector3d::Zero(); ///< of the tip, m
    double      force = 0;                   ///< normal force at the event, N
    /// A puncture's (zero for the other kinds): the material point pierced (X, m), and,
    /// when the tip touched the surface there, the surface's outward normal and the
    /// needle's unit tangent at the tip (its direction of advance); the angle between the
    /// two is the needle's entry or exit angle (tearing/stitch_evaluation.h).
    Vector3d reference = Vector3d::Zero();
    Vector3d normal    = Vector3d::Zero();
    Vector3d direction = Vector3d::Zero();
  };

  /// An event as JSON (a checkpoint's, io/checkpoint.h) and back.
  nlohmann::json
  event_state(const PunctureEvent &event);
  PunctureEvent
  event_from(const nlohmann::json &state);

  class NeedlePuncture
  {
  public:
    enum class Phase
    {
      outside,
      pressing_in,
      inside,
      pressing_out
    };

    /// The touched material point while pressing.
    struct Touch
    {
      SurfacePoint point;
      Vector3d     reference = Vector3d::Zero(); ///< X of the point, m
      Vector3d     normal    = Vector3d::Zero(); ///< outward normal at the touch
      Vector3d     direction = Vector3d::Zero(); ///< the needle's at the tip, at the touch
      bool         exit      = false;
    };

    /// @p triangles over the columns of @p reference (outward oriented).
    NeedlePuncture(const PunctureParameters &parameters, const std::vector<mesh::Triangle> &triangles,
                   const Matrix3Xd &reference);

    /// Starts or ends a touch for the tip at @p tip, advancing along the unit tangent
    /// @p direction, and the surface at @p current; call once per accepted state, before
    /// the step's forces. A touch found where the tip's path crossed the surface takes
    /// the direction there, interpolated between the last look's and this one's.
    void
    update(double time, const Vector3d &tip, const Vector3d &direction, const Matrix3Xd &current);

    /// The tip jumped (a double-pointed needle's other point leads now): the next
    /// update() finds the surface from the tip alone, not along a path from the last.
    void
    forget_path()
    {
      looked = false;
    }

    Phase
    phase() const
    {
      return state;
    }
    const Touch *
    touch() const
    {
      return pressing() ? &contact : nullptr;
    }
    /// The last touch, also after the puncture that ended it (where the pierce point is
    /// born).
    const Touch &
    last_touch() const
    {
      return contact;
    }
    bool
    pressing() const
    {
      return state == Phase::pressing_in || state == Phase::pressing_out;
    }

    /// Penalty force magnitude of the touch for the tip at @p tip and the touched point
    /// at @p x_point (0 when not pressing or separated), N; the force on the tissue point
    /// is −F n on entry, +F n on exit.
    double
    normal_force(const Vector3d &tip, const Vector3d &x_point) const;

    /// Direction of the force on the tissue point (−n on entry, +n on exit).
    Vector3d
    push_direction() const
    {
      return contact.exit ? contact.normal : Vector3d(-contact.normal);
    }

    /// After a converged step whose touch force was @p force: a puncture when it reached
    /// the threshold (returns true; last_touch() is where the pierce point is born).
    bool
    accept(double time, double force, const Vector3d &tip);

    const std::vector<PunctureEvent> &
    events() const
    {
      return log;
    }
    const PunctureParameters &
    parameters() const
    {
      return prm;
    }

    /// The touch and its history (phase, touched point, events, the last force and tip),
    /// for a checkpoint (io/checkpoint.h); restore() takes them back.
    nlohmann::json
    snapshot() const;
    void
    restore(const nlohmann::json &snapshot);

    /// The current position of a surface point.
    Vector3d
    position(const SurfacePoint &p, const Matrix3Xd &x) const;

    /// The surface's triangles changed (seed 002's subdivision), the surface being at
    /// @p x now: the bounding tree is built again.
    void
    surface_changed(const Matrix3Xd &x);
    /// The touched material point is now named @p point (the same place on another
    /// triangle: it became a vertex of its own).
    void
    rename_touch(const SurfacePoint &point)
    {
      contact.point = point;
    }

  private:
    /// Nearest surface point to @p tip among the triangles within reach; false if none.
    bool
    nearest(const Vector3d &tip, const Matrix3Xd &x, SurfacePoint &point, double &signed_distance,
            Vector3d &normal);
    /// The first crossing of the path [@p from, @p to] through the surface at @p x in the
    /// direction the phase looks for (inwards when outside), at @p along in [0, 1] of the
    /// path; false if none.
    bool
    first_crossing(const Vector3d &from, const Vector3d &to, const Matrix3Xd &x, SurfacePoint &point,
                   Vector3d &normal, double &along);

    PunctureParameters                 prm;
    const std::vector<mesh::Triangle> &triangles;
    collision::TriangleSphereTree      tree;
    Matrix3Xd                          reference;
    std::vector<std::uint32_t>         candidates;
    Phase                              state = Phase::outside;
    Touch                              contact;
    std::vector<PunctureEvent>         log;
    double                             last_force = 0;
    Vector3d                           last_tip   = Vector3d::Zero(); ///< at the last update()
    Vector3d                           last_direction = Vector3d::Zero(); ///< at the last update()
    bool                               looked     = false;             ///< whether last_tip is set
  };
} // namespace suturesim::coupling
