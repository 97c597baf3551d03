#include <suturesim/collision/proximity.h>
#include <suturesim/collision/volume_penetration.h>
#include <suturesim/realtime/angle_springs.h>
#include <suturesim/realtime/home_springs.h>
#include <suturesim/realtime/self_collision.h>
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/world.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

namespace suturesim::realtime
{
  World::World(WorldSetup setup)
    : mesh(setup.mesh)
    , tissue_model(std::move(setup.tissue))
    , suture_model(std::move(setup.suture))
    , time_integrator(std::move(setup.integrator))
    , contact_stiffness(setup.contact_stiffness)
    , refuse_above_limit(setup.refuse_above_limit)
    , h(1 / setup.rate)
    , n_substeps(setup.substeps)
  {
    if (!time_integrator)
      throw std::invalid_argument("realtime world without an integrator");
    if (!(setup.rate > 0) || n_substeps == 0)
      throw std::invalid_argument("realtime world: rate and substeps must be positive");
    if (mesh != nullptr && tissue_model)
      tissue_model->build(sys, *mesh, mesh::extract_boundary(*mesh), setup.material,
                          time_integrator->position_based());
    else
      tissue_model.reset();
    if (time_integrator->projects_tissue())
      for (const auto &i : sys.interactions)
        if (!i->projectable())
          throw ParameterError("Integrator", "the tissue's " + i->name() +
                                               " have no XPBD projection: use 'vbd' or a force-based integrator");
    tissue_interactions          = sys.interactions.size();
    sys.first_suture_interaction = tissue_interactions;
    if (suture_model)
      suture_model->build(sys, setup.suture_geometry);
    sys.gravity = setup.gravity;

    if (setup.contact_load && !(suture_model && tissue_model && setup.contact))
      throw ParameterError("Contact load",
                           "needs a suture in contact with the tissue (a scene with both, and Contact = true)");
    if (suture_model && tissue_model && setup.contact)
      {
        auto c = std::make_unique<SurfaceContact>(
          sys, tissue_model->surface(),
          SurfaceContact::Parameters{setup.contact_stiffness, setup.suture_geometry.radius,
                                     setup.contact_depth, time_integrator->position_based()},
          sys.suture, "suture-tissue contact");
        contact = c.get();
        if (setup.contact_load)
          {
            if (!suture_model->geometric() || time_integrator->position_based())
              throw ParameterError("Contact load", "the thread's pull into the surface loads the tissue for a "
                                                   "thread moved geometrically (Suture model = ftl) under a "
                                                   "force-based integrator");
            contact->carry_thread(sys, *suture_model);
          }
        sys.contacts.push_back(std::move(c));
      }
    if (suture_model)
      if (auto self = make_self_collision(setup.self_collision, setup.self_collision_parameters,
                                          {sys.suture, setup.suture_geometry.radius,
                                           suture_model->link_length(), &sys.nodes.x}))
        {
          self_collision_set = self.get();
          sys.contacts.push_back(std::move(self));
        }
  }

  std::vector<std::uint32_t>
  World::nodes_of_vertices(const std::vector<std::uint32_t> &vertices) const
  {
    std::vector<std::uint32_t> result;
    if (tissue_model)
      for (const auto v : vertices)
        if (tissue_model->node(v) >= 0)
          result.push_back(tissue_model->node(v));
    return result;
  }

  void
  World::fix_vertices(const std::vector<std::uint32_t> &vertices)
  {
    for (const auto i : nodes_of_vertices(vertices))
      {
        sys.nodes.set_held(i, Nodes::boundary, true);
        sys.nodes.target.col(i) = sys.nodes.reference.col(i);
      }
  }

  std::vector<std::uint32_t>
  World::prescribe_vertices(const std::vector<std::uint32_t> &vertices, Motion motion)
  {
    Prescribed p{nodes_of_vertices(vertices), std::move(motion)};
    for (const auto i : p.nodes)
      sys.nodes.set_held(i, Nodes::boundary, true);
    p.motion(0, p.nodes, sys.nodes.reference, sys.nodes.target);
    for (const auto i : p.nodes)
      sys.nodes.x.col(i) = sys.nodes.target.col(i);
    prescribed.push_back(std::move(p));
    return prescribed.back().nodes;
  }

  std::size_t
  World::add_tool(const std::string &name, const std::vector<std::uint32_t> &nodes,
                  const ToolPose &initial)
  {
    tools.push_back(Tool{name, {}, Matrix3Xd(), initial});
    hold(tools.back(), nodes, initial);
    return tools.size() - 1;
  }

  void
  World::hold(Tool &tool, const std::vector<std::uint32_t> &nodes, const ToolPose &pose)
  {
    const Eigen::Matrix3d R = pose.orientation.toRotationMatrix();
    tool.nodes              = nodes;
    tool.offsets.resize(3, nodes.size());
    tool.pose = pose;
    for (std::size_t k = 0; k < nodes.size(); ++k)
      {
        if (nodes[k] >= sys.nodes.size())
          throw std::invalid_argument("tool '" + tool.name + "' holds a node that does not exist");
        tool.offsets.col(k) = R.transpose() * (sys.nodes.x.col(nodes[k]) - pose.position);
        sys.nodes.set_held(nodes[k], Nodes::boundary, true);
        sys.nodes.target.col(nodes[k]) = sys.nodes.x.col(nodes[k]);
      }
  }

  void
  World::grasp(const std::size_t tool, const std::vector<std::uint32_t> &nodes, const ToolPose &pose)
  {
    if (tool >= tools.size())
      throw std::invalid_argument("realtime world: grasp by a tool that does not exist");
    hold(tools[tool], nodes, pose);
    if (initialized)
      start_poses[tool] = pose;
    for (const auto i : nodes)
      tools_on_suture = tools_on_suture && i >= sys.suture.begin && i < sys.suture.end;
  }

  std::size_t
  World::add_needle(const tools::CurvedNeedle &geometry, const NeedleCouplingParameters &parameters,
                    const ToolPose &initial, const bool hold_suture)
  {
    if (needle_coupling != nullptr)
      throw std::invalid_argument("realtime world: one needle only");
    if (!tissue_model)
      throw std::invalid_argument("realtime world: a needle needs tissue to pierce");
    NeedleCouplingParameters p = parameters;
    p.project                  = time_integrator->position_based();
    p.geometric_suture         = suture_model && suture_model->geometric();
    if (p.pierce_model == "automatic")
      p.pierce_model = PierceModel::automatic(suture_model.get(), p.project);
    auto coupling = std::make_unique<NeedleCoupling>(sys, tissue_model->surface(), geometry, p, suture_model.get());
    coupling->set_pose(initial, 0);
    // seed 002: a surface model subdivides where the needle touches it; the contact's
    // tree follows the new triangles (the needle's own puncture tree is rebuilt by it)
    coupling->subdivide_at_touch([this](const std::uint32_t triangle, const Vector3d &weights) {
      const std::int64_t node = tissue_model->subdivide(sys, triangle, weights);
      if (node >= 0)
        {
          if (contact != nullptr)
            contact->surface_changed(sys.nodes.x);
          for (auto *probe : probe_contacts)
            probe->surface_changed(sys.nodes.x);
          // the patch's springs (up to 4 k_mesh on a node with a smaller share of the
          // mass) lower an explicit step's limit: estimated again, and warned of
          assess_stability(false);
        }
      return node;
    });
    needle_coupling = coupling.get();
    sys.contacts.push_back(std::move(coupling));
    if (contact != nullptr)
      contact->exempt(&needle_coupling->suture_inside());
    std::vector<std::uint32_t> held;
    if (hold_suture && suture_model)
      {
        const double tolerance = 1e-9 * sys.length_scale();
        if ((sys.nodes.x.col(sys.suture.begin) - geometry.swage(initial)).norm() > tolerance)
          throw std::invalid_argument("realtime world: the suture does not start at the needle's swage");
        held = {sys.suture.begin, sys.suture.begin + 1};
        if (geometry.straight()) // pinned at the middle, not clamped
          held.pop_back();
      }
    needle_tool = add_tool("needle", held, initial);
    return needle_tool;
  }

  void
  World::add_access(const std::vector<Vector3d> &points, const double stiffness)
  {
    if (access_set != nullptr)
      throw std::invalid_argument("realtime world: access points are added once");
    if (!suture_model)
      throw std::invalid_argument("realtime world: access points need a suture");
    if (std::isinf(stiffness) && !time_integrator->position_based())
      throw std::invalid_argument("realtime world: rigid access points need a position-based integrator");
    const double k = stiffness > 0 ? stiffness : suture_model->link_stiffness(sys, 0);
    auto set = std::make_unique<NodeAccess>(sys.suture, suture_model->link_length(), k);
    accesses_on_link.assign(sys.suture.size() - 1, 0);
    // one link carries one access, the others keep their springs: counted, so two
    // accesses passing over the same link give it back only when both have left
    const auto hold = [this](const std::uint32_t link, const bool on) {
      unsigned &n = accesses_on_link[link];
      n           = on ? n + 1 : n - 1;
      if (n == (on ? 1U : 0U))
        suture_model->leave_out_link(sys, link, on);
    };
    for (const auto &b : points)
      {
        std::uint32_t nearest  = 0;
        double        distance = std::numeric_limits<double>::infinity();
        for (std::uint32_t i = 0; i + 1 < sys.suture.size(); ++i)
          {
            const Vector3d p = sys.nodes.x.col(sys.suture.begin + i), d = sys.nodes.x.col(sys.suture.begin + i + 1) - p;
            const double   t = std::clamp((b - p).dot(d) / d.squaredNorm(), 0.0, 1.0);
            if (const double r = (p + t * d - b).norm(); r < distance)
              distance = r, nearest = i;
          }
        set->add(b, nearest);
        hold(nearest, true);
      }
    set->on_move([hold](const std::uint32_t from, const std::uint32_t to) {
      hold(from, false);
      hold(to, true);
    });
    access_set = set.get();
    sys.contacts.push_back(std::move(set));
  }

  std::size_t
  World::add_probe(const std::string &name, const Vector3d &tip, const Vector3d &axis, const double length,
                   const double radius, const double stiffness)
  {
    if (!tissue_model)
      throw std::invalid_argument("realtime world: probe '" + name + "' needs tissue to press on");
    if (!(length > 0) || !(radius > 0) || !(stiffness > 0) || !(axis.norm() > 0) || !std::isfinite(length + radius))
      throw std::invalid_argument("realtime world: probe '" + name +
                                  "' needs a positive length, radius and stiffness and an axis");
    // nodes at most a radius apart: their spheres of radius r leave no gap on the rod's
    // surface wider than 0.13 r (at the midpoint, √(r² − (r/2)²) = 0.87 r)
    const auto          n     = static_cast<std::uint32_t>(std::max(2.0, std::ceil(length / radius) + 1));
    const std::uint32_t first = sys.nodes.size();
    const Vector3d      along = axis.normalized() * (length / (n - 1));
    std::vector<std::uint32_t> held;
    for (std::uint32_t k = 0; k < n; ++k)
      {
        // a nominal mass: the tool holds the nodes, so it moves none of them
        sys.nodes.add(tip + k * along, 1e-6, 0);
        held.push_back(first + k);
      }
    // every node pushed out, however deep the tool went in: a probe never pierces
    auto c = std::make_unique<SurfaceContact>(
      sys, tissue_model->surface(),
      SurfaceContact::Parameters{stiffness, radius, length + radius, time_integrator->position_based(), true},
      NodeRange{first, first + n}, name + "-tissue contact");
    probe_contacts.push_back(c.get());
    sys.contacts.push_back(std::move(c));
    probe_stiffness = std::max(probe_stiffness, stiffness);
    ToolPose pose;
    pose.position = tip;
    return add_tool(name, held, pose);
  }

  void
  World::add_wound_face_contact(const std::vector<std::uint32_t> &face_a, const std::vector<mesh::Triangle> &face_b,
                                const double stiffness, const double margin)
  {
    if (!tissue_model)
      throw std::invalid_argument("realtime world: the wound's face contact needs tissue");
    auto c = std::make_unique<WoundFaceContact>(sys, face_a, face_b, stiffness, margin,
                                                time_integrator->position_based());
    face_contact = c.get();
    sys.contacts.push_back(std::move(c));
  }

  void
  World::set_loads(Loads l)
  {
    loads = std::move(l);
  }

  void
  World::initialize()
  {
    time_integrator->setup(sys);
    sys.finalize();

    assess_stability(true);

    good_x = sys.nodes.x;
    good_v = sys.nodes.v;
    forces.assign(tools.size(), ToolForce());
    start_poses.clear();
    for (const auto &tool : tools)
      start_poses.push_back(tool.pose);
    transient_nodes.reserve(sys.nodes.size());
    tools_on_suture = true;
    for (const auto &tool : tools)
      for (const auto i : tool.nodes)
        tools_on_suture = tools_on_suture && i >= sys.suture.begin && i < sys.suture.end;
    initialized = true;
  }

  std::size_t
  World::cut_tissue(const std::function<bool(const Vector3d &, const Vector3d &)> &crosses)
  {
    const Matrix3Xd &X   = sys.nodes.reference;
    std::size_t      cut = 0;
    for (std::size_t k = 0; k < tissue_interactions; ++k)
      if (auto *springs = dynamic_cast<SpringSet *>(sys.interactions[k].get()))
        cut += springs->remove_if(
          [&](const std::uint32_t i, const std::uint32_t j) { return crosses(X.col(i), X.col(j)); });
    // fewer springs cannot lower an explicit step's limit, but the estimate and its
    // warning stay those of the tissue as it is
    if (cut > 0)
      assess_stability(false);
    return cut;
  }

  std::string
  World::uncuttable_tissue() const
  {
    for (std::size_t k = 0; k < tissue_interactions; ++k)
      {
        const Interaction *i = sys.interactions[k].get();
        if (dynamic_cast<const SpringSet *>(i) == nullptr && dynamic_cast<const HomeSprings *>(i) == nullptr &&
            dynamic_cast<const AngleSprings *>(i) == nullptr)
          return i->name();
      }
    return "";
  }

  void
  World::assess_stability(const bool at_setup)
  {
    // The limit of a force-based integrator, with the penalty contact stiffness on every
    // suture node as if it touched (contacts appear only later, and a stiff penalty is
    // as able to make an explicit step unstable as a stiff spring).
    if (!time_integrator->position_based())
      {
        // a probe's penalty acts on the tissue's surface nodes it presses, once per face
        // it touches: on each node as if every face around it were pressed (an estimate:
        // two of the probe's nodes may press one face)
        auto potential_contact = std::make_unique<HomeSprings>();
        if (contact != nullptr && contact_stiffness > 0)
          for (auto i = sys.suture.begin; i < sys.suture.end; ++i)
            potential_contact->add(i, sys.nodes.x.col(i), contact_stiffness);
        if (probe_stiffness > 0)
          {
            std::vector<unsigned> faces(sys.nodes.size(), 0);
            for (const auto &t : tissue_model->surface())
              for (const auto i : t)
                ++faces[i];
            for (std::uint32_t i = 0; i < sys.nodes.size(); ++i)
              if (faces[i] > 0)
                potential_contact->add(i, sys.nodes.x.col(i), faces[i] * probe_stiffness);
          }
        if (face_contact != nullptr)
          {
            std::vector<double> k(sys.nodes.size(), 0);
            face_contact->add_potential_stiffness(k);
            for (std::uint32_t i = 0; i < sys.nodes.size(); ++i)
              if (k[i] > 0)
                potential_contact->add(i, sys.nodes.x.col(i), k[i]);
          }
        const bool potential = potential_contact->size() > 0;
        if (potential)
          sys.interactions.push_back(std::move(potential_contact));
        dt_limit = time_integrator->stability_limit(sys);
        if (potential)
          sys.interactions.pop_back();
        limit_text = time_integrator->limit_description() +
                     (potential ? " (contact stiffness included)" : "");
      }
    else
      {
        dt_limit   = std::numeric_limits<double>::infinity();
        limit_text = "none: position-based integration (xpbd, vbd) is unconditionally stable";
      }

    std::ostringstream cause;
    if (dt() > dt_limit)
      {
        std::ostringstream w;
        w << "dt = " << dt() << " s is above the stability limit dt_crit = " << dt_limit
          << " s (" << limit_text << ")";
        warning_text = w.str();
        if (refuse_above_limit && at_setup)
          throw ParameterError("Substeps", warning_text + "; use more substeps");
        cause << warning_text;
      }
    else if (time_integrator->position_based())
      cause << "a constraint or contact stiffer than " << time_integrator->iterations()
            << (time_integrator->first_constraint_interaction(sys) > 0 ? " vbd" : " XPBD") << " iterations at dt = " << dt()
            << " s resolve";
    else
      cause << "a stiffness above the one estimated at set-up (large deformation or contact); "
               "dt = "
            << dt() << " s, dt_crit = " << dt_limit << " s";
    guard.setup(sys, h, cause.str());

  }

  const std::vector<ToolForce> &
  World::step(const std::vector<ToolPose> &poses)
  {
    if (!initialized)
      throw std::logic_error("World::step before initialize()");
    if (poses.size() != tools.size())
      throw std::invalid_argument("World::step: one pose per tool");
    using clock     = std::chrono::steady_clock;
    Nodes       &n  = sys.nodes;
    const double dt = h / n_substeps;
    sys.detection_time = clock::duration::zero();
    step_phases        = StepPhases();
    for (unsigned k = 0; k < n_substeps; ++k)
      {
        const auto   coupling_start = clock::now();
        const double tau = double(k + 1) / n_substeps;
        const double tk  = t + (k + 1) * dt;
        for (std::size_t j = 0; j < tools.size(); ++j)
          {
            ToolPose   pose      = tools::interpolate(start_poses[j], poses[j], tau);
            const bool is_needle = needle_coupling != nullptr && j == needle_tool;
            if (is_needle) // the needle where it lies, or where the jaws hold it
              pose = free_body ? free_body->pose() : ToolPose{pose.apply(grip.position), pose.orientation * grip.orientation};
            const Eigen::Matrix3d R = pose.orientation.toRotationMatrix();
            for (std::size_t i = 0; i < tools[j].nodes.size(); ++i)
              n.target.col(tools[j].nodes[i]) = pose.position + R * tools[j].offsets.col(i);
            if (is_needle)
              needle_coupling->set_pose(pose, tk);
          }
        for (auto &p : prescribed)
          p.motion(tk, p.nodes, n.reference, n.target);
        if (loads)
          {
            n.external.setZero();
            loads(tk, n.external);
          }
        if (suture_model)
          suture_model->before_step(sys, dt);
        const auto solve_start = clock::now();
        step_phases.coupling += solve_start - coupling_start;
        time_integrator->step(sys, dt);

        // collision constraints live for one step (seed 002)
        const auto collision_start = clock::now();
        for (const auto i : transient_nodes)
          n.set_held(i, Nodes::transient, false);
        transient_nodes.clear();
        for (const auto &c : sys.contacts)
          c->after_step(n);
        for (auto i = sys.suture.begin; i < sys.suture.end; ++i)
          if (n.held[i] & Nodes::transient)
            transient_nodes.push_back(i);
        step_phases.collision += clock::now() - collision_start;
        if (free_body)
          {
            const auto free_start = clock::now();
            move_free_needle(dt);
            step_phases.coupling += clock::now() - free_start;
          }
      }
    step_phases.collision += sys.detection_time;

    const std::string diagnosis = guard.check(sys, n_steps + 1);
    if (!diagnosis.empty())
      {
        n.x = good_x;
        n.v = good_v;
        throw DivergenceError(diagnosis, n_steps + 1);
      }
    t += h;
    ++n_steps;
    good_x = n.x;
    good_v = n.v;
    for (std::size_t j = 0; j < tools.size(); ++j)
      {
        start_poses[j] = poses[j];
        tools[j].pose  = poses[j];
      }

    const auto forces_start = clock::now();
    if (!tools.empty())
      {
        // Tools holding suture nodes only feel the suture's own interactions and the
        // contacts: the tissue's springs and volumes (most of the work) are skipped.
        evaluate_forces(tools_on_suture ? tissue_interactions : 0);
        for (std::size_t j = 0; j < tools.size(); ++j) // open jaws feel nothing
          forces[j] = free_body && j == needle_tool ? ToolForce() : load_on_tool(j, poses[j].position, h / n_substeps);
      }
    step_phases.coupling += clock::now() - forces_start;
    return forces;
  }

  ToolForce
  World::load_on_tool(const std::size_t j, const Vector3d &origin, const double dt, const bool free) const
  {
    const Nodes &n = sys.nodes;
    ToolForce    f;
    for (const auto i : tools[j].nodes)
      {
        Vector3d fi;
        if (!(suture_model && suture_model->holding_force(sys, i, fi)))
          fi = n.force.col(i);
        f.force += fi;
        f.torque += (n.x.col(i) - origin).cross(fi);
      }
    if (needle_coupling != nullptr && j == needle_tool)
      {
        const auto [force, torque] = needle_coupling->needle_load(n.x, origin, dt, free);
        f.force += force;
        f.torque += torque;
      }
    return f;
  }

  void
  World::cut_suture(const std::uint32_t segment)
  {
    if (!suture_model || segment + 1 >= sys.suture.size())
      throw std::invalid_argument("realtime world: no suture link " + std::to_string(segment) + " to cut");
    suture_model->cut(sys, segment);
  }

  void
  World::release_needle(const double density, const double drag)
  {
    if (needle_coupling == nullptr)
      throw std::invalid_argument("realtime world: no needle to let go");
    if (free_body)
      throw std::invalid_argument("realtime world: the needle is free already");
    if (!time_integrator->quasi_static())
      throw std::invalid_argument("realtime world: a released needle moves by the quasi-static law V = F/B; "
                                  "this integrator carries momentum");
    free_body.emplace(needle_coupling->geometry(), density, drag);
    free_body->release(needle_coupling->pose());
  }

  namespace
  {
    /// @p at in the frame of @p holder: the grip whose holder∘grip is @p at.
    ToolPose
    pose_in(const ToolPose &holder, const ToolPose &at)
    {
      return {holder.inverse_apply(at.position), holder.orientation.conjugate() * at.orientation};
    }
  } // namespace

  void
  World::grasp_needle(const ToolPose &tool_pose)
  {
    if (!free_body)
      throw std::invalid_argument("realtime world: the needle is held already");
    grip = pose_in(tool_pose, free_body->pose());
    free_body.reset();
  }

  void
  World::hand_needle_over(const ToolPose &holder)
  {
    if (needle_coupling == nullptr || free_body)
      throw std::invalid_argument("realtime world: only a held needle can be handed over");
    grip                     = pose_in(holder, needle_coupling->pose());
    start_poses[needle_tool] = holder; // the step moves it from here, not from the last holder
    tools[needle_tool].pose  = holder;
  }

  void
  World::reverse_needle()
  {
    if (needle_coupling == nullptr || free_body || !needle_coupling->geometry().straight())
      throw std::invalid_argument("realtime world: only a held double-pointed needle is passed across");
    if (needle_coupling->puncture_state().phase() != coupling::NeedlePuncture::Phase::outside)
      throw std::invalid_argument(needle_coupling->puncture_state().touch() != nullptr ? "its tip touches the tissue"
                                                                                      : "its tip is in the tissue");
    // the other point, which leads next, must be out of the tissue too: mirrored about
    // the middle
    const auto    &needle = needle_coupling->geometry();
    const Vector3d other  = 2 * needle.swage(needle_coupling->pose()) - needle.tip(needle_coupling->pose());
    if (collision::winding_number(other, sys.nodes.x, tissue_model->surface()) > 0.5)
      throw std::invalid_argument("its other point is still in the tissue");
    const auto &points = needle_coupling->pierce_points();
    const auto  on_needle =
      std::count_if(points.begin(), points.end(), [](const PiercePointState &p) { return !p.on_suture; });
    if (on_needle > 0)
      throw std::invalid_argument(std::to_string(on_needle) + (on_needle == 1 ? " hole is" : " holes are") +
                                  " still on the needle, not yet on the suture");
    grip.orientation = grip.orientation * Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Vector3d::UnitZ()));
    needle_coupling->forget_tip_path();
  }

  void
  World::move_free_needle(const double dt)
  {
    // the suture's pull at the swage (the tissue's interactions do not touch the
    // suture's nodes) and the needle's load
    evaluate_forces(tissue_interactions);
    const Vector3d  c    = free_body->centroid();
    const ToolForce load = load_on_tool(needle_tool, free_body->pose().position, dt, true);
    Matrix6d        K    = Matrix6d::Zero();
    needle_coupling->add_stiffness(K, c);
    if (suture_model)
      for (const auto i : tools[needle_tool].nodes)
        add_point_stiffness(K, sys.nodes.x.col(i) - c, suture_model->holding_stiffness());
    free_body->step(load.force, load.torque, sys.gravity, K, dt);
  }

  void
  World::evaluate_forces(const std::size_t first_interaction)
  {
    Nodes &n = sys.nodes;
    if (time_integrator->position_based())
      {
        // the forces the XPBD solve applied (its multipliers of the last substep); a
        // primal tissue solve's interactions, their elastic forces
        const double      dt      = h / n_substeps;
        const std::size_t primal  = time_integrator->first_constraint_interaction(sys);
        n.force.setZero();
        for (std::size_t k = first_interaction; k < sys.interactions.size(); ++k)
          k < primal ? sys.interactions[k]->add_forces(n.x, n.force)
                     : sys.interactions[k]->add_constraint_forces(n.x, n.force, dt);
        for (const auto &c : sys.contacts)
          c->add_constraint_forces(n.x, n.force, dt);
      }
    else
      {
        sys.internal_forces(n.x, n.force, first_interaction);
        for (const auto &c : sys.contacts)
          c->add_forces(n.x, n.force);
      }
    n.force += n.external;
    if (!sys.gravity.isZero())
      n.force.noalias() += sys.gravity * n.mass.transpose();
  }

  World::ReactionSet
  World::reaction_set(const std::vector<std::uint32_t> &nodes) const
  {
    ReactionSet set;
    set.nodes = nodes;
    set.touched.assign(sys.nodes.size(), 0);
    for (const auto i : nodes)
      set.touched.at(i) = 1;
    set.elements.resize(sys.interactions.size());
    set.listed.resize(sys.interactions.size());
    set.revisions.resize(sys.interactions.size());
    for (std::size_t k = 0; k < sys.interactions.size(); ++k)
      {
        set.listed[k]    = sys.interactions[k]->elements_touching(set.touched, set.elements[k]);
        set.revisions[k] = sys.interactions[k]->revision();
      }
    set.force.resize(3, sys.nodes.size());
    return set;
  }

  Vector3d
  World::reaction(ReactionSet &set) const
  {
    const Nodes &n = sys.nodes;
    Matrix3Xd   &f = set.force;
    if (f.cols() != n.x.cols() || set.elements.size() != sys.interactions.size())
      throw std::logic_error("World::reaction: the set was built for another system");
    // the forces evaluate_forces() would give the set's nodes, from the elements touching them
    f.setZero();
    const double      dt     = h / n_substeps;
    const bool        xpbd   = time_integrator->position_based();
    const std::size_t primal = time_integrator->first_constraint_interaction(sys);
    Vector3d          summed = Vector3d::Zero(); // the families that sum over the set themselves
    for (std::size_t k = 0; k < sys.interactions.size(); ++k)
      {
        const bool         constraint = xpbd && k >= primal;
        const Interaction &i          = *sys.interactions[k];
        if (set.revisions[k] != i.revision())
          {
            set.listed[k]    = i.elements_touching(set.touched, set.elements[k]);
            set.revisions[k] = i.revision();
          }
        const auto &listed = set.elements[k];
        if (!set.listed[k])
          constraint ? i.add_constraint_forces(n.x, f, dt) : i.add_forces(n.x, f);
        else if (constraint)
          {
            if (!i.add_constraint_forces_on(n.x, dt, listed, set.touched, summed))
              i.add_constraint_forces_of(n.x, f, dt, listed);
          }
        else if (!i.add_forces_on(n.x, listed, set.touched, summed))
          i.add_forces_of(n.x, f, listed);
      }
    for (const auto &c : sys.contacts)
      xpbd ? c->add_constraint_forces(n.x, f, dt) : c->add_forces(n.x, f);
    Vector3d r = -summed;
    for (const auto i : set.nodes)
      {
        Vector3d fi = f.col(i) + n.external.col(i);
        if (!sys.gravity.isZero())
          fi += sys.gravity * n.mass[i];
        r -= fi;
      }
    return r;
  }

  std::size_t
  World::add_probe(const Vector3d &X)
  {
    if (!tissue_model)
      throw ParameterError("Probes", "the scene has no tissue");
    const Matrix3Xd &R         = sys.nodes.reference;
    const double     tolerance = 1e-6 * sys.length_scale();
    Probe            best{{0, 0, 0, 0}, Eigen::Vector4d::Zero()};
    double           best_distance = std::numeric_limits<double>::infinity();
    // inside a tetrahedron (volume model)
    for (const auto &c : tissue_model->volume_cells())
      {
        Eigen::Matrix3d A;
        A << R.col(c[1]) - R.col(c[0]), R.col(c[2]) - R.col(c[0]), R.col(c[3]) - R.col(c[0]);
        const Vector3d        l = A.lu().solve(X - R.col(c[0]));
        const Eigen::Vector4d w(1 - l.sum(), l[0], l[1], l[2]);
        if (w.minCoeff() >= -1e-12)
          {
            probes.push_back({c, w});
            return probes.size() - 1;
          }
      }
    // else on the nearest surface triangle
    Vector3d bary;
    for (const auto &t : tissue_model->surface())
      {
        const Vector3d q = collision::closest_point_on_triangle(X, R.col(t[0]), R.col(t[1]), R.col(t[2]), bary);
        const double   d = (q - X).norm();
        if (d < best_distance)
          {
            best_distance = d;
            best          = {{t[0], t[1], t[2], t[0]}, Eigen::Vector4d(bary[0], bary[1], bary[2], 0)};
          }
      }
    if (best_distance > tolerance)
      {
        std::ostringstream s;
        s << "point (" << X[0] << ", " << X[1] << ", " << X[2] << ") m is " << best_distance
          << " m away from the "
          << (tissue_model->volume_cells().empty() ? "surface (the surface model has no nodes inside)"
                                                   : "tissue");
        throw ParameterError("Probes", s.str());
      }
    probes.push_back(best);
    return probes.size() - 1;
  }

  Vector3d
  World::probe_displacement(const std::size_t probe) const
  {
    const Probe &p = probes[probe];
    Vector3d     u = Vector3d::Zero();
    for (unsigned k = 0; k < 4; ++k)
      u += p.weights[k] * (sys.nodes.x.col(p.nodes[k]) - sys.nodes.reference.col(p.nodes[k]));
    return u;
  }
} // namespace suturesim::realtime
