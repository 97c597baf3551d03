// Realtime-path kernels (README, "Realtime path"): the spring-force kernel in ns per
// spring beside a memory-bandwidth probe measured in the same binary, the XPBD volume
// sweep in ns per tetrahedron, the whole haptic tick on a seed-004-scale block, the FTL
// and XPBD suture steps at 50, 512 and 4096 nodes, and bounding-sphere refit against
// rebuild.
// Plain C++ + Eigen: links the realtime library only.
#include <suturesim/collision/triangle_sphere_tree.h>
#include <suturesim/core/background_writer.h>
#include <suturesim/core/worker_team.h>
#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/tissue_model.h>
#include <suturesim/realtime/volume_constraints.h>
#include <suturesim/realtime/world.h>

#include <benchmark/benchmark.h>

#include "realtime/test_meshes.h"
#include "realtime/test_worlds.h"

#include <atomic>
#include <chrono>
#include <cmath>
#include <numeric>
#include <random>

using namespace suturesim;
using namespace suturesim::realtime;

namespace
{
  /// Sustained read+write bandwidth (bytes/s) of a STREAM-like triad over 3 × 128 MB,
  /// the best of five passes: the bound a streaming kernel can reach on this machine.
  double
  triad_bandwidth()
  {
    static const double bandwidth = [] {
      const std::size_t   n = std::size_t(16) << 20;
      std::vector<double> a(n, 1.0), b(n, 2.0), c(n, 0.0);
      double              best = 0;
      for (int pass = 0; pass < 5; ++pass)
        {
          const auto start = std::chrono::steady_clock::now();
          for (std::size_t i = 0; i < n; ++i)
            c[i] = a[i] + 3.0 * b[i];
          const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
          benchmark::DoNotOptimize(c.data());
          best = std::max(best, 3.0 * sizeof(double) * n / seconds);
        }
      return best;
    }();
    return bandwidth;
  }

  /// A cubic lattice with its three axis springs per node: about @p n springs, in the
  /// order SpringSet::sort() gives the tissue models.
  void
  lattice(const std::size_t n, Matrix3Xd &x, SpringSet &springs)
  {
    const auto side = static_cast<std::uint32_t>(std::ceil(std::cbrt(n / 3.0))) + 1;
    x.resize(3, std::size_t(side) * side * side);
    std::mt19937                           rng(1);
    std::uniform_real_distribution<double> u(-0.1, 0.1);
    const auto index = [&](std::uint32_t i, std::uint32_t j, std::uint32_t k) { return i + side * (j + side * k); };
    for (std::uint32_t k = 0; k < side; ++k)
      for (std::uint32_t j = 0; j < side; ++j)
        for (std::uint32_t i = 0; i < side; ++i)
          x.col(index(i, j, k)) << i + u(rng), j + u(rng), k + u(rng);
    for (std::uint32_t k = 0; k < side; ++k)
      for (std::uint32_t j = 0; j < side; ++j)
        for (std::uint32_t i = 0; i < side; ++i)
          {
            if (i + 1 < side)
              springs.add(index(i, j, k), index(i + 1, j, k), 1.0, 1.0);
            if (j + 1 < side)
              springs.add(index(i, j, k), index(i, j + 1, k), 1.0, 1.0);
            if (k + 1 < side)
              springs.add(index(i, j, k), index(i, j, k + 1), 1.0, 1.0);
          }
    springs.sort();
  }

  void
  SpringForces(benchmark::State &state)
  {
    SpringSet springs("lattice");
    Matrix3Xd x;
    lattice(state.range(0), x, springs);
    Matrix3Xd  f     = Matrix3Xd::Zero(3, x.cols());
    const auto start = std::chrono::steady_clock::now();
    for (auto _ : state)
      {
        springs.add_forces(x, f);
        benchmark::DoNotOptimize(f.data());
        benchmark::ClobberMemory();
      }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const double n       = springs.size();
    const double ns      = seconds / (n * state.iterations()) * 1e9;
    // Bytes per spring from memory when nothing is cached: two 4-byte ends, rest length
    // and stiffness streamed (24), both ends' positions read (48) and forces read and
    // written (96): the bound of a kernel that waits only for memory.
    const double bandwidth          = triad_bandwidth();
    const double bound              = (24 + 48 + 96) / bandwidth * 1e9;
    state.counters["springs"]       = n;
    state.counters["ns_per_spring"] = ns;
    state.counters["bandwidth_GBps"] = bandwidth * 1e-9;
    state.counters["bound_ns"]      = bound;
    state.counters["ratio_to_bound"] = ns / bound;
  }
  BENCHMARK(SpringForces)->Arg(10000)->Arg(1000000)->Unit(benchmark::kMicrosecond);

  /// The same springs as XPBD distance constraints: one Gauss–Seidel sweep.
  void
  SpringProjection(benchmark::State &state)
  {
    SpringSet springs("lattice");
    Matrix3Xd x;
    lattice(state.range(0), x, springs);
    const VectorXd w = VectorXd::Ones(x.cols());
    springs.prepare_projection(1e-3);
    const auto start = std::chrono::steady_clock::now();
    for (auto _ : state)
      {
        springs.project(x, w, 1e-3);
        benchmark::DoNotOptimize(x.data());
      }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.counters["ns_per_spring"] = seconds / (double(springs.size()) * state.iterations()) * 1e9;
  }
  BENCHMARK(SpringProjection)->Arg(10000)->Arg(1000000)->Unit(benchmark::kMicrosecond);

  /// One XPBD sweep over the volume constraints of a box of @p n × @p n × n/4 cubes, six
  /// tetrahedra each (18: 7 776 tetrahedra, the seed-004-scale block's size; 100:
  /// 1.5 million, far beyond the caches), ns per tetrahedron.
  void
  VolumeProjection(benchmark::State &state)
  {
    const auto                 n    = static_cast<unsigned>(state.range(0));
    const auto                 mesh = test_support::box_mesh(0.04, 0.04, 0.01, n, n, std::max(1u, n / 4));
    std::vector<std::uint32_t> node(mesh.vertices.cols());
    std::iota(node.begin(), node.end(), 0u);
    VolumeConstraints volumes;
    volumes.add_mesh(mesh, node, 1e5);
    Matrix3Xd      x = mesh.vertices;
    const VectorXd w = VectorXd::Ones(x.cols());
    volumes.prepare_projection(1e-3);
    const auto start = std::chrono::steady_clock::now();
    for (auto _ : state)
      {
        volumes.project(x, w, 1e-3);
        benchmark::DoNotOptimize(x.data());
      }
    const double seconds         = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.counters["tetrahedra"] = volumes.size();
    state.counters["ns_per_tet"] = seconds / (double(volumes.size()) * state.iterations()) * 1e9;
  }
  BENCHMARK(VolumeProjection)->Arg(18)->Arg(100)->Unit(benchmark::kMicrosecond);

  /// The haptic thread's whole tick on a block of the seed-004-scale benchmark's size
  /// (a 18 × 18 × 4 box: 1 805 nodes, 7 776 tetrahedra, its bottom fixed) under a
  /// 100-node suture folded onto itself, grasped at its end and dragged: the step (XPBD,
  /// one tissue sweep and eight over the suture and contacts, contact and seed 002's
  /// self-collision on), the bottom's reaction and the row handed to the writer thread,
  /// which formats nothing here (its sink only counts). XPBD against vertex block descent
  /// on the tissue (vbd_integrator.cc), both with XPBD's eight suture sweeps.
  void
  HapticTick(benchmark::State &state, const std::string &integrator, const std::map<std::string, std::string> &values,
             const std::string &tissue = "volume", const std::map<std::string, std::string> &tissue_values = {})
  {
    const auto mesh = test_support::box_mesh(0.04, 0.04, 0.01, 18, 18, 4);
    auto       setup = test_support::block_under_folded_suture(mesh, tissue, integrator, values, "xpbd-rod",
                                                                "transient-constraint", 99, tissue_values);
    setup.substeps       = 1; // as the seed-004-scale scene: one step a tick
    World world(std::move(setup));
    const auto bottom = mesh::vertices_with_tag(mesh::extract_boundary(mesh), 1);
    world.fix_vertices(bottom);
    const auto s = world.system().suture;
    world.add_tool("grasper", {s.end - 1}, {world.system().nodes.x.col(s.end - 1)});
    world.initialize();
    auto                    reaction = world.reaction_set(world.nodes_of_vertices(bottom));
    std::atomic<std::size_t> written{0};
    struct NoState
    {};
    BackgroundWriter<NoState> writer(4, 16384, NoState{}, 1,
                                     {[&written](const double *) { ++written; }, [](const NoState &) {}, [] {}});
    std::vector<ToolPose> poses(1);
    poses[0].position = world.system().nodes.x.col(s.end - 1);
    double row[4]     = {};
    for (auto _ : state)
      {
        poses[0].position += Vector3d(-2e-6, 1e-6, 0);
        world.step(poses);
        const Vector3d r = world.reaction(reaction);
        row[0]           = world.time();
        row[1] = r[0], row[2] = r[1], row[3] = r[2];
        writer.push_row(row);
      }
    writer.finish();
    state.counters["nodes"]        = world.system().nodes.size();
    state.counters["contacts"]     = world.surface_contact()->active();
    state.counters["rows_dropped"] = writer.rows_dropped();
  }
  BENCHMARK_CAPTURE(HapticTick, xpbd_1_plus_8, std::string("xpbd"),
                    std::map<std::string, std::string>{{"Iterations", "1"}, {"Suture iterations", "8"}})
    ->Unit(benchmark::kMicrosecond);
  BENCHMARK_CAPTURE(HapticTick, vbd_1_plus_8, std::string("vbd"),
                    std::map<std::string, std::string>{{"Iterations", "1"}, {"Suture iterations", "8"}})
    ->Unit(benchmark::kMicrosecond);
  // the finite-element tissue (Tissue model = fe: neo-Hookean tetrahedra) under the same
  // step: its ratio to vbd_1_plus_8 is what elements cost over springs and volumes
  BENCHMARK_CAPTURE(HapticTick, vbd_1_plus_8_fe, std::string("vbd"),
                    std::map<std::string, std::string>{{"Iterations", "1"}, {"Suture iterations", "8"}},
                    std::string("fe"))
    ->Unit(benchmark::kMicrosecond);
  // its bulk term on the nodes' patches (nodal_volumes.h): the ratio to vbd_1_plus_8_fe
  // is what the averaging costs
  BENCHMARK_CAPTURE(HapticTick, vbd_1_plus_8_fe_nodal, std::string("vbd"),
                    std::map<std::string, std::string>{{"Iterations", "1"}, {"Suture iterations", "8"}},
                    std::string("fe"), std::map<std::string, std::string>{{"Volumetric energy", "nodal"}})
    ->Unit(benchmark::kMicrosecond);
  // the descent's colours shared by two threads (vbd_integrator.cc): the ratios to the
  // one-thread ticks above are what the second core saves (wall time: the helper's CPU
  // time is not the tick's)
  BENCHMARK_CAPTURE(HapticTick, vbd_1_plus_8_2_threads, std::string("vbd"),
                    std::map<std::string, std::string>{{"Iterations", "1"}, {"Suture iterations", "8"}, {"Threads", "2"}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
  BENCHMARK_CAPTURE(HapticTick, vbd_1_plus_8_fe_2_threads, std::string("vbd"),
                    std::map<std::string, std::string>{{"Iterations", "1"}, {"Suture iterations", "8"}, {"Threads", "2"}},
                    std::string("fe"))
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
  BENCHMARK_CAPTURE(HapticTick, vbd_1_plus_8_fe_nodal_2_threads, std::string("vbd"),
                    std::map<std::string, std::string>{{"Iterations", "1"}, {"Suture iterations", "8"}, {"Threads", "2"}},
                    std::string("fe"), std::map<std::string, std::string>{{"Volumetric energy", "nodal"}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
  // the warm start, then also on two threads (slab_sweep.h): the ratios to xpbd_1_plus_8
  // are what the two cost and save
  BENCHMARK_CAPTURE(HapticTick, xpbd_1_plus_8_warm, std::string("xpbd"),
                    std::map<std::string, std::string>{{"Iterations", "1"}, {"Suture iterations", "8"}, {"Warm start", "true"}})
    ->Unit(benchmark::kMicrosecond);
  BENCHMARK_CAPTURE(HapticTick, xpbd_1_plus_8_warm_2_threads, std::string("xpbd"),
                    std::map<std::string, std::string>{
                      {"Iterations", "1"}, {"Suture iterations", "8"}, {"Warm start", "true"}, {"Threads", "2"}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();
  // the seed-004-scale scene's setting: the haptic thread's slab the larger, since the
  // helper finds the contacts before it sweeps its own
  BENCHMARK_CAPTURE(HapticTick, xpbd_1_plus_8_warm_2_threads_share_0_65, std::string("xpbd"),
                    std::map<std::string, std::string>{{"Iterations", "1"},
                                                       {"Suture iterations", "8"},
                                                       {"Warm start", "true"},
                                                       {"Threads", "2"},
                                                       {"Slab share", "0.65"}})
    ->Unit(benchmark::kMicrosecond)
    ->UseRealTime();

  /// One hand-over of core/worker_team.h (Threads = 2 makes one per tissue sweep and one
  /// for the contact detection): the caller and its helper each run an empty part.
  void
  WorkerTeamHandOver(benchmark::State &state)
  {
    WorkerTeam team(2);
    int        parts[2] = {};
    for (auto _ : state)
      team.run([&](const unsigned t) { benchmark::DoNotOptimize(++parts[t]); });
  }
  BENCHMARK(WorkerTeamHandOver)->Unit(benchmark::kMicrosecond)->UseRealTime();

  /// One haptic step of a suture alone, its end moved by a tool on a circle.
  void
  SutureStep(benchmark::State &state, const std::string &suture, const std::string &integrator)
  {
    const auto nodes = static_cast<unsigned>(state.range(0));
    WorldSetup w;
    w.suture = test_support::make_model<SutureModel::Registry>(suture);
    // a 3-0 suture, 0.5 mm per link
    w.suture_geometry = test_support::straight_suture(nodes - 1, 5e-4 * (nodes - 1), Vector3d::Zero(),
                                                      Vector3d::UnitX(), 118, 3.7e-7, 1.12e-4, 1140);
    w.integrator = test_support::make_model<Integrator::Registry>(integrator, integrator == "xpbd"
                                                                                ? std::map<std::string, std::string>{{"Iterations", "10"}}
                                                                                : std::map<std::string, std::string>{});
    w.gravity = Vector3d(0, 0, -9.81);
    World world(std::move(w));
    const auto end = world.system().suture.end - 1;
    world.add_tool("grasper", {end}, {world.system().nodes.x.col(end)});
    world.initialize();
    std::vector<ToolPose> pose(1);
    const Vector3d        start = world.system().nodes.x.col(end);
    double                phase = 0;
    for (auto _ : state)
      {
        phase += 1e-3;
        pose[0].position = start + 0.01 * Vector3d(std::cos(phase) - 1, std::sin(phase), 0);
        benchmark::DoNotOptimize(world.step(pose).data());
      }
    state.counters["nodes"] = nodes;
  }
  BENCHMARK_CAPTURE(SutureStep, ftl, std::string("ftl"), std::string("quasi-static"))
    ->Arg(50)->Arg(512)->Arg(4096)->Unit(benchmark::kMicrosecond);
  BENCHMARK_CAPTURE(SutureStep, xpbd_rod_10_iterations, std::string("xpbd-rod"), std::string("xpbd"))
    ->Arg(50)->Arg(512)->Arg(4096)->Unit(benchmark::kMicrosecond);

  /// The tissue-surface tree of a box of about @p n triangles under a moving deformation.
  struct SurfaceTree
  {
    mesh::SimplexMesh           mesh;
    std::vector<mesh::Triangle> triangles;
    Matrix3Xd                   x;
    explicit SurfaceTree(const unsigned cells)
      : mesh(test_support::box_mesh(1, 1, 0.25, cells, cells, std::max(1u, cells / 4)))
      , triangles(mesh::extract_boundary(mesh).triangles)
      , x(mesh.vertices)
    {}
    void
    deform(const double t)
    {
      for (Eigen::Index v = 0; v < x.cols(); ++v)
        x.col(v) = mesh.vertices.col(v) + 0.05 * std::sin(t + 3 * mesh.vertices(0, v)) * Vector3d::UnitZ();
    }
  };

  void
  TriangleTreeRefit(benchmark::State &state)
  {
    SurfaceTree                   s(state.range(0));
    collision::TriangleSphereTree tree;
    tree.build(s.x, s.triangles, 1e-3);
    double t = 0;
    for (auto _ : state)
      {
        state.PauseTiming();
        s.deform(t += 0.01);
        state.ResumeTiming();
        tree.refit(s.x);
        benchmark::DoNotOptimize(tree.spheres().data());
      }
    state.counters["triangles"] = s.triangles.size();
  }
  BENCHMARK(TriangleTreeRefit)->Arg(8)->Arg(32)->Unit(benchmark::kMicrosecond);

  /// The lazy refit the realtime contact uses (TriangleSphereTree::update) under the same
  /// motion: every vertex moves by up to 5e-4 of the block per call, the slack is a tenth
  /// of an element (0.0125), so a vertex escapes about every 25 calls.
  void
  TriangleTreeUpdate(benchmark::State &state)
  {
    SurfaceTree                   s(state.range(0));
    collision::TriangleSphereTree tree;
    tree.build(s.x, s.triangles, 1e-3);
    const double slack = 0.1 / state.range(0);
    tree.update(s.x, slack);
    double t = 0;
    for (auto _ : state)
      {
        state.PauseTiming();
        s.deform(t += 0.01);
        state.ResumeTiming();
        tree.update(s.x, slack);
        benchmark::DoNotOptimize(tree.spheres().data());
      }
    state.counters["triangles"] = s.triangles.size();
  }
  BENCHMARK(TriangleTreeUpdate)->Arg(8)->Arg(32)->Unit(benchmark::kMicrosecond);

  void
  TriangleTreeRebuild(benchmark::State &state)
  {
    SurfaceTree s(state.range(0));
    double      t = 0;
    for (auto _ : state)
      {
        state.PauseTiming();
        s.deform(t += 0.01);
        state.ResumeTiming();
        collision::TriangleSphereTree tree;
        tree.build(s.x, s.triangles, 1e-3);
        benchmark::DoNotOptimize(tree.spheres().data());
      }
    state.counters["triangles"] = s.triangles.size();
  }
  BENCHMARK(TriangleTreeRebuild)->Arg(8)->Arg(32)->Unit(benchmark::kMicrosecond);

  /// Seed 002's subdivision event on the surface model of an n × n × 3 box (the topology
  /// change alone: the World then rebuilds the surface's two sphere trees, see
  /// TriangleTreeRebuild, and estimates the step's limit again). Each iteration
  /// subdivides another triangle of the top, about a node's two neighbours' worth of
  /// linear searches over the triangles and springs.
  void
  SurfaceSubdivisionEvent(benchmark::State &state)
  {
    const auto n        = static_cast<unsigned>(state.range(0));
    const auto mesh     = test_support::box_mesh(0.04, 0.04, 0.01, n, n, 3);
    const auto boundary = mesh::extract_boundary(mesh);
    const auto capacity = std::to_string(4096);
    std::unique_ptr<TissueModel> model;
    System                       s;
    const auto                   rebuild = [&]() {
      s     = System();
      model = test_support::make_model<TissueModel::Registry>("surface", {{"Subdivision capacity", capacity}});
      model->build(s, mesh, boundary, TissueMaterial{1e5, 0.3, 1100, {}}, false);
    };
    rebuild();
    std::vector<std::uint32_t> top;
    for (std::uint32_t t = 0; t < boundary.triangles.size(); ++t)
      if (boundary.tags[t] == 2)
        top.push_back(t);
    std::size_t next = 0;
    for (auto _ : state)
      {
        if (next == top.size())
          {
            state.PauseTiming();
            rebuild();
            next = 0;
            state.ResumeTiming();
          }
        benchmark::DoNotOptimize(model->subdivide(s, top[next++], Eigen::Vector3d(0.2, 0.3, 0.5)));
      }
    state.counters["triangles"] = boundary.triangles.size();
  }
  BENCHMARK(SurfaceSubdivisionEvent)->Arg(8)->Arg(32)->Unit(benchmark::kMicrosecond);
} // namespace

BENCHMARK_MAIN();
