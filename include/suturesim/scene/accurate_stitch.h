#pragma once
/**
 * @file
 * The needle in the accurate path (Model = accurate, Bodies = tissue, or tissue and
 * suture), built and stepped: quasi-static steps along the needle's trajectory, each a
 * Newton solve of the FE tissue with the needle's loads at embedded material points
 * (coupling/accurate/tissue_needle.h).
 *  - With the suture (Bodies = tissue and suture, Needle/Attach suture): a Cosserat rod
 *    (rod/rod_model.h) clamped at the swage (position and frame move with the needle:
 *    the hard constraint of seed 002), its far end free or held by a grasper from its
 *    Grasp time on. Pierce points pass onto it at the swage and slide along it with the
 *    same friction law. Tissue and suture are solved by one Newton iteration, the
 *    suture condensed onto the tissue's points (coupling/accurate/condensed_suture.h);
 *    its nodes touch the tissue's surface by penalty (coupling/accurate/suture_contact.h)
 *    and a viscous drag holds its slack tail (rod/viscous_drag.h, Suture/Stabilization).
 *  - Rounds within a step follow only what a solve cannot change within itself: the
 *    contacts and, with Enforcement = lagrange, the multipliers' Uzawa update; a step
 *    that does not settle in Coupling iterations rounds fails.
 *  - With the phase field (`Tissue/Phase field`), the step's rounds alternate with the
 *    damage's solve until d settles (tissue::TissueModel::minimise_alternately()); the
 *    damage belongs to the tissue's state (undo, checkpoint).
 *  - Steps are controlled by core/cutback_stepper.h: a failed step is halved
 *    (Time/Max cutbacks in a row) with the needle's and the suture's state; a step that
 *    carries the touch force past 1.04 × the puncture threshold is halved too (up to 8
 *    more times), so that the puncture lands within 4 % above the threshold.
 *  - Closure (scene/wound_closure.h): the gap probes join the tissue's probes; the
 *    tie-off stops the needle's and the far end's motions; the incision's faces touch
 *    by penalty (coupling/accurate/wound_contact.h, Closure/Face contact).
 *  - An interrupted series (Needle/Pass/Series = interrupted; scene/interrupted_series.h
 *    decides when and where): the other hand's hold on a stitch's tail and the tie-off's
 *    holds on both strands clamp the rod's nodes where they are (all six components),
 *    and the thread is cut by leaving out one rod element (rod::RodModel::cut).
 * The record (forces.csv, VTU, summary.json) is scene/accurate_stitch_record.h's.
 */

#include <suturesim/core/cutback_stepper.h>
#include <suturesim/coupling/accurate/condensed_suture.h>
#include <suturesim/coupling/accurate/suture_contact.h>
#include <suturesim/coupling/accurate/tissue_needle.h>
#include <suturesim/coupling/accurate/wound_contact.h>
#include <suturesim/rod/viscous_drag.h>
#include <suturesim/scene/coupled_newton_trace.h>
#include <suturesim/scene/interrupted_series.h>
#include <suturesim/scene/needle_clearance.h>
#include <suturesim/scene/scene_parameters.h>
#include <suturesim/scene/suture_newton_trace.h>
#include <suturesim/tissue/condensed_bodies.h>
#include <suturesim/tissue/point_load_list.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>
#include <deal.II/distributed/tria.h>

#include <memory>
#include <optional>
#include <vector>

namespace suturesim::scene
{
  class AccurateStitch
  {
  public:
    /// Meshes the tissue into @p directory and builds every part of the problem.
    AccurateStitch(SceneParameters &scene, const std::string &directory, dealii::TimerOutput &timer);

    /// Equilibrium at t = 0 with the needle away; false with @p failure when it fails.
    bool
    solve_initial(std::string &failure);

    /// The cut-back stepper's hooks: solve to @p tn over a step @p dt; undo() goes back
    /// to the last accepted state, all of it and bit for bit (tissue, needle, the suture
    /// with its grasp and its contacts with the tissue, the wound faces' contact), so
    /// that a halved step, and the checkpoint a run that gives up writes, start where
    /// the failed step started (test Restart.AFailedRunsCheckpointIsItsLastAccepted…).
    StepAttempt
    attempt(double tn, double dt);
    void
    undo();
    /// Accepts the state: the needle's load and the pierce points' anchors. The state
    /// is then recorded, before advance() prepares the next step (the point loads of
    /// new pierce points, the surface).
    void
    accept();
    void
    advance();

    /// The state of the last accepted step, for a checkpoint (io/checkpoint.h): what every
    /// process holds alike (needle, suture, contacts, closure, the loads recorded), and
    /// this process's part of the tissue. restore() takes both back, in place of
    /// solve_initial().
    nlohmann::json
    snapshot() const;
    nlohmann::json
    local_snapshot() const;
    void
    restore(const nlohmann::json &shared, const nlohmann::json &local);

    /// This step's solver account (summary.json "steps").
    nlohmann::json
    step_statistics(double dt, unsigned cutbacks) const;

    /// The first event after @p t that an adaptive step ends on (∞: none): the kinks of
    /// the needle's motion and of the grasped end's (its grasp among them), s.
    double
    next_event(double t) const;

    // --- what the record reads -----------------------------------------------------------
    SceneParameters        &scene;
    const NeedleParameters &np;
    dealii::parallel::distributed::Triangulation<3> tria;
    mesh::MeshInfo                                  mesh_info;
    tissue::TissueParameters                        tissue_parameters; ///< with the gap probes
    std::size_t                                     first_gap_probe = 0;
    std::optional<ClosureMonitor>                   closure;
    std::unique_ptr<tissue::TissueModel>            model;
    tissue::BoundarySurface                         surface;
    tearing::Wound                                  wound; ///< the stitch evaluation's, reference
    tools::CurvedNeedle                             geometry;
    std::unique_ptr<coupling::TissueNeedle>         needle;
    tools::Trajectory                               path;
    /// a planned pass's needle out of the tissue after it; its reason() ends the run
    std::optional<NeedleClearance>                  clearance;
    double                                          pull_start = 0;
    std::optional<rod::RodModel>                    suture;
    std::optional<coupling::SutureContact>          contact;
    std::optional<coupling::WoundContact>           faces;
    std::optional<InterruptedSeries>                series; ///< Needle/Pass/Series = interrupted
    Eigen::Matrix3Xd                                x_surface; ///< the surface's vertices, last accepted state
    bool                                            grasped = false;
    /// of the last accepted step: the needle's force and torque, the grasper's pull on
    /// the far end, the drag's total, N (N m)
    std::pair<dealii::Tensor<1, 3>, dealii::Tensor<1, 3>> load;
    double                                                 end_tension = 0, stabilization_force = 0;

    /// The closure pairs' gaps (m) for the tissue's probe displacements @p probes.
    std::vector<double>
    gaps(const std::vector<dealii::Tensor<1, 3>> &probes) const;

    /// The tissue points of the point loads, current positions.
    std::vector<dealii::Point<3>>
    positions() const;

  private:
    /// The needle's planned path through the tissue (Motion = pass; else empty), for
    /// Mesh/Local refinement.
    std::vector<dealii::Point<3>>
    needle_path() const;
    void
    build_suture();
    void
    build_contacts();
    /// The suture's Newton settings under the coupled solve (and its trace into
    /// @p directory when asked for).
    void
    tune_suture_newton(const std::string &directory);
    /// The point loads on the tissue: the needle's touch and pierce points first (the
    /// needle numbers them from 0), then the contacts.
    void
    locate_loads();
    /// The needle's pose at time @p t: its motion, stopped at a tie-off, and in an
    /// interrupted series at each stitch's tail taken and tie-off.
    tools::Pose
    needle_pose(double t) const;
    /// An interrupted series after the step accepted at @p t: a tail taken, a stitch tied
    /// off (its nodes held, the thread cut).
    void
    advance_series(double t);
    /// The series' holds and cuts so far, on the rod and the pierce points' thread (a
    /// restart's).
    void
    apply_series();
    /// Moves the suture's held nodes to time @p t: the swage, an interrupted series' tails
    /// on their way to their lays, and the far end once grasped (from where it was then, by
    /// its keyframes, as in the realtime path).
    void
    hold_suture(double t);
    /// Moves the held node @p node to @p to, and the slack thread between it and the
    /// pierce point before it along, in proportion to the arc length (a predictor).
    void
    carry(std::size_t node, const rod::Vec3 &to);
    /// New contacts of the suture against the surface at @p at; true when they changed.
    /// From the sixth round of a step on, the set only grows (SutureContact::detect()).
    bool
    detect_contacts(const Eigen::Matrix3Xd &at);
    /// The faces' loaded pairs for the surface at @p at; true when they changed.
    bool
    detect_faces(const Eigen::Matrix3Xd &at);
    /// Coupled solves until the contacts and multipliers settle (this step's rounds),
    /// adding to the attempt's step_iterations and suture_iterations (attempt() zeroes them).
    void
    solve_rounds(double tn);

    double                                   force_floor = 0;
    bool                                     lagrange    = false;
    tools::Pose                              pose0;
    rod::Quat                                frame0;
    rod::Vec3                                grasped_at = rod::Vec3::Zero();
    rod::NewtonParameters                    suture_newton;
    tissue::PointLoadList                    loads;
    std::optional<rod::ViscousDrag>          drag;
    rod::NodalTerms                          node_terms, drag_terms, contact_terms;
    std::optional<SutureNewtonTrace>         trace;
    std::optional<coupling::CondensedSuture> body;
    std::vector<tissue::CondensedBody *>     parts;
    std::optional<tissue::CondensedBodies>   both;
    std::optional<CoupledNewtonTrace>        coupled_trace; ///< wraps the body solved with the tissue
    tissue::CondensedBody                   *coupled = nullptr;
    std::vector<rod::Vec3>                   saved_x;
    std::vector<rod::Quat>                   saved_q;
    bool                                     saved_grasped = false; ///< grasped, at the step's start
    Eigen::Matrix3Xd                         round_surface;
    tissue::NewtonReport                     report;
    unsigned                                 rounds         = 0;
    bool                                     solve_failed   = false; ///< the last coupled or tissue solve (not its rounds)
    unsigned                                 step_iterations = 0; ///< this attempt's, over its rounds
    unsigned                                 suture_iterations = 0; ///< this attempt's most of one suture solve
    std::vector<double>                      damage_changes; ///< this attempt's damage solves' changes of d
    std::vector<double>                      events;          ///< sorted, s
    std::optional<tools::SurgicalSeries>     planned;         ///< an interrupted series' passes
    double                                   step_time = 0;   ///< of the step attempted last, s
    Eigen::VectorXd                          suture_reaction; ///< a series': the rod's residual accepted last, N (N m)
    bool                                     points_changed = false;
  };
} // namespace suturesim::scene
