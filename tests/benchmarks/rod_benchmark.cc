// Cosserat rod and sphere tree timings (issue 3):
//  - one Newton iteration (assembly of residual and tangent + block-tridiagonal solve)
//    for N = 16 ... 1024 elements; the per-element time shows O(N);
//  - bottom-up refit (seed 000, Algorithm 1) against a full rebuild at 512 and 4096
//    segments, every point moved.
// Run: build/tests/benchmarks/rod_benchmark --benchmark_repetitions=5
//        --benchmark_report_aggregates_only=true
// ("s_per_element" is the iteration time divided by N.)
#include <suturesim/collision/sphere_tree.h>
#include <suturesim/rod/rod_model.h>

#include <benchmark/benchmark.h>

using namespace suturesim;
using rod::Quat;
using rod::Vec3;

namespace
{
  rod::RodModel
  bent_rod(const int N)
  {
    std::vector<Vec3> x;
    std::vector<Quat> q;
    for (int i = 0; i <= N; ++i)
      {
        x.emplace_back(0.1 * i / N, 0.001 * std::sin(0.1 * i), 0);
        q.push_back(rod::quaternion_exp(Vec3(0.01 * i, 0, 0.02)));
      }
    rod::SectionStiffness s;
    s.force << 100, 40, 40;
    s.moment << 1e-4, 2e-4, 2e-4;
    rod::RodModel model(x, q, s, 1e-4, Vec3(1e-12, 1e-12, 1e-12));
    model.constrain(0, {{true, true, true, true, true, true}});
    model.forces().back() = Vec3(0, -0.1, 0);
    return model;
  }

  void
  NewtonIteration(benchmark::State &state)
  {
    const int     N     = state.range(0);
    rod::RodModel model = bent_rod(N);
    for (auto _ : state)
      benchmark::DoNotOptimize(model.newton_direction());
    state.counters["s_per_element"] = benchmark::Counter(
      static_cast<double>(N) * state.iterations(),
      benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  }
  BENCHMARK(NewtonIteration)->RangeMultiplier(2)->Range(16, 1024)->Unit(benchmark::kMicrosecond);

  std::vector<Eigen::Vector3d>
  chain(const int n, const double phase)
  {
    std::vector<Eigen::Vector3d> p;
    for (int i = 0; i <= n; ++i)
      p.emplace_back(std::cos(0.01 * i + phase), std::sin(0.013 * i), 0.001 * i);
    return p;
  }

  void
  SphereTreeRefit(benchmark::State &state)
  {
    const int             n = state.range(0);
    collision::SphereTree tree;
    tree.build(chain(n, 0), 1e-4);
    const auto a = chain(n, 0.1), b = chain(n, 0.2);
    bool       flip = false;
    for (auto _ : state)
      {
        benchmark::DoNotOptimize(tree.refit((flip = !flip) ? a : b));
      }
  }
  BENCHMARK(SphereTreeRefit)->Arg(512)->Arg(4096)->Unit(benchmark::kMicrosecond);

  void
  SphereTreeRebuild(benchmark::State &state)
  {
    const int             n = state.range(0);
    collision::SphereTree tree;
    const auto            a = chain(n, 0.1), b = chain(n, 0.2);
    bool                  flip = false;
    for (auto _ : state)
      {
        tree.build((flip = !flip) ? a : b, 1e-4);
        benchmark::DoNotOptimize(tree.spheres().data());
      }
  }
  BENCHMARK(SphereTreeRebuild)->Arg(512)->Arg(4096)->Unit(benchmark::kMicrosecond);
} // namespace

BENCHMARK_MAIN();
