#include <suturesim/core/error.h>
#include <suturesim/io/state_json.h>
#include <suturesim/scene/accurate_stitch.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <tuple>
#include <sstream>
#include <string>

namespace suturesim::scene
{
  using namespace dealii;

  AccurateStitch::AccurateStitch(SceneParameters &s, const std::string &directory, TimerOutput &timer)
    : scene(s)
    , np(s.needle)
    , tria(MPI_COMM_WORLD)
    , tissue_parameters(s.tissue)
    , geometry(s.needle.needle())
    , path(s.needle.trajectory())
  {
    // the accurate path moves its needle as a kinematic tool throughout: it has no free
    // rigid body to let go
    const auto [section, key] = np.release_entry();
    scene.scope(section).require(!np.released(), key,
                                 "the accurate path cannot let the needle go (it is a kinematic tool there); run "
                                 "this scene under Model = realtime");
    scene.scope("Needle").require(np.shape != "double-pointed", "Shape",
                                  "the accurate path's needle is a curved arc (coupling/accurate/tissue_needle.h), "
                                  "and its jaws cannot pass a needle across; run this scene under Model = realtime");
    {
      TimerOutput::Scope section(timer, "mesh");
      mesh_info = mesh::create_mesh(scene.mesh, directory, tria, needle_path());
    }
    scene.boundary_conditions.resolve(mesh_info);
    // the closure's gap probes join the tissue's own (after them)
    first_gap_probe = tissue_parameters.probes.size();
    if (scene.closure.present())
      {
        closure.emplace(scene.closure);
        for (const auto &pair : scene.closure.pairs)
          for (const auto &[side, X] : {std::pair{"a", pair.a}, std::pair{"b", pair.b}})
            tissue_parameters.probes.emplace_back("gap_" + pair.name + "_" + side, Point<3>(X[0], X[1], X[2]));
      }
    model = std::make_unique<tissue::TissueModel>(MPI_COMM_WORLD, tissue_parameters, *scene.material,
                                                  scene.boundary_conditions, tria, timer);
    model->setup();
    surface = model->boundary_surface();
    wound   = scene.wound(mesh_info, surface.reference, surface.triangles, surface.ids);

    coupling::TissueNeedleParameters parameters;
    parameters.puncture             = np.puncture;
    parameters.friction             = np.friction;
    parameters.transverse_stiffness = np.transverse_stiffness;
    parameters.spacing              = np.spacing;
    parameters.lagrange             = np.enforcement == "lagrange";
    parameters.normal_smoothing     = np.transverse_stiffness * np.coupling_tolerance;
    parameters.load_radius          = np.load_radius;
    lagrange                        = parameters.lagrange;
    np.check_entry_on_surface(surface.triangles, surface.reference, scene.scope("Needle/Pass"));
    needle = std::make_unique<coupling::TissueNeedle>(geometry, parameters, surface.triangles, surface.reference);
    if (!np.load_across_wound) // its faces: checked with the scene (SceneParameters::parse_common)
      needle->set_cut([this](const Point<3> &a, const Point<3> &b) {
        return wound.hides({a[0], a[1], a[2]}, {b[0], b[1], b[2]});
      });
    pull_start = np.motion == "pass" ? np.planned_pass().t_turn_end : 0;
    clearance.emplace(np);
    pose0      = path.pose(0);
    if (scene.bodies == "tissue and suture")
      build_suture();
    if (suture && closure && scene.closure.tie_off_each_stitch)
      {
        // (its checks: scenarios/accurate_needle.cc)
        planned = np.planned_series();
        closure->set_stitches(InterruptedSeries::windows(*planned));
        std::vector<double> arc{0.0};
        for (const auto &r : suture->references())
          arc.push_back(arc.back() + r.length);
        series.emplace(np, std::move(arc), geometry.length());
      }
    build_contacts();
    // where adaptive steps end: the needle's kinks, the grasp and the grasped end's
    // keyframes (linear between them, so each is a kink)
    events = path.kinks();
    if (suture && scene.suture.last_end.type != "free")
      {
        events.push_back(scene.suture.last_end.grasp_time);
        for (const auto &key : scene.suture.last_end.keyframes)
          events.push_back(key.first);
      }
    std::sort(events.begin(), events.end());
    events.erase(std::unique(events.begin(), events.end()), events.end());
    model->expect_symmetric_tangent(needle->symmetric_tangent(),
                                    "the pierce points' friction on the thread (Pierce points/Friction "
                                    "coefficient > 0) or Lagrange tie");
    // The tissue is solved to a hundredth of the force a pierce tie carries at the
    // coupling tolerance: finer residuals move no point measurably, and a solve that
    // starts near equilibrium would otherwise chase its relative tolerance for half a
    // dozen iterations. The suture, whose equilibrium under each tissue iterate is part
    // of the tissue's residual (coupling/accurate/condensed_suture.h), to a tenth of
    // that: on the tissue's floor itself it left the coupled iteration stalled just
    // above it (the stitch's tightening: 2.5e-4 N after 25 iterations at k⊥ = 5e4 N/m,
    // floor 5e-5 N), and its iterations cost little.
    force_floor = 0.01 * np.transverse_stiffness * np.coupling_tolerance;
    if (suture)
      tune_suture_newton(directory);
    // the suture, solved with the tissue in one Newton iteration
    if (suture)
      body.emplace(*suture, suture_newton, *needle, contact ? &*contact : nullptr, loads,
                   drag || contact ? &node_terms : nullptr);
    // what is solved with the tissue: the suture, the wound's faces, or both
    if (body)
      parts.push_back(&*body);
    if (faces)
      parts.push_back(&*faces);
    both.emplace(parts);
    coupled = parts.empty() ? nullptr : parts.size() == 1 ? parts.front() : &*both;
    if (coupled && body && scene.suture.trace_failures && Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
      {
        coupled_trace.emplace(*coupled, (std::filesystem::path(directory) / "coupled_newton_trace.csv").string(),
                              [this](const tissue::CondensedBody::Trial &trial) {
                                CoupledNewtonTrace::BodyState state;
                                state.suture_iterations = body->last_iterations();
                                state.contacts          = contact ? contact->contacts().size() : 0;
                                state.pressing          = contact ? contact->n_pressing(suture->positions()) : 0;
                                state.touching          = faces ? faces->n_touching() : 0;
                                state.points            = body->point_states();
                                // a state not reached keeps BodyState's NaN largest entry
                                if (!std::isnan(trial.residual))
                                  {
                                    const auto [largest, dof] = model->largest_free_residual();
                                    state.largest             = largest;
                                    std::tie(state.largest_at, state.largest_component) = model->dof_location(dof);
                                  }
                                return state;
                              });
        coupled = &*coupled_trace;
      }
  }

  std::vector<Point<3>>
  AccurateStitch::needle_path() const
  {
    // the arc the tip follows from the entry to the exit point (a pass turns the needle
    // about its own arc centre, so its body follows the same arc)
    std::vector<Point<3>> arc;
    if (np.motion != "pass")
      return arc;
    const auto     pass = np.planned_pass(); // one pass: SceneParameters refuses a series with it
    constexpr unsigned samples = 64;
    for (unsigned k = 0; k <= samples; ++k)
      {
        const double t = pass.t_tip_entry + (pass.t_tip_exit - pass.t_tip_entry) * k / samples;
        const auto   x = geometry.tip(path.pose(t));
        arc.emplace_back(x[0], x[1], x[2]);
      }
    return arc;
  }

  void
  AccurateStitch::build_suture()
  {
    // straight from the swage along the needle's trailing direction, its first node
    // clamped to the swage's frame (which turns with the needle)
    rod::RodParameters rp = scene.suture;
    rp.centreline         = "straight";
    rp.start              = geometry.swage(pose0);
    rp.direction          = -geometry.tangent(pose0, geometry.length());
    rp.last_end.type      = "free"; // held by hold_suture() from its grasp time on
    suture.emplace(rp.create_model());
    suture->constrain(0, {{true, true, true, true, true, true}});
    frame0 = suture->rotations()[0];
    std::vector<double> lengths;
    for (const auto &r : suture->references())
      lengths.push_back(r.length);
    needle->set_thread(&suture->positions(), lengths, &suture->rotations());
    if (scene.suture.stabilization > 0)
      drag.emplace(*suture, scene.suture.stabilization);
  }

  void
  AccurateStitch::build_contacts()
  {
    // the suture's nodes against the tissue's surface, outside the pierce points
    if (suture && scene.suture.tissue_contact.enabled)
      {
        contact.emplace(coupling::SutureContactParameters{scene.suture.tissue_contact.stiffness,
                                                          scene.suture.section.radius,
                                                          scene.suture.tissue_contact.depth,
                                                          scene.suture.tissue_contact.smoothing},
                        surface.triangles, surface.reference);
        contact->set_suture(&suture->positions());
      }
    // the incision's faces against each other (Closure/Face contact)
    if (scene.closure.present() && !scene.closure.face_contact.empty())
      {
        const auto [a, b] = scene.closure.face_contact_ids(mesh_info);
        faces.emplace(coupling::WoundContactParameters{scene.closure.face_contact_stiffness,
                                                       scene.closure.face_contact_margin},
                      surface.reference, surface.triangles, surface.ids, a, b);
      }
    // the terms the pass adds at the suture's nodes: the drag and the contact
    drag_terms = [this](const std::size_t i, const rod::Vec3 &xi, const rod::Quat &, rod::Vec6 &r, rod::Mat6 &J) {
      if (drag)
        drag->add(i, xi, r, J);
    };
    contact_terms = [this](const std::size_t i, const rod::Vec3 &xi, const rod::Quat &, rod::Vec6 &r,
                           rod::Mat6 &J) {
      if (contact)
        contact->add_node_terms(i, xi, r, J);
    };
    node_terms = [this](const std::size_t i, const rod::Vec3 &xi, const rod::Quat &q, rod::Vec6 &r, rod::Mat6 &J) {
      drag_terms(i, xi, q, r, J);
      contact_terms(i, xi, q, r, J);
    };
  }

  void
  AccurateStitch::tune_suture_newton(const std::string &directory)
  {
    suture_newton                = scene.suture.newton;
    if (scene.suture.trace_failures && Utilities::MPI::this_mpi_process(MPI_COMM_WORLD) == 0)
      {
        trace.emplace(std::vector<std::pair<std::string, const rod::NodalTerms *>>{{"stabilization", &drag_terms},
                                                                                  {"contact", &contact_terms}},
                      (std::filesystem::path(directory) / "suture_newton_trace.csv").string(),
                      [this] { return body->point_states(); });
        suture_newton.observer = [this](const rod::NewtonIterate &iterate) { trace->record(*suture, iterate); };
      }
    suture_newton.absolute_floor = std::max(suture_newton.absolute_floor, 0.1 * force_floor);
    // the suture's equilibrium under each tissue iterate: slack thread crawls at the
    // step cap below (measured: up to a hundred iterations at the tightening), and an
    // iteration costs a fraction of a millisecond
    suture_newton.max_iterations = std::max(suture_newton.max_iterations, 500u);
    // a stiff pierce tie pulls the node it holds by millimetres on the first iteration
    // of a round, and the free tail would swing with it: half an element and a quarter
    // radian per iteration at most
    double shortest = std::numeric_limits<double>::infinity();
    for (const auto &r : suture->references())
      shortest = std::min(shortest, r.length);
    suture_newton.max_displacement = 0.5 * shortest;
    suture_newton.max_rotation     = 0.25;
  }

  void
  AccurateStitch::locate_loads()
  {
    std::vector<const tissue::PointLoads *> list{needle.get()};
    if (contact)
      list.push_back(&*contact);
    if (faces)
      list.push_back(&*faces);
    loads.set(list);
    if (faces)
      faces->set_offset(loads.offset(list.size() - 1));
    model->set_point_loads(loads.points().empty() ? nullptr : &loads);
  }

  void
  AccurateStitch::hold_suture(const double t)
  {
    const tools::Pose pose = needle_pose(t);
    suture->set_node(0, geometry.swage(pose), pose.orientation * pose0.orientation.inverse() * frame0);
    // an interrupted series' tail hands, each carrying its tail to its lay
    for (std::size_t k = 0; series && k < series->size(); ++k)
      if (const auto node = series->tail_node(k))
        carry(*node, series->tail_position(k, t, closure->stitch_ties()));
    const auto       &end  = scene.suture.last_end;
    const std::size_t last = suture->n_nodes() - 1;
    if (end.type == "free" || t < end.grasp_time)
      return;
    if (!grasped)
      {
        grasped      = true;
        grasped_at   = suture->positions()[last];
        const bool r = end.fixes_rotation();
        suture->constrain(last, {{true, true, true, r, r, r}});
      }
    const double motion = closure ? closure->motion_time(t) : t;
    carry(last, end.position(std::max(motion, end.grasp_time), grasped_at));
  }

  void
  AccurateStitch::carry(const std::size_t node, const rod::Vec3 &to)
  {
    // A hand carries the slack thread between it and the pierce point before it along
    // as a predictor, the move growing linearly with the arc length to it: moved alone,
    // the end node of a thread drawn at 60 mm/s stretched its element to several times
    // its length, and the suture's Newton iteration, its directions turning the slack
    // thread by thousands of radians, crawled at the step cap for 500 iterations
    // (docs/interrupted_stitch.md). The solve then starts from a thread of about its
    // own length.
    const rod::Vec3 d = to - suture->positions()[node];
    // a hand that has stopped (a tail laid and tied, an end after the tie-off) is there
    // already: hold_suture() asks this of it at every attempt
    if (d.isZero(0))
      return;
    std::size_t from = 0;
    for (const std::size_t e : needle->thread_elements())
      if (e < node)
        from = std::max(from, e + 1);
    const auto &refs = suture->references();
    double      span = 0;
    for (std::size_t k = from; k < node; ++k)
      span += refs[k].length;
    double along = 0;
    for (std::size_t i = from + 1; i < node && span > 0; ++i)
      {
        along += refs[i - 1].length;
        suture->set_node(i, suture->positions()[i] + along / span * d, suture->rotations()[i]);
      }
    suture->set_node(node, to, suture->rotations()[node]);
  }

  tools::Pose
  AccurateStitch::needle_pose(const double t) const
  {
    const double motion = closure ? closure->motion_time(t) : t;
    return planned ? planned->pose(motion, series->pull_stops(), closure->stitch_ties()) : path.pose(motion);
  }

  void
  AccurateStitch::advance_series(const double t)
  {
    if (!series)
      return;
    const auto                           x     = positions();
    const std::size_t                    first = needle->first_pierce_index();
    const auto                          &p     = needle->pierce_points(); // ζ ascending: the newest first
    std::vector<InterruptedSeries::Hole> holes;
    for (std::size_t j = 0; j < p.size(); ++j)
      holes.push_back({p[j].zeta, {x[first + j][0], x[first + j][1], x[first + j][2]}, p[j].anchor > geometry.length()});
    const auto act = series->advance(t, holes, *closure, scene.scope("Needle/Pass"),
                                     [this](const std::size_t i) -> Eigen::Vector3d { return suture->positions()[i]; });
    // the hand's pull on the tail as the stitch is tied off: the reaction at its clamped
    // node in the accepted state
    if (!act.tie.empty())
      series->set_tail_force(act.stitch, suture_reaction.segment<3>(6 * *series->tail_node(act.stitch)).norm());
    if (act.tail || !act.tie.empty())
      apply_series();
  }

  void
  AccurateStitch::apply_series()
  {
    // clamped where they are: a hand or a knot holds the strand and its turn
    for (const std::size_t node : series->held_nodes())
      suture->constrain(node, {{true, true, true, true, true, true}});
    for (const std::size_t e : series->cut_elements())
      {
        suture->cut(e);
        needle->cut_thread(e);
      }
  }

  std::vector<Point<3>>
  AccurateStitch::positions() const
  {
    std::vector<Point<3>> x(needle->points().size());
    for (std::size_t k = 0; k < x.size(); ++k)
      x[k] = model->point_position(k);
    return x;
  }

  bool
  AccurateStitch::detect_contacts(const Eigen::Matrix3Xd &at)
  {
    // left out: the nodes a stitch's pierce points draw into the tissue and the nodes a
    // support holds
    std::vector<char> skip = needle->thread_nodes_in_tracts();
    skip.front()           = 1;
    skip.back()            = skip.back() || grasped;
    if (series)
      for (const std::size_t node : series->held_nodes())
        skip[node] = 1;
    // After five rounds, the most that any step of the wound series that settled took
    // (L1, 2026-11-28), the set only grows: on L1 and L2 a step's contacts still changed
    // after 40 rounds, each a coupled solve, and the step was halved
    // (docs/interrupted_stitch.md).
    const bool changed = contact->detect(at, suture->positions(), skip, rounds > 5);
    if (changed)
      locate_loads();
    return changed;
  }

  bool
  AccurateStitch::detect_faces(const Eigen::Matrix3Xd &at)
  {
    const bool changed = faces && faces->detect(at);
    if (changed)
      locate_loads();
    return changed;
  }

  bool
  AccurateStitch::solve_initial(std::string &failure)
  {
    // a pass that starts inside the tissue has pierce points at t = 0 already
    if (needle->begin_step(0, path.pose(0), surface.reference))
      locate_loads();
    report = model->solve_static(0, force_floor);
    failure = report.failure;
    if (report.converged)
      model->surface_positions(surface, x_surface);
    return report.converged;
  }

  void
  AccurateStitch::solve_rounds(const double tn)
  {
    for (rounds = 1;; ++rounds)
      {
        report = coupled ? model->solve_coupled(tn, force_floor, *coupled) : model->solve_static(tn, force_floor);
        solve_failed = !report.converged;
        step_iterations += report.iterations;
        if (body)
          suture_iterations = std::max(suture_iterations, body->take_peak_iterations());
        if (!report.converged || !(suture || lagrange || faces))
          return;
        const auto x = positions();
        if (contact || faces)
          model->surface_positions(surface, round_surface);
        const bool   touched = detect_faces(round_surface);
        const bool   changed = (contact && detect_contacts(round_surface)) || touched;
        const double gap     = lagrange ? needle->constraint_gap(x) : 0;
        if (!changed && gap <= np.coupling_tolerance)
          return;
        if (rounds == np.coupling_iterations)
          {
            std::ostringstream why;
            why << "after " << rounds << " rounds the contacts still changed, the pierce ties gape by " << gap
                << " m (Pierce points/Accurate/Coupling tolerance " << np.coupling_tolerance << " m)";
            report.converged = false;
            report.failure   = why.str();
            return;
          }
        if (lagrange)
          needle->update_multipliers(x);
      }
  }

  StepAttempt
  AccurateStitch::attempt(const double tn, const double dt)
  {
    step_time = tn;
    needle->save();
    model->save_state();
    if (suture)
      {
        saved_x       = suture->positions();
        saved_q       = suture->rotations();
        saved_grasped = grasped;
        hold_suture(tn);
      }
    if (contact)
      contact->save();
    if (faces)
      faces->save();
    if (needle->begin_step(tn, needle_pose(tn), x_surface))
      locate_loads();
    detect_faces(x_surface); // the last accepted state
    if (drag)
      drag->begin_step(&saved_x, dt);
    // Tissue and suture by one Newton iteration, the suture condensed onto the tissue's
    // points (the elements carrying the thread's pierce points follow within it). The
    // attempt's iterations count over all its rounds.
    step_iterations   = 0;
    suture_iterations = 0;
    if (body)
      body->take_peak_iterations();
    solve_rounds(tn);
    // with the phase field, the coupled solve alternates with the damage's until both settle
    if (report.converged)
      {
        const auto failure = model->minimise_alternately(
          [&] {
            solve_rounds(tn);
            return report.converged ? std::string() : report.failure;
          },
          damage_changes);
        if (!failure.empty())
          {
            report.converged = false;
            report.failure   = failure;
          }
      }
    if (!report.converged)
      {
        if (trace && report.failure.find("suture: ") != std::string::npos)
          trace->write(tn, dt);
        if (coupled_trace && solve_failed)
          coupled_trace->write(tn, dt);
        return {StepAttempt::Outcome::failed, report.failure};
      }
    // land the puncture within 4 % above the threshold: a step that overshoots is cut
    if (needle->touch_force(positions()) > 1.04 * np.puncture.threshold)
      return {StepAttempt::Outcome::too_long, "", step_iterations};
    // an adaptive step longer than the nominal one does not tie off: the tie-off (a
    // step's state, the motions stop there) lands as finely as with fixed steps
    if (dt > scene.time.step_size * (1 + 1e-9) && closure && closure->ties_off(tn, gaps(model->probe_displacements())))
      return {StepAttempt::Outcome::too_long, "", step_iterations};
    return {StepAttempt::Outcome::converged, "", step_iterations};
  }

  std::vector<double>
  AccurateStitch::gaps(const std::vector<Tensor<1, 3>> &probes) const
  {
    std::vector<double> g;
    const auto         &pairs = scene.closure.pairs;
    for (std::size_t k = 0; k < pairs.size(); ++k)
      {
        const auto &ua = probes[first_gap_probe + 2 * k], &ub = probes[first_gap_probe + 2 * k + 1];
        g.push_back(closure->gap(k, pairs[k].a + Eigen::Vector3d(ua[0], ua[1], ua[2]),
                                 pairs[k].b + Eigen::Vector3d(ub[0], ub[1], ub[2])));
      }
    return g;
  }

  double
  AccurateStitch::next_event(const double t) const
  {
    // the first event beyond t by more than round-off (a step that ended on one)
    const auto next = std::upper_bound(events.begin(), events.end(), t + 1e-12 * std::max(1.0, std::abs(t)));
    return next == events.end() ? std::numeric_limits<double>::infinity() : *next;
  }

  void
  AccurateStitch::undo()
  {
    model->restore_state();
    needle->restore();
    if (suture)
      {
        // as they were, bit for bit (set_node() would normalise the rotations again)
        for (std::size_t i = 0; i < saved_x.size(); ++i)
          suture->restore_node(i, saved_x[i], saved_q[i]);
        // a step that ended on the grasp and was halved ends before it: the end is
        // free again, and grasped where it is when a step reaches the grasp time
        if (grasped && !saved_grasped)
          {
            grasped = false;
            suture->constrain(suture->n_nodes() - 1, {});
          }
      }
    // the contacts the step's rounds detected go with it
    if (contact)
      contact->restore();
    if (faces)
      faces->restore();
    locate_loads();
  }

  void
  AccurateStitch::accept()
  {
    const auto x = positions();
    // the suture pulls on the swage: minus the support's reaction at its node 0
    rod::Vec6 swage_pull = rod::Vec6::Zero();
    if (suture)
      {
        // at the points of the converged iterate, the last the suture was brought to
        // equilibrium with
        const Eigen::VectorXd r = body->residual();
        swage_pull              = -r.head<6>();
        end_tension             = r.tail<6>().head<3>().norm(); // the grasper's reaction
        if (series)
          suture_reaction = r; // the series' hands' and ties' reactions
        stabilization_force     = drag ? drag->total_force(suture->positions()) : 0.0;
        suture->commit_contact();
      }
    load           = needle->needle_load(x, swage_pull);
    points_changed = needle->accept_step(x);
  }

  void
  AccurateStitch::advance()
  {
    if (points_changed)
      locate_loads();
    model->surface_positions(surface, x_surface);
    clearance->check(closure ? closure->motion_time(step_time) : step_time, needle_pose(step_time), x_surface,
                     surface.triangles);
    advance_series(step_time);
  }

  nlohmann::json
  AccurateStitch::step_statistics(const double dt, const unsigned cutbacks) const
  {
    nlohmann::json s{{"dt", dt},
                     {"newton_iterations", report.iterations},
                     {"suture_newton_iterations", suture_iterations},
                     {"cutbacks", cutbacks},
                     {"coupling_rounds", rounds},
                     {"residual_norms", report.residual_norms}};
    if (model->damage_field())
      s["damage"] = model->damage_record(damage_changes);
    return s;
  }

  nlohmann::json
  AccurateStitch::snapshot() const
  {
    nlohmann::json j{{"needle", needle->snapshot()},
                     {"grasped", grasped},
                     {"grasped_at", io::triple(grasped_at)},
                     {"load", {io::triple(load.first), io::triple(load.second)}},
                     {"end_tension", end_tension},
                     {"stabilization_force", stabilization_force}};
    if (suture)
      {
        std::vector<double> x, q;
        for (std::size_t i = 0; i < suture->n_nodes(); ++i)
          {
            const auto &r = suture->rotations()[i];
            x.insert(x.end(), {suture->positions()[i][0], suture->positions()[i][1], suture->positions()[i][2]});
            q.insert(q.end(), {r.w(), r.x(), r.y(), r.z()});
          }
        // the self-contact's friction history (rod/contact_friction.h)
        std::vector<double> anchors;
        for (const auto &a : suture->friction().anchors())
          a.write(anchors);
        j["suture"] = {{"x", x}, {"q", q}, {"friction_anchors", anchors}};
      }
    if (contact)
      j["contact"] = contact->snapshot();
    if (faces)
      j["faces"] = faces->snapshot();
    if (closure)
      j["closure"] = closure->snapshot();
    if (series)
      j["series"] = series->snapshot();
    return j;
  }

  nlohmann::json
  AccurateStitch::local_snapshot() const
  {
    return model->local_state();
  }

  void
  AccurateStitch::restore(const nlohmann::json &j, const nlohmann::json &local)
  {
    model->restore_local_state(local);
    needle->restore(j.at("needle"));
    if (suture)
      {
        const auto x = j.at("suture").at("x").get<std::vector<double>>(), q = j.at("suture").at("q").get<std::vector<double>>();
        if (x.size() != 3 * suture->n_nodes() || q.size() != 4 * suture->n_nodes())
          throw InputError("--restart: the checkpoint's suture has another number of nodes");
        // exactly as saved (the checkpoint keeps each double whole): normalised again, the
        // rotations would differ from the stopped run's in their last bit
        for (std::size_t i = 0; i < suture->n_nodes(); ++i)
          {
            const rod::Quat qi(q[4 * i], q[4 * i + 1], q[4 * i + 2], q[4 * i + 3]);
            if (!(std::abs(qi.norm() - 1) <= 1e-12))
              throw InputError("--restart: the checkpoint's suture rotation at node " +
                               std::to_string(i) + " is not a unit quaternion");
            suture->restore_node(i, rod::Vec3(x[3 * i], x[3 * i + 1], x[3 * i + 2]), qi);
          }
        const auto anchors = j.at("suture").value("friction_anchors", std::vector<double>{});
        if (anchors.size() % rod::FrictionAnchor::size != 0)
          throw InputError("--restart: the checkpoint's suture friction anchors are not whole records");
        std::vector<rod::FrictionAnchor> records;
        for (std::size_t i = 0; i < anchors.size(); i += rod::FrictionAnchor::size)
          {
            records.push_back(rod::FrictionAnchor::read(&anchors[i]));
            const auto &h = records.back();
            if (h.a + 1 >= suture->n_nodes() || h.b + 1 >= suture->n_nodes())
              throw InputError("--restart: a suture friction anchor names a segment the suture does not have");
          }
        suture->set_friction_anchors(std::move(records));
        grasped = j.at("grasped").get<bool>();
        grasped_at = io::triple_as<rod::Vec3>(j.at("grasped_at"));
        // the grasper's hold, as hold_suture() set it at the grasp
        if (grasped)
          {
            const bool r = scene.suture.last_end.fixes_rotation();
            suture->constrain(suture->n_nodes() - 1, {{true, true, true, r, r, r}});
          }
      }
    if (contact)
      contact->restore(j.at("contact"));
    if (faces)
      faces->restore(j.at("faces"));
    if (closure)
      closure->restore(j.at("closure"));
    if (series)
      {
        try
          {
            series->restore(j.at("series"));
          }
        catch (const std::invalid_argument &e)
          {
            throw InputError(std::string("--restart: ") + e.what());
          }
        apply_series();
      }
    load                = {io::triple_as<Tensor<1, 3>>(j.at("load").at(0)), io::triple_as<Tensor<1, 3>>(j.at("load").at(1))};
    end_tension         = j.at("end_tension").get<double>();
    stabilization_force = j.at("stabilization_force").get<double>();
    points_changed      = false;
    locate_loads();
    model->surface_positions(surface, x_surface);
  }
} // namespace suturesim::scene
