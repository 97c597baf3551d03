#include <suturesim/core/error.h>
#include <suturesim/core/model_parameters.h>
#include <suturesim/mesh/gmsh_reader.h>
#include <suturesim/scene/knot_parameters.h>
#include <suturesim/scene/realtime_world.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

namespace suturesim::scene
{
  using namespace dealii;
  namespace rt = realtime;

  namespace
  {
    /// An interrupted series' tools, two per stitch from @p first (RealtimeWorld's
    /// first_series_tool): stitch @p k's tie, then its tail's hand.
    std::size_t
    tie_tool(const std::size_t first, const std::size_t k)
    {
      return first + 2 * k;
    }
    std::size_t
    tail_tool(const std::size_t first, const std::size_t k)
    {
      return tie_tool(first, k) + 1;
    }

    rt::ToolPose
    pose_of(const rod::EndCondition &end, const Eigen::Vector3d &initial, const double t)
    {
      rt::ToolPose pose;
      pose.position = initial;
      if (end.type == "prescribed")
        {
          const Eigen::Vector3d theta = end.motion(t).second;
          pose.position               = end.position(t, initial);
          const double angle          = theta.norm();
          if (angle > 0)
            pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(angle, theta / angle));
        }
      return pose;
    }

    /// E and ν of the small-strain limit of shear modulus @p mu and bulk modulus @p K.
    std::pair<double, double>
    youngs_and_poisson(const double mu, const double K)
    {
      return {9 * K * mu / (3 * K + mu), (3 * K - 2 * mu) / (2 * (3 * K + mu))};
    }

    /// Fails with a realtime model's ParameterError, which names only its key: the key
    /// is one of a chosen model's (Realtime/<model>/Key) where the file or --set gives
    /// it there, else one of Realtime's own.
    [[noreturn]] void
    fail_realtime(const SceneParameters &scene, const RealtimeSettings &settings, const ParameterError &e)
    {
      const ParameterScope realtime = scene.scope("Realtime");
      for (const std::string &model : {settings.tissue_model, settings.suture_model, settings.self_collision,
                                       settings.integrator, settings.pierce_model})
        if (realtime.parameter_file().given("Realtime/" + model + "/" + e.key))
          realtime.subsection(model).fail(e.key, e.problem);
      realtime.fail(e.key, e.problem);
    }
  } // namespace

  RealtimeWorld::RealtimeWorld(SceneParameters &s, const RealtimeSettings &settings, RealtimeModels models,
                               const std::string &directory)
    : scene(s)
  {
    rt::WorldSetup setup;
    setup.rate               = settings.rate;
    setup.substeps           = settings.substeps;
    setup.refuse_above_limit = settings.refuse_above_limit;
    if (scene.has_tissue())
      {
        read_tissue(setup, directory);
        setup.tissue = std::move(models.tissue);
      }
    if (scene.has_suture())
      {
        place_suture(setup);
        setup.suture                    = std::move(models.suture);
        setup.self_collision            = settings.self_collision;
        setup.self_collision_parameters = models.self_collision;
      }
    setup.contact           = scene.has_tissue() && scene.has_suture() && settings.contact;
    setup.contact_stiffness = settings.contact_stiffness;
    setup.contact_depth     = settings.contact_depth;
    setup.contact_load      = settings.contact_load;
    setup.integrator        = std::move(models.integrator);
    // the models check what they read of their parameters as they are built (the
    // self-collision response, the tissue's bending points against the mesh)
    try
      {
        world = std::make_unique<rt::World>(std::move(setup));
      }
    catch (const ParameterError &e)
      {
        fail_realtime(scene, settings, e);
      }

    if (scene.has_tissue())
      {
        hold_boundaries();
        add_tractions(settings.traction_subdivision);
        add_face_contact(settings);
      }
    add_tools(settings);
    add_probes();
    add_access(settings);
    add_probe(settings);
    add_knot_planner();
    add_series();
    try
      {
        world->initialize();
      }
    catch (const ParameterError &e)
      {
        fail_realtime(scene, settings, e);
      }
    if (settings.tearing.strength > 0)
      {
        const ParameterScope tear = scene.scope("Realtime/Tearing");
        if (!scene.has_tissue() || !needle)
          tear.fail("Ligament strength", "tears start at the needle's pierce points: the scene needs tissue and a "
                                         "needle");
        tear.require(wound.present(), "Ligament strength",
                     "the tear's path is classified against the wound: name its faces (Stitch evaluation/Wound "
                     "faces or Closure/Face contact)");
        try
          {
            tearing.emplace(settings.tearing, wound, *world);
          }
        catch (const std::invalid_argument &e)
          {
            tear.fail("Ligament strength", e.what());
          }
      }
    if (!world->warning().empty())
      std::cerr << "warning: " << scene.file->name() << ": " << world->warning() << '\n';
  }

  void
  RealtimeWorld::read_tissue(rt::WorldSetup &setup, const std::string &directory)
  {
    tissue_mesh = mesh::read_simplex_mesh(scene.mesh, directory);
    try
      {
        surface = mesh::extract_boundary(tissue_mesh);
      }
    catch (const std::invalid_argument &e)
      {
        throw InputError(scene.mesh.file + ": " + e.what());
      }
    for (const auto &[id, name] : tissue_mesh.boundary_names)
      mesh_info.boundary_names[id] = name;
    mesh_info.description = tissue_mesh.description;
    scene.boundary_conditions.resolve(mesh_info);
    wound = scene.wound(mesh_info, tissue_mesh.vertices, surface.triangles, surface.tags);
    // the supports are known with the mesh's boundaries only: checked here, not at set-up
    const ParameterScope bc = scene.scope("Tissue/Boundary conditions");
    for (const auto &d : scene.boundary_conditions.dirichlet)
      bc.require(d.components[0] && d.components[1] && d.components[2], "Fixed",
                 "boundary '" + d.name +
                   "': the realtime path holds nodes in every direction; component "
                   "restrictions (name:x) need Model = accurate");

    const auto &material = *scene.material;
    std::tie(setup.material.youngs_modulus, setup.material.poisson_ratio) =
      youngs_and_poisson(material.shear_modulus(), material.bulk_modulus());
    setup.material.density = material.density();
    for (const auto &r : scene.tissue.region_moduli)
      {
        const auto named = std::find_if(tissue_mesh.material_names.begin(), tissue_mesh.material_names.end(),
                                        [&](const auto &m) { return m.second == r.name; });
        if (named == tissue_mesh.material_names.end())
          throw InputError(scene.file->name() + ": Tissue/Region moduli: the mesh (" + scene.mesh.file +
                           ") has no physical volume '" + r.name + "'");
        const auto [E, nu]                   = youngs_and_poisson(r.shear_modulus, r.bulk_modulus);
        setup.material.regions[named->first] = {E, nu};
      }
    setup.mesh          = &tissue_mesh;
    const auto &gravity = scene.boundary_conditions.gravity;
    setup.gravity       = {gravity[0], gravity[1], gravity[2]};
  }

  void
  RealtimeWorld::place_suture(rt::WorldSetup &setup)
  {
    const auto            &rod = scene.suture;
    std::vector<rod::Vec3> x;
    std::vector<rod::Quat> q;
    rod.initial_configuration(x, q);
    for (const auto &p : x)
      setup.suture_geometry.points.push_back(p);
    if (scene.needle.present() && scene.needle.attach_suture)
      RealtimeNeedle::place_suture(scene.needle, setup.suture_geometry.points);
    const auto &section           = rod.section;
    const auto  k                 = section.stiffness();
    setup.suture_geometry.radius  = section.radius;
    setup.suture_geometry.EA      = k.force[0];
    setup.suture_geometry.EI      = k.moment[1];
    setup.suture_geometry.density = section.density;
    if (!scene.has_tissue())
      setup.gravity = rod.gravity;
    else if (!rod.gravity.isZero() && !rod.gravity.isApprox(setup.gravity))
      scene.scope("Suture/Loads").fail("Gravity", "differs from Tissue/Boundary conditions/Gravity; the realtime path "
                                            "has one gravity for all bodies");
  }

  void
  RealtimeWorld::hold_boundaries()
  {
    for (const auto &d : scene.boundary_conditions.dirichlet)
      {
        const auto vertices = mesh::vertices_with_tag(surface, d.id);
        if (!d.prescribed)
          {
            world->fix_vertices(vertices);
            boundaries.push_back({d.name, world->nodes_of_vertices(vertices)});
            continue;
          }
        auto *bc = &scene.boundary_conditions;
        boundaries.push_back(
          {d.name, world->prescribe_vertices(vertices, [bc](const double t, const std::vector<std::uint32_t> &nodes,
                                                            const rt::Matrix3Xd &X, rt::Matrix3Xd &target) {
             auto          &g = bc->displacement(t);
             Vector<double> u(3);
             for (const auto i : nodes)
               {
                 g.vector_value(Point<3>(X(0, i), X(1, i), X(2, i)), u);
                 for (int c = 0; c < 3; ++c)
                   target(c, i) = X(c, i) + u[c];
               }
           })});
      }
  }

  void
  RealtimeWorld::add_tractions(const unsigned subdivision)
  {
    // Tractions t0(X, t) as the consistent nodal loads of linear triangles, f_i = ∫ t0 N_i
    // dA (N_i = λ_i), by the composite centroid rule of mesh::subtriangle_centroids: at a
    // point of barycentric λ and weight w, the share A w λ_i to vertex i. With n = 1 that
    // is t0 at the centroid times A/3 to each vertex.
    struct Sample
    {
      std::array<std::int64_t, 3> nodes;
      Point<3>                    point;
      std::array<double, 3>       share; ///< A w λ_i, m²
    };
    const auto          rule = mesh::subtriangle_centroids(subdivision);
    std::vector<Sample> samples;
    for (std::size_t f = 0; f < surface.triangles.size(); ++f)
      if (scene.boundary_conditions.traction_boundaries.count(surface.tags[f]))
        {
          const auto        &tri = surface.triangles[f];
          const rt::Vector3d a = tissue_mesh.vertices.col(tri[0]), b = tissue_mesh.vertices.col(tri[1]),
                             c = tissue_mesh.vertices.col(tri[2]);
          const double       area   = 0.5 * (b - a).cross(c - a).norm();
          const auto        *tissue = world->tissue();
          for (const auto &q : rule)
            {
              const auto        &l = q.barycentric;
              const rt::Vector3d x = l[0] * a + l[1] * b + l[2] * c;
              samples.push_back({{{tissue->node(tri[0]), tissue->node(tri[1]), tissue->node(tri[2])}},
                                 Point<3>(x[0], x[1], x[2]),
                                 {{area * q.weight * l[0], area * q.weight * l[1], area * q.weight * l[2]}}});
            }
        }
    if (samples.empty())
      return;
    auto *bc = &scene.boundary_conditions;
    world->set_loads([bc, samples](const double t, rt::Matrix3Xd &external) {
      auto          &traction = bc->traction(t);
      Vector<double> t0(3);
      for (const auto &s : samples)
        {
          traction.vector_value(s.point, t0);
          for (int k = 0; k < 3; ++k)
            if (s.nodes[k] >= 0)
              for (int c = 0; c < 3; ++c)
                external(c, s.nodes[k]) += t0[c] * s.share[k];
        }
    });
  }

  void
  RealtimeWorld::add_face_contact(const RealtimeSettings &settings)
  {
    if (!(settings.face_contact_stiffness > 0))
      return;
    scene.scope("Realtime").require(!scene.closure.face_contact.empty(), "Face contact stiffness",
                                    "the faces it keeps apart are Closure/Face contact's: name them");
    const auto [a, b] = scene.closure.face_contact_ids(mesh_info);
    // face A's nodes, face B's triangles in system nodes (outward, as the tissue's surface is)
    const auto                 &tissue = *world->tissue();
    std::vector<std::uint32_t>  face_a;
    std::vector<mesh::Triangle> face_b;
    for (const auto v : mesh::vertices_with_tag(surface, a))
      face_a.push_back(static_cast<std::uint32_t>(tissue.node(v)));
    for (std::size_t t = 0; t < tissue.surface().size(); ++t)
      if (tissue.surface_tags()[t] == static_cast<int>(b))
        face_b.push_back(tissue.surface()[t]);
    try
      {
        world->add_wound_face_contact(face_a, face_b, settings.face_contact_stiffness,
                                      scene.closure.face_contact_margin);
      }
    catch (const std::invalid_argument &e)
      {
        scene.scope("Closure").fail("Face contact", e.what());
      }
  }

  void
  RealtimeWorld::add_tools(const RealtimeSettings &settings)
  {
    if (scene.needle.present())
      {
        if (!scene.has_tissue())
          scene.scope("Needle").fail("Shape", "a needle needs tissue (Bodies = tissue or tissue and suture)");
        scene.needle.check_entry_on_surface(world->tissue()->surface(), world->system().nodes.reference,
                                            scene.scope("Needle/Pass"));
        try
          {
            needle.emplace(scene.needle, *world, settings.pierce_model, settings.pierce_mass_ratio, wound);
            clearance.emplace(scene.needle);
          }
        catch (const ParameterError &e) // the coupling's own parameters (Load radius)
          {
            scene.scope("Pierce points").fail(e.key, e.problem);
          }
        catch (const std::invalid_argument &e)
          {
            if (std::string(e.what()).find("pierce model") != std::string::npos)
              scene.scope("Realtime").fail("Pierce model", e.what());
            scene.scope("Needle").fail("Shape", e.what());
          }
        const auto [section, key] = scene.needle.release_entry();
        scene.scope(section).require(!scene.needle.released() || world->integrator().quasi_static(), key,
                                     "a released needle moves by the quasi-static law V = F/B: it needs "
                                     "Realtime/Integrator = quasi-static");
      }
    first_end_tool = needle ? 1 : 0;
    if (!scene.has_suture())
      return;
    const auto         &sys   = world->system();
    const std::uint32_t first = sys.suture.begin, last = sys.suture.end - 1;
    for (const auto &[name, end, a, b] :
         {std::tuple{std::string("suture_start"), &scene.suture.start_end, first, first + 1},
          std::tuple{std::string("suture_end"), &scene.suture.last_end, last, last - 1}})
      {
        if (end->type == "free")
          continue;
        // A grasper that fixes the end's frame holds two nodes (position and direction);
        // a pin or a moving pin holds one.
        std::vector<std::uint32_t> held{a};
        if (end->fixes_rotation())
          held.push_back(b);
        const rt::Vector3d X = sys.nodes.x.col(a);
        // a grasper that closes later holds nothing until then
        const bool later = end->grasp_time > 0;
        world->add_tool(name, later ? std::vector<std::uint32_t>() : held, pose_of(*end, X, 0));
        tool_ends.push_back({name, end, X, held, !later});
      }
  }

  void
  RealtimeWorld::add_access(const RealtimeSettings &settings)
  {
    if (settings.access_points.empty())
      return;
    const ParameterScope realtime = scene.scope("Realtime");
    realtime.require(scene.has_suture(), "Access points", "access points need a suture to pass through them");
    std::vector<rt::Vector3d> points;
    for (const auto &[name, b] : settings.access_points)
      {
        access_names.push_back(name);
        points.push_back(b);
      }
    try
      {
        world->add_access(points, settings.access_stiffness);
      }
    catch (const std::invalid_argument &e)
      {
        realtime.fail("Access points", e.what());
      }
  }

  void
  RealtimeWorld::add_probe(const RealtimeSettings &settings)
  {
    if (!(settings.probe.length > 0))
      return;
    const ParameterScope at = scene.scope("Realtime/Probe");
    at.require(scene.has_tissue(), "Length", "a probe presses on tissue: the scene has none");
    probe = settings.probe;
    try
      {
        probe_tool = world->add_probe("probe", probe.tip, probe.axis, probe.length, probe.radius, probe.stiffness);
      }
    catch (const std::invalid_argument &e)
      {
        at.fail("Length", e.what());
      }
  }

  void
  RealtimeWorld::add_probes()
  {
    for (const auto &[name, X] : scene.tissue.probes)
      try
        {
          probes.emplace_back(name, world->add_probe({X[0], X[1], X[2]}));
        }
      catch (const ParameterError &e)
        {
          scene.scope("Tissue").fail("Probes", "'" + name + "': " + e.problem);
        }
    if (!scene.closure.present())
      return;
    // the closure measurement: two probes per pair
    if (!scene.has_tissue())
      scene.scope("Closure").fail("Gap probes", "closure needs tissue");
    closure.emplace(scene.closure);
    if (scene.closure.tie_off_each_stitch)
      {
        // each stitch closes from its pull's start, is tied off from its pull's end (or
        // its tail's taking) to its tightening's end
        closure->set_stitches(InterruptedSeries::windows(scene.needle.planned_series()));
      }
    for (const auto &pair : scene.closure.pairs)
      try
        {
          gap_probes.emplace_back(world->add_probe(pair.a), world->add_probe(pair.b));
        }
      catch (const ParameterError &e)
        {
          scene.scope("Closure").fail("Gap probes", "'" + pair.name + "': " + e.problem);
        }
    gaps.resize(gap_probes.size());
  }

  void
  RealtimeWorld::tool_poses(const double t, std::vector<rt::ToolPose> &poses)
  {
    const std::size_t stitches = series ? series->size() : 0;
    poses.resize(first_end_tool + tool_ends.size() + (probe_tool ? 1 : 0) + 2 * stitches);
    // an interrupted series' ties hold the thread where they took it, its tail hands
    // carry their tails to their lays (Needle/Pass/Tail lay) and hold them there
    for (std::size_t k = 0; k < 2 * stitches; ++k)
      poses[first_series_tool + k] = rt::ToolPose();
    for (std::size_t k = 0; k < stitches; ++k)
      poses[tail_tool(first_series_tool, k)].position = series->tail_displacement(k, t, closure->stitch_ties());
    for (std::size_t k = 0; k < tool_ends.size(); ++k)
      {
        auto &e = tool_ends[k];
        if (!e.grasped && t >= e.end->grasp_time)
          {
            // the grasper closes on the end where it is now
            e.initial = world->system().nodes.x.col(e.held.front());
            world->grasp(first_end_tool + k, e.held, pose_of(*e.end, e.initial, e.end->grasp_time));
            e.grasped = true;
          }
        poses[first_end_tool + k] = pose_of(*e.end, e.initial, std::max(t, e.end->grasp_time));
      }
    if (needle)
      {
        try
          {
            needle->operate_jaws(*world, t);
          }
        catch (const ParameterError &e) // the jaws' (RealtimeNeedle::operate_jaws)
          {
            const auto [section, key] = e.key == "Passes across" ? std::pair<std::string, std::string>{"Needle", e.key}
                                                                 : scene.needle.release_entry();
            scene.scope(section).fail(key, e.problem);
          }
        static const std::vector<double> none;
        poses[needle->tool()] = needle->pose(t, series ? series->pull_stops() : none, closure ? closure->stitch_ties() : none);
        // the driver's pose, before a knot planner takes the needle over
        if (!planner || planner->phase() == knot::KnotPlanner::Phase::waiting)
          clearance->check(t, poses[needle->tool()], world->system().nodes.x, world->tissue()->surface());
      }
    if (probe_tool)
      poses[*probe_tool].position = probe.position(t);
    if (planner)
      {
        const auto         &sys  = world->system();
        const rt::Matrix3Xd rope = sys.nodes.x.middleCols(sys.suture.begin, sys.suture.size());
        // the ends' tools (KnotParameters::check: both held): the last end's grasper, and
        // the first end's, or the needle holding it at its swage
        const std::size_t first  = needle ? needle->tool() : first_end_tool;
        const std::size_t last   = first_end_tool + tool_ends.size() - 1;
        const std::size_t moving = planner->moving_first_end() ? first : last;
        if (scene.knot.plane_from_pierce_points && planner->phase() == knot::KnotPlanner::Phase::waiting &&
            t >= scene.knot.start_time)
          planner->set_normal(pierce_plane_normal(t));
        const knot::Ends  to = planner->move(rope, t, t - planner_time, world->tool_forces()[moving].force.norm());
        planner_time         = t;
        // until it starts, the tools follow their own motions
        if (planner->phase() == knot::KnotPlanner::Phase::waiting)
          return;
        poses[last].position = to.last;
        if (needle)
          {
            // the needle as taken, translated as far as the planner moved the first end
            // (not at all when only the last end moves: the planner holds it where it was)
            if (!needle_taken)
              needle_taken.emplace(poses[first], rope.col(0));
            poses[first] = needle_taken->first;
            poses[first].position += to.first - needle_taken->second;
          }
        else if (planner->moves_first_end())
          poses[first].position = to.first;
      }
  }

  Eigen::Vector3d
  RealtimeWorld::pierce_plane_normal(const double t) const
  {
    // the pierce points in the order the needle made them, where the tissue is now
    const auto &points = world->needle()->pierce_points();
    const auto  n      = points.size();
    if (n >= 3)
      {
        const Eigen::Vector3d &p1 = points[n - 3].position, &p2 = points[n - 2].position, &p3 = points[n - 1].position;
        const Eigen::Vector3d  normal = (p2 - p1).cross(p3 - p1);
        // three points on one line (to a part in 10^6 of the spread) span no plane
        if (normal.norm() > 1e-6 * (p2 - p1).norm() * (p3 - p1).norm())
          return normal;
      }
    scene.scope("Knot").fail("Projection plane", "'pierce points' needs three pierce points not on one line when "
                                                 "the planner starts (t = " + shortest_text(t) + " s); the needle has made " +
                                                   std::to_string(n));
  }

  void
  RealtimeWorld::add_knot_planner()
  {
    KnotParameters::check(scene);
    if (scene.knot.knot != "none")
      planner.emplace(scene.knot);
  }

  double
  RealtimeWorld::closure_tension() const
  {
    if (needle && scene.closure.tie_off_each_stitch)
      return world->tool_forces()[needle->tool()].force.norm();
    if (!tool_ends.empty() && tool_ends.back().grasped)
      return world->tool_forces()[first_end_tool + tool_ends.size() - 1].force.norm();
    if (needle)
      return world->tool_forces()[needle->tool()].force.norm();
    return 0;
  }

  const std::string &
  RealtimeWorld::stop_reason() const
  {
    static const std::string none;
    return clearance ? clearance->reason() : none;
  }

  void
  RealtimeWorld::measure_closure()
  {
    if (!closure)
      return;
    for (std::size_t k = 0; k < gap_probes.size(); ++k)
      {
        const auto &pair = scene.closure.pairs[k];
        gaps[k]          = closure->gap(k, pair.a + world->probe_displacement(gap_probes[k].first),
                                        pair.b + world->probe_displacement(gap_probes[k].second));
      }
    closure->update(world->time(), gaps, closure_tension());
  }

  void
  RealtimeWorld::add_series()
  {
    if (!closure || !scene.closure.tie_off_each_stitch)
      return;
    const ParameterScope pass = scene.scope("Needle/Pass");
    scene.scope("Suture/Last end")
      .require(scene.suture.last_end.type == "free", "Type",
               "must be free in an interrupted series (Needle/Pass/Series): the other hand takes each stitch's "
               "tail once it is Tail length long");
    // a cut link would join the two pieces' ends in the self-collision's segments
    pass.require(world->self_collision() == nullptr, "Series",
                 "an interrupted series cuts its thread: Realtime/Self-collision must be off");
    const auto &sys = world->system();
    uncut           = Eigen::RowVectorXd::Ones(sys.suture.size() - 1);
    // the thread's nodes a link apart from the swage
    std::vector<double> arc(sys.suture.size());
    for (std::size_t i = 0; i < arc.size(); ++i)
      arc[i] = static_cast<double>(i) * world->suture()->link_length();
    series.emplace(scene.needle, std::move(arc), world->needle()->geometry().length());
    for (std::size_t k = 0; k < series->size(); ++k)
      for (const char *role : {"tie", "tail"})
        {
          const std::size_t tool =
            world->add_tool("stitch_" + std::to_string(k + 1) + "_" + role, {}, rt::ToolPose());
          if (k == 0 && std::string(role) == "tie")
            first_series_tool = tool;
        }
  }

  void
  RealtimeWorld::advance_series()
  {
    if (!series)
      return;
    std::vector<InterruptedSeries::Hole> holes;
    for (const auto &p : world->needle()->pierce_points()) // ζ ascending: the newest first
      holes.push_back({p.zeta, p.position, p.on_suture});
    const std::uint32_t first = world->system().suture.begin;
    const auto          act   = series->advance(world->time(), holes, *closure, scene.scope("Needle/Pass"),
                                                [&](const std::size_t i) -> Eigen::Vector3d {
                                                  return world->system().nodes.x.col(first + i);
                                                });
    const std::size_t   k     = act.stitch;
    if (act.tail)
      world->grasp(tail_tool(first_series_tool, k), {first + static_cast<std::uint32_t>(*act.tail)}, rt::ToolPose());
    if (act.tie.empty())
      return;
    std::vector<std::uint32_t> held;
    for (const std::size_t node : act.tie)
      held.push_back(first + static_cast<std::uint32_t>(node));
    // the hand's pull on the tail as the stitch is tied off
    series->set_tail_force(k, world->tool_forces()[tail_tool(first_series_tool, k)].force.norm());
    world->grasp(tie_tool(first_series_tool, k), held, rt::ToolPose());
    world->cut_suture(static_cast<std::uint32_t>(act.cut));
    uncut[static_cast<Eigen::Index>(act.cut)] = 0;
  }

  void
  RealtimeWorld::write_series(nlohmann::json &metrics) const
  {
    if (series)
      series->write(metrics);
  }
} // namespace suturesim::scene
