#pragma once
/**
 * @file
 * The "Suture" subsection of a scene: initial centreline (straight, circular arc or
 * polyline), elements, cross-section and material (or a named suture preset), end
 * conditions (free, clamped, pinned, or prescribed motion by keyframes), loads (end force
 * and end moment of fixed direction at the last end, gravity, distributed load, ramped
 * or constant), self-contact and Newton settings. It builds the RodModel and applies
 * the time-dependent boundary values and loads.
 */

#include <suturesim/rod/cross_section.h>
#include <suturesim/rod/rod_model.h>
#include <suturesim/core/parameter_file.h>

#include <deal.II/base/parameter_handler.h>

#include <map>
#include <string>
#include <vector>

namespace suturesim::rod
{
  struct EndCondition
  {
    std::string type = "free"; ///< free | clamped | pinned | prescribed
    /// t → (displacement of the end from its initial position [m], optional rotation
    /// vector applied to its initial frame [rad]); piecewise linear in t, held constant
    /// outside the keyframes.
    std::map<double, std::vector<double>> keyframes;
    /// From this time on the end is held (a grasper closing on it, realtime path); the
    /// keyframes then move it from where it was at that time, s. 0: from the start.
    double grasp_time = 0;
    /// "grasp": the keyframes displace the end from where it was held (its initial
    /// position, or where the grasper took it); "world": they are positions, reached
    /// in a straight line from where it was held by the first keyframe after the grasp
    /// (so that both model paths, whose ends hang differently, pull from the same
    /// place).
    std::string frame = "grasp";

    bool
    fixes_rotation() const;
    /// Displacement and rotation vector at time t.
    std::pair<Vec3, Vec3>
    motion(double t) const;
    /// Position of the end at time t (from the grasp time on, or from the start) when
    /// held at @p held_at, m.
    Vec3
    position(double t, const Vec3 &held_at) const;

    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(const dealii::ParameterHandler &prm, const ParameterScope &scope);
  };

  struct RodParameters
  {
    std::string       centreline = "straight";
    Vec3              start      = Vec3::Zero();
    Vec3              direction  = Vec3::UnitX();
    double            length     = 0.1;
    Vec3              centre     = Vec3::Zero();
    Vec3              normal     = Vec3::UnitZ();
    double            arc_radius = 0.01, start_angle = 0, sweep = M_PI;
    std::vector<Vec3> polyline;
    unsigned          elements = 32;

    std::string  preset = "custom";
    CrossSection section;

    EndCondition start_end, last_end;

    Vec3        end_force   = Vec3::Zero();
    Vec3        end_moment  = Vec3::Zero();
    Vec3        gravity     = Vec3::Zero();
    Vec3        distributed = Vec3::Zero();
    std::string load_ramp   = "linear";

    ContactParameters contact;
    NewtonParameters  newton;
    /// accurate stitch: each failed suture solve's iterations to suture_newton_trace.csv
    bool              trace_failures = false;
    double            damping = 0; ///< mass-proportional, 1/s
    double            stabilization = 0; ///< viscous drag per unit length, quasi-static pass, N s/m²
    /// Contact of the suture's nodes with the tissue's surface (accurate path with the
    /// tissue; coupling/accurate/suture_contact.h).
    struct TissueContact
    {
      bool   enabled   = true;
      double stiffness = 5e4;  ///< per node, N/m
      double depth     = 1e-3; ///< how far inside a node is still pushed out, m
      double smoothing = 1e-6; ///< the penalty's kink rounded over |g| < smoothing, m
    } tissue_contact;

    /// Declares into the current subsection ("Suture").
    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm, const ParameterScope &scope);

    /// The initial centreline: N + 1 nodes and frames whose first director is the
    /// tangent (parallel transported along polylines, so the rod starts twist free).
    void
    initial_configuration(std::vector<Vec3> &x, std::vector<Quat> &q) const;

    /// The stress-free rod with its end constraints and contact set up.
    RodModel
    create_model() const;

    /// Load factor at time t of a run ending at @p end_time.
    double
    load_factor(double t, double end_time) const;

    /// Sets the nodal loads of time t.
    void
    apply_loads(RodModel &model, double t, double end_time) const;

    /// Moves prescribed ends to their keyframe positions at time t (clamped and pinned
    /// ends stay where they started: @p initial holds that configuration).
    void
    apply_motion(RodModel &model, const RodModel &initial, double t) const;
  };
} // namespace suturesim::rod
