#include <suturesim/collision/volume_penetration.h>
#include <suturesim/core/error.h>
#include <suturesim/core/parameter_adapter.h>
#include <suturesim/io/polyline_writer.h>
#include <suturesim/io/simplex_writer.h>
#include <suturesim/mesh/gmsh_reader.h>
#include <suturesim/realtime/haptic_loop.h>
#include <suturesim/realtime/self_collision.h>
#include <suturesim/realtime/world.h>
#include <suturesim/scene/realtime_needle.h>
#include <suturesim/scene/realtime_scene.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <optional>
#include <iostream>
#include <sstream>

namespace suturesim::scene
{
  using namespace dealii;
  namespace rt = realtime;

  namespace
  {
    std::string
    processor_name()
    {
      std::ifstream in("/proc/cpuinfo");
      for (std::string line; std::getline(in, line);)
        if (line.rfind("model name", 0) == 0)
          return line.substr(line.find(':') + 2);
      return "unknown";
    }

    Eigen::Vector3d
    to_eigen(const Tensor<1, 3> &t)
    {
      return {t[0], t[1], t[2]};
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
          const double angle = theta.norm();
          if (angle > 0)
            pose.orientation = Eigen::Quaterniond(Eigen::AngleAxisd(angle, theta / angle));
        }
      return pose;
    }
  } // namespace

  void
  RealtimeScene::declare(ParameterHandler &prm)
  {
    declare_models<rt::TissueModel::Registry>(
      prm, "Tissue model", "volume",
      "Realtime tissue model, built from the tetrahedra of Mesh (the .geo must offer "
      "tetrahedra, e.g. Geo parameters = hexahedra: 0).");
    declare_models<rt::Integrator::Registry>(prm, "Integrator", "xpbd",
                                             "Realtime time integrator of tissue and suture.");
    declare_models<rt::SutureModel::Registry>(prm, "Suture model", "xpbd-rod",
                                              "Realtime suture model.");
    declare_models<rt::PierceModel::Registry>(
      prm, "Pierce model", "automatic",
      "How pierce points hold on to the needle and suture and slip along them; 'automatic': "
      "soft-constraint with the ftl suture under a force-based integrator, node-path otherwise.",
      "automatic|");
    declare_models<rt::SelfCollision::Registry>(prm, "Self-collision", "off",
                                                "Suture self-collision response; 'off': none.",
                                                "off|");
    prm.declare_entry("Contact", "true", Patterns::Bool(),
                      "Suture-tissue surface contact (tissue and suture scenes). Unit: none.");
    prm.declare_entry("Contact stiffness", "100", Patterns::Double(0),
                      "Penalty stiffness k of suture-tissue contact (compliance 1/k under "
                      "XPBD). Unit: N/m. Range: >= 0.");
    prm.declare_entry("Contact depth", "1e-3", Patterns::Double(0),
                      "How far inside the tissue surface a suture node is still pushed out "
                      "(deeper nodes are taken to have pierced it). Unit: m. Range: >= 0.");
    prm.declare_entry("Rate", "1000", Patterns::Double(1, 1e7),
                      "Haptic rate: one step(tool poses) -> tool forces per 1/Rate of "
                      "simulated time, and the deadline of each step. Unit: Hz. Range: "
                      "[1, 1e7].");
    prm.declare_entry("Substeps", "1", Patterns::Integer(1, 100000),
                      "Integrator substeps per haptic step (dt = 1/(Rate Substeps)). Unit: "
                      "none. Range: [1, 100000].");
    prm.declare_entry("Above stability limit", "warn", Patterns::Selection("warn|refuse"),
                      "What to do when dt exceeds the integrator's stability limit dt_crit "
                      "(reported in summary.json): warn and run, or refuse to run. Unit: "
                      "none.");
    prm.declare_entry("Pacing", "false", Patterns::Bool(),
                      "Wait for the wall clock between steps as a haptic loop does (true), "
                      "or step as fast as possible (false, for benchmarks). Unit: none.");
  }

  RealtimeScene::RealtimeScene(ParameterHandler &prm, const ParameterScope &s, RealtimeInputs inputs)
    : scope(s)
    , in(std::move(inputs))
  {
    tissue_name         = prm.get("Tissue model");
    integrator_name     = prm.get("Integrator");
    suture_name         = prm.get("Suture model");
    self_collision_name = prm.get("Self-collision");
    pierce_model_name   = prm.get("Pierce model");
    contact             = prm.get_bool("Contact");
    contact_stiffness   = prm.get_double("Contact stiffness");
    contact_depth       = prm.get_double("Contact depth");
    rate                = prm.get_double("Rate");
    substeps            = prm.get_integer("Substeps");
    refuse_above_limit  = prm.get("Above stability limit") == "refuse";
    pacing              = prm.get_bool("Pacing");

    integrator = create_model<rt::Integrator::Registry>(prm, scope, integrator_name);
    if (in.tissue)
      tissue_model = create_model<rt::TissueModel::Registry>(prm, scope, tissue_name);
    if (in.suture)
      {
        suture_model = create_model<rt::SutureModel::Registry>(prm, scope, suture_name);
        if (self_collision_name != "off")
          self_collision_values =
            read_model_values<rt::SelfCollision::Registry>(prm, self_collision_name);
      }
    if (in.tissue && in.suture && contact)
      scope.require(contact_stiffness > 0, "Contact stiffness",
                    "must be > 0 N/m when Contact = true");

    // What the realtime path does not model is refused, not silently dropped.
    if (in.suture)
      {
        const ParameterScope suture(scope.parameter_file(), "Suture");
        suture.require(in.rod->end_force.isZero() && in.rod->end_moment.isZero(), "End force",
                       "end loads are not applied by the realtime path (Model = realtime); "
                       "move the end with Last end = prescribed instead");
        suture.require(in.rod->distributed.isZero(), "Distributed load",
                       "is not applied by the realtime path (Model = realtime)");
        suture.subsection("Cross section")
          .require(in.rod->section.density > 0, "Density",
                   "must be > 0 kg/m^3: the realtime suture has mass");
      }
    if (in.tissue)
      {
        const ParameterScope bc(scope.parameter_file(), "Tissue/Boundary conditions");
        for (const auto &d : in.boundary_conditions->dirichlet)
          bc.require(d.components[0] && d.components[1] && d.components[2], "Fixed",
                     "boundary '" + d.name +
                       "': the realtime path holds nodes in every direction; component "
                       "restrictions (name:x) need Model = accurate");
        ParameterScope(scope.parameter_file(), "Tissue/Material")
          .require(in.material->density() > 0, "Density",
                   "must be > 0 kg/m^3: the realtime tissue has mass");
      }
  }

  RealtimeScene::~RealtimeScene() = default;

  void
  RealtimeScene::run(io::Recorder &recorder)
  {
    const ParameterFile &file = scope.parameter_file();
    rt::WorldSetup       setup;
    setup.rate               = rate;
    setup.substeps           = substeps;
    setup.refuse_above_limit = refuse_above_limit;

    // --- tissue -------------------------------------------------------------------------
    mesh::SimplexMesh     tissue_mesh;
    mesh::BoundarySurface surface;
    mesh::MeshInfo        mesh_info;
    if (in.tissue)
      {
        tissue_mesh = mesh::read_simplex_mesh(*in.mesh, recorder.directory());
        try
          {
            surface = mesh::extract_boundary(tissue_mesh);
          }
        catch (const std::invalid_argument &e)
          {
            throw InputError(in.mesh->file + ": " + e.what());
          }
        for (const auto &[id, name] : tissue_mesh.boundary_names)
          mesh_info.boundary_names[id] = name;
        mesh_info.description = tissue_mesh.description;
        in.boundary_conditions->resolve(mesh_info);

        const double mu = in.material->shear_modulus(), K = in.material->bulk_modulus();
        setup.material.youngs_modulus = 9 * K * mu / (3 * K + mu);
        setup.material.poisson_ratio  = (3 * K - 2 * mu) / (2 * (3 * K + mu));
        setup.material.density        = in.material->density();
        for (const auto &r : in.region_moduli)
          {
            const auto named = std::find_if(tissue_mesh.material_names.begin(), tissue_mesh.material_names.end(),
                                            [&](const auto &m) { return m.second == r.name; });
            if (named == tissue_mesh.material_names.end())
              throw InputError(file.name() + ": Tissue/Region moduli: the mesh (" + in.mesh->file +
                               ") has no physical volume '" + r.name + "'");
            const double mu = r.shear_modulus, K = r.bulk_modulus;
            setup.material.regions[named->first] = {9 * K * mu / (3 * K + mu),
                                                    (3 * K - 2 * mu) / (2 * (3 * K + mu))};
          }
        setup.mesh                    = &tissue_mesh;
        setup.tissue                  = std::move(tissue_model);
        setup.gravity                 = to_eigen(in.boundary_conditions->gravity);
      }

    // --- suture -------------------------------------------------------------------------
    const bool with_needle = in.needle != nullptr && in.needle->present();
    if (in.suture)
      {
        std::vector<rod::Vec3> x;
        std::vector<rod::Quat> q;
        in.rod->initial_configuration(x, q);
        for (const auto &p : x)
          setup.suture_geometry.points.push_back(p);
        if (with_needle && in.needle->attach_suture)
          RealtimeNeedle::place_suture(*in.needle, setup.suture_geometry.points);
        const auto &section              = in.rod->section;
        const auto  k                    = section.stiffness();
        setup.suture_geometry.radius     = section.radius;
        setup.suture_geometry.EA         = k.force[0];
        setup.suture_geometry.EI         = k.moment[1];
        setup.suture_geometry.density    = section.density;
        setup.suture                     = std::move(suture_model);
        setup.self_collision             = self_collision_name;
        setup.self_collision_parameters  = self_collision_values;
        if (!in.tissue)
          setup.gravity = in.rod->gravity;
        else if (!in.rod->gravity.isZero() && !in.rod->gravity.isApprox(setup.gravity))
          ParameterScope(file, "Suture").fail(
            "Gravity", "differs from Tissue/Boundary conditions/Gravity; the realtime path "
                       "has one gravity for all bodies");
      }
    setup.contact           = in.tissue && in.suture && contact;
    setup.contact_stiffness = contact_stiffness;
    setup.contact_depth     = contact_depth;
    setup.integrator        = std::move(integrator);

    rt::World world(std::move(setup));

    // --- holds, tools, loads, probes -------------------------------------------------------
    struct Boundary
    {
      std::string                name;
      std::vector<std::uint32_t> nodes;
    };
    std::vector<Boundary> boundaries;
    if (in.tissue)
      {
        for (const auto &d : in.boundary_conditions->dirichlet)
          {
            const auto vertices = mesh::vertices_with_tag(surface, d.id);
            if (!d.prescribed)
              {
                world.fix_vertices(vertices);
                boundaries.push_back({d.name, world.nodes_of_vertices(vertices)});
              }
            else
              {
                auto *bc = in.boundary_conditions;
                boundaries.push_back(
                  {d.name, world.prescribe_vertices(
                             vertices, [bc](const double t, const std::vector<std::uint32_t> &nodes,
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
        // Tractions t0(X, t) as nodal loads: a third of each loaded triangle's force, t0
        // at its centroid times its reference area, to each of its vertices.
        struct Loaded
        {
          std::array<std::int64_t, 3> nodes;
          Point<3>                    centroid;
          double                      area;
        };
        std::vector<Loaded> loaded;
        for (std::size_t f = 0; f < surface.triangles.size(); ++f)
          if (in.boundary_conditions->traction_boundaries.count(surface.tags[f]))
            {
              const auto &tri = surface.triangles[f];
              const rt::Vector3d a = tissue_mesh.vertices.col(tri[0]),
                                 b = tissue_mesh.vertices.col(tri[1]),
                                 c = tissue_mesh.vertices.col(tri[2]);
              const rt::Vector3d m = (a + b + c) / 3;
              Loaded l{{{world.tissue()->node(tri[0]), world.tissue()->node(tri[1]),
                         world.tissue()->node(tri[2])}},
                       Point<3>(m[0], m[1], m[2]),
                       0.5 * (b - a).cross(c - a).norm()};
              loaded.push_back(l);
            }
        if (!loaded.empty())
          {
            auto *bc = in.boundary_conditions;
            world.set_loads([bc, loaded](const double t, rt::Matrix3Xd &external) {
              auto          &traction = bc->traction(t);
              Vector<double> t0(3);
              for (const auto &l : loaded)
                {
                  traction.vector_value(l.centroid, t0);
                  for (const auto n : l.nodes)
                    if (n >= 0)
                      for (int c = 0; c < 3; ++c)
                        external(c, n) += t0[c] * l.area / 3;
                }
            });
          }
      }

    struct ToolEnd
    {
      std::string                name;
      const rod::EndCondition   *end;
      rt::Vector3d               initial;
      std::vector<std::uint32_t> held;
      bool                       grasped = true; ///< false until its Grasp time
    };
    std::optional<RealtimeNeedle> needle;
    if (with_needle)
      {
        if (!in.tissue)
          ParameterScope(file, "Needle").fail("Shape", "a needle needs tissue (Bodies = tissue or tissue and suture)");
        try
          {
            needle.emplace(*in.needle, world, pierce_model_name);
          }
        catch (const std::invalid_argument &e)
          {
            if (std::string(e.what()).find("pierce model") != std::string::npos)
              scope.fail("Pierce model", e.what());
            ParameterScope(file, "Needle").fail("Shape", e.what());
          }
      }
    // the tools of the suture's ends come after the needle's
    const std::size_t    first_end_tool = needle ? 1 : 0;
    std::vector<ToolEnd> tool_ends;
    if (in.suture)
      {
        const auto         &sys   = world.system();
        const std::uint32_t first = sys.suture.begin, last = sys.suture.end - 1;
        for (const auto &[name, end, a, b] :
             {std::tuple{std::string("suture_start"), &in.rod->start_end, first, first + 1},
              std::tuple{std::string("suture_end"), &in.rod->last_end, last, last - 1}})
          {
            if (end->type == "free")
              continue;
            // A grasper that fixes the end's frame holds two nodes (position and
            // direction); a pin or a moving pin holds one.
            std::vector<std::uint32_t> held{a};
            if (end->fixes_rotation())
              held.push_back(b);
            const rt::Vector3d X = sys.nodes.x.col(a);
            // a grasper that closes later holds nothing until then
            const bool later = end->grasp_time > 0;
            world.add_tool(name, later ? std::vector<std::uint32_t>() : held, pose_of(*end, X, 0));
            tool_ends.push_back({name, end, X, held, !later});
          }
      }

    std::vector<std::pair<std::string, std::size_t>> probes;
    for (const auto &[name, X] : in.probes)
      try
        {
          probes.emplace_back(name, world.add_probe({X[0], X[1], X[2]}));
        }
      catch (const ParameterError &e)
        {
          ParameterScope(file, "Tissue").fail("Probes", "'" + name + "': " + e.problem);
        }

    // the closure measurement: two probes per pair
    std::optional<ClosureMonitor>                  closure;
    std::vector<std::pair<std::size_t, std::size_t>> gap_probes;
    if (in.closure != nullptr)
      {
        if (!in.tissue)
          ParameterScope(file, "Closure").fail("Gap probes", "closure needs tissue");
        closure.emplace(*in.closure);
        for (const auto &pair : in.closure->pairs)
          try
            {
              gap_probes.emplace_back(world.add_probe(pair.a), world.add_probe(pair.b));
            }
          catch (const ParameterError &e)
            {
              ParameterScope(file, "Closure").fail("Gap probes", "'" + pair.name + "': " + e.problem);
            }
      }

    try
      {
        world.initialize();
      }
    catch (const ParameterError &e)
      {
        scope.fail(e.key, e.problem);
      }
    if (!world.warning().empty())
      std::cerr << "warning: " << file.name() << ": " << world.warning() << '\n';

    // --- the record -----------------------------------------------------------------------
    const auto &sys     = world.system();
    auto       &summary = recorder.summary();
    summary["scene"]      = in.scene_name;
    summary["scene_file"] = file.name();
    summary["model"]      = "realtime";
    summary["machine"]    = processor_name() + ", one core";
    auto &realtime        = summary["realtime"];
    const std::string settings = world.integrator().settings();
    realtime = {{"integrator", settings.empty() ? integrator_name : integrator_name + " (" + settings + ")"},
                             {"rate_hz", rate},
                             {"substeps", substeps},
                             {"dt_s", world.dt()},
                             {"dt_crit_s", std::isfinite(world.stability_limit())
                                             ? nlohmann::json(world.stability_limit())
                                             : nlohmann::json("none")},
                             {"stability_limit", world.stability_description()},
                             {"nodes", sys.nodes.size()}};
    if (!world.warning().empty())
      summary["warnings"].push_back(world.warning());
    if (in.tissue)
      {
        realtime["tissue_model"] = tissue_name;
        summary["mesh"]          = {{"description", tissue_mesh.description},
                                    {"vertices", tissue_mesh.vertices.cols()},
                                    {"tetrahedra", tissue_mesh.tetrahedra.size()},
                                    {"surface_triangles", surface.triangles.size()}};
      }
    if (in.suture)
      {
        realtime["suture_model"]   = suture_name;
        realtime["self_collision"] = self_collision_name;
        realtime["contact"]        = in.tissue && contact;
        summary["suture"]          = {{"nodes", sys.suture.size()},
                                      {"radius", in.rod->section.radius},
                                      {"EA", world.suture()->geometry().EA},
                                      {"EI", world.suture()->geometry().EI}};
      }
    for (const auto &i : sys.interactions)
      realtime["interactions"][i->name()] = i->size();
    summary["metrics"] = nlohmann::json::object();
    summary["steps"]   = nlohmann::json::array();

    std::vector<std::string> columns{"time [s]"};
    for (const auto &t : tool_ends)
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(t.name + "_force_" + std::string(1, c) + " [N]");
    if (needle)
      needle->add_columns(columns);
    for (const auto &b : boundaries)
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(b.name + "_reaction_" + std::string(1, c) + " [N]");
    for (const auto &[name, index] : probes)
      for (const char c : {'x', 'y', 'z'})
        columns.push_back(name + "_displacement_" + std::string(1, c) + " [m]");
    if (closure)
      for (const auto &pair : in.closure->pairs)
        columns.push_back("gap_" + pair.name + " [m]");
    columns.push_back("kinetic_energy [J]");
    columns.push_back("elastic_energy [J]");
    recorder.set_columns(columns);

    // the gaps of the current state, and the suture tension the closure is charged to:
    // what the grasper on the suture's far end feels, else the needle's pull
    std::vector<double> gaps(gap_probes.size());
    const auto          measure_closure = [&]() {
      if (!closure)
        return;
      for (std::size_t k = 0; k < gap_probes.size(); ++k)
        {
          const auto &pair = in.closure->pairs[k];
          gaps[k]          = closure->gap(k, pair.a + world.probe_displacement(gap_probes[k].first),
                                          pair.b + world.probe_displacement(gap_probes[k].second));
        }
      double tension = 0;
      if (!tool_ends.empty())
        tension = world.tool_forces()[first_end_tool + tool_ends.size() - 1].force.norm();
      else if (needle)
        tension = world.tool_forces()[needle->tool()].force.norm();
      closure->update(world.time(), gaps, tension);
    };

    std::vector<double> row(columns.size());
    const auto          record_row = [&]() {
      std::size_t c = 0;
      row[c++]      = world.time();
      for (std::size_t k = 0; k < tool_ends.size(); ++k)
        for (int d = 0; d < 3; ++d)
          row[c++] = world.tool_forces()[first_end_tool + k].force[d];
      if (needle)
        needle->fill_row(world, row, c);
      for (const auto &b : boundaries)
        {
          const auto r = world.reaction(b.nodes);
          for (int d = 0; d < 3; ++d)
            row[c++] = r[d];
        }
      for (const auto &[name, index] : probes)
        {
          const auto u = world.probe_displacement(index);
          for (int d = 0; d < 3; ++d)
            row[c++] = u[d];
        }
      for (const double g : gaps)
        row[c++] = g;
      row[c++] = sys.kinetic_energy();
      row[c++] = sys.elastic_energy(sys.nodes.x);
      recorder.add_row(row);
    };

    std::size_t n_outputs    = 0;
    double      last_written = -1;
    const auto  write_output = [&]() {
      const double t      = world.time();
      last_written        = t;
      const auto   suffix = [&](const std::string &series) {
        std::ostringstream name;
        name << series << "_" << std::setw(5) << std::setfill('0') << n_outputs << ".vtu";
        return name.str();
      };
      if (in.tissue)
        {
          const auto  &tm   = *world.tissue();
          const auto   n    = sys.tissue.end;
          const auto   X    = sys.nodes.reference.leftCols(n);
          const auto   x    = sys.nodes.x.leftCols(n);
          const auto   name = suffix("tissue");
          if (!tm.volume_cells().empty())
            {
              io::SimplexData<4> data{x, tm.volume_cells(), {}, {}};
              data.vector_fields = {{"displacement", x - X}, {"velocity", sys.nodes.v.leftCols(n)}};
              io::write_simplex_vtu(recorder.directory() + "/" + name, data, t);
            }
          else
            {
              io::SimplexData<3> data{x, tm.surface(), {}, {}};
              data.vector_fields = {{"displacement", x - X}, {"velocity", sys.nodes.v.leftCols(n)}};
              io::write_simplex_vtu(recorder.directory() + "/" + name, data, t);
            }
          recorder.add_vtu("tissue", t, name);
        }
      if (in.suture)
        {
          io::PolylineData data;
          for (auto i = sys.suture.begin; i < sys.suture.end; ++i)
            data.points.push_back(sys.nodes.x.col(i));
          std::vector<double> tension;
          world.suture()->segment_tension(sys, tension);
          data.point_fields   = {{"radius", std::vector<double>(data.points.size(),
                                                                 in.rod->section.radius)}};
          data.segment_fields = {{"tension", tension}};
          const auto name     = suffix("suture");
          io::write_polyline_vtu(recorder.directory() + "/" + name, data, t);
          recorder.add_vtu("suture", t, name);
        }
      ++n_outputs;
    };

    // --- the haptic loop --------------------------------------------------------------------
    const double      end_time = in.time->end_time;
    const std::size_t n_steps  = static_cast<std::size_t>(std::llround(end_time * rate));
    if (n_steps == 0)
      ParameterScope(file, "Time").fail("End time", "is shorter than one haptic step 1/Rate");
    const double interval = in.time->output_interval;
    std::cout << "suturesim: scene '" << in.scene_name << "', realtime: "
              << (in.tissue ? tissue_name + " tissue (" + tissue_mesh.description + "), " : "")
              << (in.suture ? suture_name + " suture of " + std::to_string(sys.suture.size()) +
                                " nodes, "
                            : "")
              << integrator_name << ", " << rate << " Hz x " << substeps << " substeps, "
              << n_steps << " steps\n";

    measure_closure();
    write_output();
    record_row();
    const auto                wall_start = std::chrono::steady_clock::now();
    rt::HapticLoop            loop(world, rate, n_steps, pacing);
    std::vector<rt::ToolPose> poses(first_end_tool + tool_ends.size());
    double                    next_output = interval;
    std::string               failure;
    for (std::size_t step = 1; step <= n_steps; ++step)
      {
        // prescribed motions stop at a tie-off
        const double t = closure ? closure->motion_time(step / rate) : step / rate;
        for (std::size_t k = 0; k < tool_ends.size(); ++k)
          {
            auto &e = tool_ends[k];
            if (!e.grasped && t >= e.end->grasp_time)
              {
                // the grasper closes on the end where it is now
                e.initial = sys.nodes.x.col(e.held.front());
                world.grasp(first_end_tool + k, e.held, pose_of(*e.end, e.initial, e.end->grasp_time));
                e.grasped = true;
              }
            poses[first_end_tool + k] = pose_of(*e.end, e.initial, std::max(t, e.end->grasp_time));
          }
        if (needle)
          poses[needle->tool()] = needle->pose(t);
        try
          {
            loop.tick(poses);
          }
        catch (const rt::DivergenceError &e)
          {
            failure = e.what();
            break;
          }
        measure_closure();
        record_row();
        if (interval > 0 && t >= next_output - 1e-12 * end_time)
          {
            write_output();
            next_output += interval;
          }
      }
    // The last state (the last good one after a divergence) is always written.
    if (world.time() != last_written)
      write_output();

    const auto stats                        = loop.statistics();
    auto      &metrics                      = summary["metrics"];
    metrics["steps"]                        = stats.steps;
    metrics["step_time_median_us"]          = stats.median_us;
    metrics["step_time_p99_us"]             = stats.p99_us;
    metrics["step_time_max_us"]             = stats.max_us;
    metrics["step_time_mean_us"]            = stats.mean_us;
    metrics["deadline_us"]                  = stats.deadline_us;
    metrics["deadline_misses"]              = stats.deadline_misses;
    metrics["final_time"]                   = world.time();
    metrics["simulated_time"]               = world.time();
    metrics["wall_time"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();
    if (closure)
      closure->write(metrics);
    // no suture node may end inside the tissue, deeper than its radius below the surface,
    // but those the thread carries between two pierce points
    if (in.tissue && in.suture && !world.tissue()->volume_cells().empty())
      {
        const rt::Matrix3Xd nodes = sys.nodes.x.middleCols(sys.suture.begin, sys.suture.size());
        std::vector<char> pierced;
        if (world.needle())
          pierced = world.needle()->suture_inside();
        const auto inside = collision::volume_penetration(sys.nodes.x.leftCols(sys.tissue.end),
                                                          world.tissue()->volume_cells(), world.tissue()->surface(),
                                                          nodes, in.rod->section.radius);
        const auto split = collision::split_by_tracts(inside, pierced);
        metrics["suture_nodes_inside_tissue"] = split.outside_tracts;
        metrics["suture_penetration_depth"]   = split.depth;
        metrics["suture_nodes_in_tracts"]     = split.in_tracts;
      }
    for (std::size_t k = 0; k < tool_ends.size(); ++k)
      metrics[tool_ends[k].name + "_force_magnitude"] = world.tool_forces()[first_end_tool + k].force.norm();
    if (needle)
      needle->finish(world, summary);
    for (const auto &[name, index] : probes)
      {
        const auto u = world.probe_displacement(index);
        for (int d = 0; d < 3; ++d)
          metrics[name + "_displacement_" + std::string(1, char('x' + d))] = u[d];
      }
    std::cout << "suturesim: " << stats.steps << " steps, step time median " << stats.median_us
              << " us, p99 " << stats.p99_us << " us, max " << stats.max_us << " us, "
              << stats.deadline_misses << " deadline misses (" << stats.deadline_us << " us)\n";
    if (!failure.empty())
      throw SolverError(failure + "; outputs hold the last good state (t = " +
                        std::to_string(world.time()) + " s)");
  }
} // namespace suturesim::scene
