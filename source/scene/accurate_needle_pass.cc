#include <suturesim/collision/volume_penetration.h>
#include <suturesim/core/error.h>
#include <suturesim/coupling/accurate/condensed_suture.h>
#include <suturesim/coupling/accurate/suture_contact.h>
#include <suturesim/coupling/accurate/tissue_needle.h>
#include <suturesim/coupling/accurate/wound_contact.h>
#include <suturesim/rod/rod_integrator.h>
#include <suturesim/scene/accurate_needle_pass.h>
#include <suturesim/scene/wound_closure.h>
#include <suturesim/tissue/condensed_bodies.h>
#include <suturesim/tissue/point_load_list.h>

#include <deal.II/distributed/tria.h>

#include <algorithm>
#include <cstdio>
#include <iomanip>
#include <limits>
#include <optional>
#include <sstream>

namespace suturesim::scene
{
  using namespace dealii;


  void
  run_accurate_needle_pass(const AccurateNeedleInputs &in, io::Recorder &recorder, TimerOutput &timer,
                           ConditionalOStream &pcout)
  {
    MPI_Comm                                 comm = MPI_COMM_WORLD;
    parallel::distributed::Triangulation<3> tria(comm);
    mesh::MeshInfo                           mesh_info;
    {
      TimerOutput::Scope scope(timer, "mesh");
      mesh_info = mesh::create_mesh(*in.mesh, recorder.directory(), tria);
    }
    in.boundary_conditions->resolve(mesh_info);
    // the closure's gap probes join the tissue's own (after them)
    tissue::TissueParameters tissue_parameters = *in.tissue;
    const std::size_t        first_gap_probe   = tissue_parameters.probes.size();
    std::optional<ClosureMonitor> closure;
    if (in.closure)
      {
        closure.emplace(*in.closure);
        for (const auto &pair : in.closure->pairs)
          for (const auto &[side, X] : {std::pair{"a", pair.a}, std::pair{"b", pair.b}})
            tissue_parameters.probes.emplace_back("gap_" + pair.name + "_" + side, Point<3>(X[0], X[1], X[2]));
      }
    tissue::TissueModel model(comm, tissue_parameters, *in.material, *in.boundary_conditions, tria, timer);
    model.setup();

    const NeedleParameters &np      = *in.needle;
    const auto              surface = model.boundary_surface();
    coupling::TissueNeedleParameters parameters;
    parameters.puncture             = np.puncture;
    parameters.friction             = np.friction;
    parameters.transverse_stiffness = np.transverse_stiffness;
    parameters.spacing              = np.spacing;
    parameters.lagrange             = np.enforcement == "lagrange";
    parameters.normal_smoothing     = np.transverse_stiffness * np.coupling_tolerance;
    const bool lagrange             = parameters.lagrange;
    const tools::CurvedNeedle geometry = np.needle();
    coupling::TissueNeedle    needle(geometry, parameters, surface.triangles, surface.reference);
    const tools::Trajectory   path       = np.trajectory();
    const double              pull_start = np.motion == "pass" ? np.planned_pass().t_turn_end : 0;

    // the suture: straight from the swage along the needle's trailing direction, its
    // first node clamped to the swage's frame (which turns with the needle)
    std::optional<rod::RodModel> suture;
    const tools::Pose            pose0 = path.pose(0);
    rod::Quat                    frame0;
    bool                         grasped = false;
    rod::Vec3                    grasped_at;
    if (in.suture)
      {
        rod::RodParameters rp = *in.suture;
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
        needle.set_thread(&suture->positions(), lengths, &suture->rotations());
      }
    // the suture's nodes against the tissue's surface, outside the pierce points
    std::optional<coupling::SutureContact> contact;
    if (suture && in.suture->tissue_contact.enabled)
      {
        contact.emplace(coupling::SutureContactParameters{in.suture->tissue_contact.stiffness,
                                                          in.suture->section.radius, in.suture->tissue_contact.depth},
                        surface.triangles, surface.reference);
        contact->set_suture(&suture->positions());
      }
    // the incision's faces against each other (Closure/Face contact)
    std::optional<coupling::WoundContact> faces;
    if (in.closure && !in.closure->face_contact.empty())
      {
        const auto [a, b] = in.closure->face_contact_ids(mesh_info);
        faces.emplace(coupling::WoundContactParameters{in.closure->face_contact_stiffness,
                                                       in.closure->face_contact_margin},
                      surface.reference, surface.triangles, surface.ids, a, b);
      }
    // the tissue's point loads: the needle's touch and pierce points first (the needle
    // numbers them from 0), then the contacts
    tissue::PointLoadList loads;
    const auto            locate_loads = [&]() {
      std::vector<const tissue::PointLoads *> parts{&needle};
      if (contact)
        parts.push_back(&*contact);
      if (faces)
        parts.push_back(&*faces);
      loads.set(parts);
      if (faces)
        faces->set_offset(loads.offset(parts.size() - 1));
      model.set_point_loads(loads.points().empty() ? nullptr : &loads);
    };
    // moves the suture's held nodes to time t: the swage, and the far end once grasped
    // (from where it was then, by its keyframes, as in the realtime path)
    const auto hold_suture = [&](const double t) {
      const tools::Pose pose = path.pose(closure ? closure->motion_time(t) : t);
      suture->set_node(0, geometry.swage(pose), pose.orientation * pose0.orientation.inverse() * frame0);
      const auto       &end  = in.suture->last_end;
      const std::size_t last = suture->n_nodes() - 1;
      if (end.type == "free" || t < end.grasp_time)
        return;
      if (!grasped)
        {
          grasped    = true;
          grasped_at = suture->positions()[last];
          const bool r = end.fixes_rotation();
          suture->constrain(last, {{true, true, true, r, r, r}});
        }
      const double motion = closure ? closure->motion_time(t) : t;
      suture->set_node(last, end.position(std::max(motion, end.grasp_time), grasped_at), suture->rotations()[last]);
    };
    // The tissue is solved to a hundredth of the force a pierce tie carries at the
    // coupling tolerance: finer residuals move no point measurably, and a solve that
    // starts near equilibrium would otherwise chase its relative tolerance for half a
    // dozen iterations. The suture, whose equilibrium under each tissue iterate is part
    // of the tissue's residual (coupling/accurate/condensed_suture.h), to a tenth of
    // that: on the tissue's floor itself it left the coupled iteration stalled just
    // above it (the stitch's tightening: 2.5e-4 N after 25 iterations at k⊥ = 5e4 N/m,
    // floor 5e-5 N), and its iterations cost little.
    const double          force_floor = 0.01 * np.transverse_stiffness * np.coupling_tolerance;
    rod::NewtonParameters suture_newton;
    if (in.suture)
      {
        suture_newton                = in.suture->newton;
        suture_newton.absolute_floor = std::max(suture_newton.absolute_floor, 0.1 * force_floor);
        // the suture's equilibrium under each tissue iterate: slack thread crawls at
        // the step cap below (measured: up to a hundred iterations at the tightening),
        // and an iteration costs a fraction of a millisecond
        suture_newton.max_iterations = std::max(suture_newton.max_iterations, 500u);
        // a stiff pierce tie pulls the node it holds by millimetres on the first
        // iteration of a round, and the free tail would swing with it: half an element
        // and a quarter radian per iteration at most
        double shortest = std::numeric_limits<double>::infinity();
        for (const auto &r : suture->references())
          shortest = std::min(shortest, r.length);
        suture_newton.max_displacement = 0.5 * shortest;
        suture_newton.max_rotation     = 0.25;
      }
    std::vector<rod::Vec3> saved_x;
    std::vector<rod::Quat> saved_q;

    auto &summary      = recorder.summary();
    summary["scene"]      = in.scene_name;
    summary["scene_file"] = in.scene_file;
    summary["model"]      = "accurate";
    summary["mesh"]       = {{"description", mesh_info.description},
                             {"cells", tria.n_global_active_cells()},
                             {"dofs", model.n_dofs()},
                             {"element_degree", in.tissue->degree},
                             {"formulation", in.tissue->formulation},
                             {"surface_triangles", surface.triangles.size()}};
    if (suture)
      summary["suture"] = {{"elements", suture->n_elements()},
                           {"length", needle.curve_length() - geometry.length()},
                           {"coupling_tolerance", np.coupling_tolerance},
                           {"coupling", "one Newton iteration of tissue and suture, the suture condensed onto the tissue's points; rounds for carriers, contacts and multipliers"}};
    summary["metrics"]    = nlohmann::json::object();
    summary["steps"]      = nlohmann::json::array();
    pcout << "suturesim: scene '" << in.scene_name << "', " << mesh_info.description << ", "
          << tria.n_global_active_cells() << " cells, " << model.n_dofs() << " DoFs, needle "
          << np.shape << " R = " << np.radius << " m, " << np.enforcement << " pierce points"
          << (suture ? ", Cosserat suture of " + std::to_string(suture->n_elements()) + " elements" : "") << "\n";

    std::vector<std::string> columns{"time [s]"};
    for (const auto &d : in.boundary_conditions->dirichlet)
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(d.name + "_reaction_" + std::string(1, c) + " [N]");
    for (std::size_t p = 0; p < first_gap_probe; ++p)
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(model.probes()[p].first + "_displacement_" + std::string(1, c) + " [m]");
    if (closure)
      for (const auto &pair : in.closure->pairs)
        columns.push_back("gap_" + pair.name + " [m]");
    np.add_columns(columns);
    if (suture)
      {
        for (const std::string end : {"swage", "free_end"})
          columns.push_back("suture_tension_" + end + " [N]");
        columns.push_back("suture_stabilization_force [N]");
        columns.push_back("suture_tissue_contact_force [N]");
        columns.push_back("suture_tissue_contacts [1]");
      }
    if (faces)
      {
        columns.push_back("wound_face_contact_force [N]");
        columns.push_back("wound_face_contacts [1]");
      }
    recorder.set_columns(columns);

    const auto positions = [&]() {
      std::vector<Point<3>> x(needle.points().size());
      for (std::size_t k = 0; k < x.size(); ++k)
        x[k] = model.point_position(k);
      return x;
    };
    // new contacts for the suture as it is against the tissue's surface at @p at (its
    // vertices' current positions); true when the set changed (the tissue then has new
    // loads). Left out: the nodes a stitch's pierce points draw into the tissue and the
    // nodes a support holds.
    const auto detect_contacts = [&](const Eigen::Matrix3Xd &at) {
      std::vector<char> skip = needle.thread_nodes_in_tracts();
      skip.front()           = 1;
      skip.back()            = skip.back() || grasped;
      const bool changed     = contact->detect(at, suture->positions(), skip);
      if (changed)
        locate_loads();
      return changed;
    };
    double      peak_pull = 0, last_output = -1, end_tension = 0;
    // Suture/Stabilization: a drag c v per unit length, c ℓ_i (x_i − x_i,n)/Δt on node i
    // (ℓ_i half of each element beside it), with its Jacobian c ℓ_i/Δt I. Its total on
    // the converged state of the last step is recorded.
    std::vector<double> node_length;
    double              step_length = 0, stabilization_force = 0;
    if (suture)
      {
        node_length.assign(suture->positions().size(), 0.0);
        for (std::size_t e = 0; e < suture->references().size(); ++e)
          {
            node_length[e] += 0.5 * suture->references()[e].length;
            node_length[e + 1] += 0.5 * suture->references()[e].length;
          }
      }
    // the terms the pass adds at the suture's nodes: the stabilization and the contact
    const bool            stabilized = suture && in.suture->stabilization > 0;
    const rod::NodalTerms node_terms = [&](const std::size_t i, const rod::Vec3 &xi, const rod::Quat &,
                                           rod::Vec6 &r, rod::Mat6 &J) {
      if (stabilized)
        {
          const double c = in.suture->stabilization * node_length[i] / step_length;
          r.head<3>() += c * (xi - saved_x[i]);
          J.topLeftCorner<3, 3>() += c * rod::Mat3::Identity();
        }
      if (contact)
        contact->add_node_terms(i, xi, r, J);
    };
    const rod::NodalTerms *suture_terms = stabilized || contact ? &node_terms : nullptr;
    // the suture, solved with the tissue in one Newton iteration
    std::optional<coupling::CondensedSuture> body;
    if (suture)
      body.emplace(*suture, suture_newton, needle, contact ? &*contact : nullptr, loads, suture_terms);
    // what is solved with the tissue: the suture, the wound's faces, or both
    std::vector<tissue::CondensedBody *> parts;
    if (body)
      parts.push_back(&*body);
    if (faces)
      parts.push_back(&*faces);
    tissue::CondensedBodies  both(parts);
    tissue::CondensedBody    *coupled = parts.empty() ? nullptr : parts.size() == 1 ? parts.front() : &both;
    // the faces' loaded pairs for the surface at @p at; true when they changed
    const auto detect_faces = [&](const Eigen::Matrix3Xd &at) {
      const bool changed = faces && faces->detect(at);
      if (changed)
        locate_loads();
      return changed;
    };
    Eigen::Matrix3Xd round_surface; // the surface after a round's solve
    unsigned    output_index = 0;
    std::string last_file;
    // the needle's load of the converged state is taken before the step is accepted (a
    // puncture changes the set of points)
    std::pair<Tensor<1, 3>, Tensor<1, 3>> load;
    const auto  record = [&](const double t, nlohmann::json statistics) {
      std::vector<double> row{t};
      auto               &metrics = summary["metrics"];
      for (const auto &r : model.reactions(t))
        {
          for (unsigned d = 0; d < 3; ++d)
            row.push_back(r.force[d]);
          metrics["reaction_force"][r.boundary] = {r.force[0], r.force[1], r.force[2]};
        }
      const auto probes = model.probe_displacements();
      for (std::size_t p = 0; p < first_gap_probe; ++p)
        for (unsigned d = 0; d < 3; ++d)
          {
            row.push_back(probes[p][d]);
            metrics[model.probes()[p].first + "_displacement_" + std::string(1, char('x' + d))] = probes[p][d];
          }
      if (closure)
        {
          // the gaps, charged to the tension the grasper on the far end feels (else
          // the needle's pull), as in the realtime path
          std::vector<double> gaps;
          for (std::size_t k = 0; k < in.closure->pairs.size(); ++k)
            {
              const auto  &pair = in.closure->pairs[k];
              const auto  &ua = probes[first_gap_probe + 2 * k], &ub = probes[first_gap_probe + 2 * k + 1];
              gaps.push_back(closure->gap(k, pair.a + Eigen::Vector3d(ua[0], ua[1], ua[2]),
                                          pair.b + Eigen::Vector3d(ub[0], ub[1], ub[2])));
              row.push_back(gaps.back());
            }
          closure->update(t, gaps, grasped ? end_tension : load.first.norm());
        }
      const auto &[force, torque] = load;
      for (unsigned d = 0; d < 3; ++d)
        row.push_back(force[d]);
      for (unsigned d = 0; d < 3; ++d)
        row.push_back(torque[d]);
      for (unsigned d = 0; d < 3; ++d)
        row.push_back(needle.pose().position[d]);
      if (t >= pull_start)
        peak_pull = std::max(peak_pull, force.norm());
      const auto &points = needle.pierce_points();
      for (unsigned k = 0; k < np.recorded; ++k)
        if (k < points.size())
          for (const double v : {points[k].slipping ? 2.0 : 1.0, points[k].anchor, points[k].slip_speed,
                                 points[k].normal, points[k].friction})
            row.push_back(v);
        else
          for (int j = 0; j < 5; ++j)
            row.push_back(0);
      if (suture)
        {
          const auto states = suture->element_states();
          row.push_back(states.front().N[0]);
          row.push_back(states.back().N[0]);
          row.push_back(stabilization_force);
          row.push_back(contact ? contact->total_force(suture->positions()) : 0.0);
          row.push_back(contact ? contact->contacts().size() : 0);
        }
      if (faces)
        {
          row.push_back(faces->total_force());
          row.push_back(faces->n_touching());
        }
      recorder.add_row(row);
      const auto &time = *in.time;
      if (time.output_interval <= 0 || last_output < 0 ||
          t >= last_output + time.output_interval * (1 - 1e-9) || t >= time.end_time * (1 - 1e-12))
        {
          if (suture)
            {
              const io::PolylineData data = rod::polyline_data(*suture, in.suture->section.radius);
              char name[32];
              std::snprintf(name, sizeof(name), "suture_%05u.vtu", output_index);
              if (recorder.is_root())
                io::write_polyline_vtu(recorder.directory() + "/" + name, data, t);
              recorder.add_vtu("suture", t, name);
            }
          last_file = model.write_vtu(recorder.directory(), output_index++, t);
          recorder.add_vtu("tissue", t, last_file);
          last_output = t;
        }
      statistics["time"] = t;
      summary["steps"].push_back(statistics);
    };

    const auto fail = [&](const double t, const std::string &reason) {
      summary["metrics"]["simulated_time"] = last_output; // the last converged state's
      std::ostringstream s;
      s << "Newton failed at t = " << t << " s after " << in.time->max_cutbacks
        << " step halvings: " << reason << "; last converged state t = " << last_output << " s"
        << (last_file.empty() ? "" : " in " + recorder.directory() + "/" + last_file);
      throw SolverError(s.str());
    };

    // equilibrium at t = 0, the needle away
    needle.begin_step(0, path.pose(0), surface.reference);
    {
      const auto report = model.solve_static(0, force_floor);
      if (!report.converged)
        fail(0, report.failure);
      record(0, {{"newton_iterations", report.iterations}});
    }
    Eigen::Matrix3Xd x_surface;
    model.surface_positions(surface, x_surface);

    const double T  = in.time->end_time, h = in.time->step_size;
    double       t  = 0, dt = h;
    unsigned     cutbacks = 0, steps = 0, total_iterations = 0;
    while (t < T * (1 - 1e-12))
      {
        const double step_dt = std::min(dt, T - t), tn = t + step_dt;
        needle.save();
        model.save_state();
        if (suture)
          {
            saved_x = suture->positions();
            saved_q = suture->rotations();
            hold_suture(tn);
          }
        if (needle.begin_step(tn, path.pose(closure ? closure->motion_time(tn) : tn), x_surface))
          locate_loads();
        detect_faces(x_surface); // the last accepted state
        // Tissue and suture by one Newton iteration, the suture condensed onto the
        // tissue's points (coupling/accurate/condensed_suture.h; the elements carrying
        // the thread's pierce points follow within it). Rounds only follow what a solve
        // cannot change within itself: the contacts and the Lagrange multipliers; a
        // round that changes neither (and leaves no tie gaping) ends the step.
        step_length = step_dt;
        tissue::NewtonReport report;
        unsigned             rounds = 0;
        for (rounds = 1;; ++rounds)
          {
            report = coupled ? model.solve_coupled(tn, force_floor, *coupled) : model.solve_static(tn, force_floor);
            if (!report.converged || !(suture || lagrange || faces))
              break;
            const auto x = positions();
            if (contact || faces)
              model.surface_positions(surface, round_surface);
            const bool   touched = detect_faces(round_surface);
            const bool   changed = (contact && detect_contacts(round_surface)) || touched;
            const double gap     = lagrange ? needle.constraint_gap(x) : 0;
            if (!changed && gap <= np.coupling_tolerance)
              break;
            if (rounds == np.coupling_iterations)
              {
                std::ostringstream why;
                why << "after " << rounds << " rounds the contacts still changed, the pierce ties "
                    << "gape by " << gap << " m (Pierce points/Coupling tolerance " << np.coupling_tolerance
                    << " m)";
                report.converged = false;
                report.failure   = why.str();
                break;
              }
            if (lagrange)
              needle.update_multipliers(x);
          }
        // back to the state before the step, which is then halved
        const auto halve = [&]() {
          model.restore_state();
          needle.restore();
          if (suture)
            for (std::size_t i = 0; i < saved_x.size(); ++i)
              suture->set_node(i, saved_x[i], saved_q[i]);
          locate_loads();
          ++cutbacks;
          dt = 0.5 * step_dt;
        };
        if (!report.converged)
          {
            if (cutbacks == in.time->max_cutbacks)
              fail(tn, report.failure);
            pcout << "t = " << tn << " s: step of " << step_dt << " s halved: " << report.failure << "\n";
            halve();
            continue;
          }
        const auto x = positions();
        // land the puncture within 4 % above the threshold: cut a step that overshoots
        if (needle.touch_force(x) > 1.04 * np.puncture.threshold && cutbacks < in.time->max_cutbacks + 8)
          {
            halve();
            continue;
          }
        // the suture pulls on the swage: minus the support's reaction at its node 0
        rod::Vec6 swage_pull = rod::Vec6::Zero();
        if (suture)
          {
            // at the points of the converged iterate, the last the suture was brought
            // to equilibrium with
            const Eigen::VectorXd r = body->residual();
            swage_pull  = -r.head<6>();
            end_tension = r.tail<6>().head<3>().norm(); // the grasper's reaction
            // the drag's total magnitude over the free nodes: an upper bound of what it
            // adds to any force recorded
            stabilization_force = 0;
            if (stabilized)
              for (std::size_t i = 1; i + 1 < node_length.size(); ++i)
                stabilization_force += in.suture->stabilization * node_length[i] / step_dt *
                                       (suture->positions()[i] - saved_x[i]).norm();
          }
        load = needle.needle_load(x, swage_pull);
        const bool changed = needle.accept_step(x);
        t                  = tn;
        ++steps;
        total_iterations += report.iterations;
        record(t, {{"dt", step_dt},
                   {"newton_iterations", report.iterations},
                   {"cutbacks", cutbacks},
                   {"coupling_rounds", rounds},
                   {"residual_norms", report.residual_norms}});
        if (changed)
          locate_loads();
        model.surface_positions(surface, x_surface);
        // one line a step (as ASPECT): a run that slows down shows where and why
        pcout << "step " << steps << "  t = " << std::setprecision(5) << t << " s  dt = " << step_dt
              << " s  Newton " << report.iterations << " it  rounds " << rounds << "  pierce points "
              << needle.pierce_points().size() << "  contacts " << (contact ? contact->contacts().size() : 0)
              << std::endl;
        cutbacks = 0;
        dt       = std::min(2 * dt, h);
      }

    np.write_summary(summary, needle.all_events(), peak_pull);
    summary["metrics"]["simulated_time"] = t;
    if (suture)
      {
        // as in the realtime path: no suture node may end inside the tissue, deeper than
        // its radius below the surface, but those a stitch carries between two pierce
        // points (the FE tissue known by its deformed boundary: a winding-number test)
        Eigen::Matrix3Xd nodes(3, suture->positions().size());
        for (std::size_t i = 0; i < suture->positions().size(); ++i)
          nodes.col(i) = suture->positions()[i];
        const auto split = collision::split_by_tracts(
          collision::surface_penetration(x_surface, surface.triangles, nodes, in.suture->section.radius),
          needle.thread_nodes_in_tracts());
        auto &metrics                          = summary["metrics"];
        metrics["suture_nodes_inside_tissue"] = split.outside_tracts;
        metrics["suture_penetration_depth"]   = split.depth;
        metrics["suture_nodes_in_tracts"]     = split.in_tracts;
      }
    if (closure)
      closure->write(summary["metrics"]);
    summary["solver"]["steps"]                   = steps;
    summary["solver"]["newton_iterations_total"] = total_iterations;
  }
} // namespace suturesim::scene
