// Accurate tissue solver cost: a neo-Hookean block (Q2, mixed u-p-J, nu = 0.45, bottom
// fixed, top pressed down 10 % in two load steps) at about 1e4 and 1e5 DoFs, with the
// direct (MUMPS Cholesky) and the AMG-CG (PETSc GAMG, rigid-body near null space)
// linear solvers. Counters per run:
//   dofs, newton_per_step          Newton iterations per load step
//   assembly_us_per_cell           one K and R assembly divided by the cells
//   solve_s_per_newton             linear-solve wall time per Newton iteration
//   us_core_per_dof_newton         (assembly + solve) per iteration × cores / DoFs
//                                  (anchor: ~200 µs·core/DoF, Davydov et al. 2020)
//   peak_rss_MB                    peak resident memory of the process so far: run one
//                                  case per process for a clean figure (README).
// cell_assembly times one cell's residual and tangent (CellAssembler::assemble) on a
// distorted hexahedron at a finite strain: the kernel of every Newton iteration, without
// the global matrix, so its time is the time per cell.
// Run: build/tests/benchmarks/tissue_benchmark --benchmark_filter=...
#include <suturesim/core/blas_threads.h>
#include <suturesim/core/mpi_session.h>
#include <suturesim/io/recorder.h>
#include <suturesim/core/parameter_file.h>
#include <suturesim/scene/simulation.h>
#include <suturesim/tissue/cell_assembler.h>

#include "unit/distorted_cell.h"

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/mapping_q1.h>

#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <sstream>

using namespace suturesim;

namespace
{
  std::string
  block_scene(const int n, const std::string &method)
  {
    std::ostringstream s;
    s << "set Scene name = benchmark_block\n"
         "subsection Mesh\n set Source = deal.II\n"
         " set Generator = subdivided_hyper_rectangle\n"
         " set Generator arguments = "
      << n << ", " << n << ", " << n
      << " : 0, 0, 0 : 0.01, 0.01, 0.01 : true\nend\n"
         "subsection Tissue\n set Element degree = 2\n set Formulation = mixed\n"
         " subsection Material\n  set Poisson ratio = 0.45\n end\n"
         " subsection Boundary conditions\n  set Fixed = 4\n"
         "  set Prescribed displacement = 5\n"
         "  subsection Prescribed displacement function\n"
         "   set Function expression = 0; 0; -0.001 * t\n  end\n end\n"
         " subsection Linear solver\n  set Method = "
      << method << "\n  set Relative tolerance = 1e-8\n end\nend\n"
         "subsection Time\n set End time = 1\n set Step size = 0.5\n"
         " set Output interval = 10\nend\n";
    return s.str();
  }

  void
  run_block(benchmark::State &state, const std::string &method)
  {
    const int n = static_cast<int>(state.range(0));
    for (auto _ : state)
      {
        dealii::ParameterHandler prm;
        scene::Simulation::declare_parameters(prm);
        ParameterFile file(prm, block_scene(n, method), "benchmark.prm", ".");
        scene::Simulation    simulation(prm, file);
        const std::string    dir =
          (std::filesystem::temp_directory_path() / "suturesim_benchmark").string();
        io::Recorder recorder(dir, MPI_COMM_WORLD);
        std::streambuf *cout_buffer = std::cout.rdbuf(nullptr); // keep the report clean
        simulation.run(recorder);
        std::cout.rdbuf(cout_buffer);

        const auto &summary = recorder.summary();
        double      newton = 0, assembly = 0, solve = 0, linear_its = 0;
        unsigned    steps  = 0;
        for (const auto &step : summary["steps"])
          if (step["newton_iterations"].get<unsigned>() > 0)
            {
              ++steps;
              newton += step["newton_iterations"].get<double>();
              assembly += step["assembly_seconds"].get<double>();
              solve += step["solve_seconds"].get<double>();
              linear_its += step["linear_iterations"].get<double>();
            }
        const double cells     = summary["mesh"]["cells"].get<double>();
        const double dofs      = summary["mesh"]["dofs"].get<double>();
        const double ranks     = dealii::Utilities::MPI::n_mpi_processes(MPI_COMM_WORLD);
        // assemblies = Newton iterations + one per step (the initial residual)
        const double assemblies = newton + steps;
        state.counters["dofs"]                 = dofs;
        state.counters["newton_per_step"]      = newton / steps;
        state.counters["assembly_us_per_cell"] = 1e6 * assembly / assemblies / cells;
        state.counters["solve_s_per_newton"]   = solve / newton;
        state.counters["krylov_its_per_newton"] = linear_its / newton;
        state.counters["us_core_per_dof_newton"] =
          1e6 * (assembly / assemblies + solve / newton) * ranks / dofs;
        rusage usage;
        getrusage(RUSAGE_SELF, &usage);
        state.counters["peak_rss_MB"] = usage.ru_maxrss / 1024.0;
      }
  }

  /// Arguments: element degree, pressure degree (mixed, Newton-unknown update).
  void
  cell_assembly(benchmark::State &state)
  {
    using namespace dealii;
    const unsigned     degree = static_cast<unsigned>(state.range(0));
    Triangulation<3>   tria;
    testing::distorted_cube(tria);
    FESystem<3>   fe(FE_Q<3>(degree), 3);
    DoFHandler<3> dofs(tria);
    dofs.distribute_dofs(fe);
    MappingQ1<3>            mapping;
    tissue::CellAssembler   assembler(mapping, fe, QGauss<3>(degree + 1), true,
                                      static_cast<unsigned>(state.range(1)));
    const tissue::Material  material = testing::mooney_rivlin(0.45);
    const unsigned          n        = fe.n_dofs_per_cell();
    dealii::Vector<double>  u(n), r(n);
    FullMatrix<double>      K(n, n);
    for (unsigned i = 0; i < n; ++i) // about 5 % strain
      u[i] = 5e-4 * std::sin(1.7 * i + 0.3);
    tissue::MixedCell fields;
    const auto        cell = dofs.begin_active();
    assembler.assemble(cell, u, material, {}, r, &K, &fields, tissue::MixedUpdate::exact);
    for (auto _ : state)
      {
        assembler.assemble(cell, u, material, {}, r, &K, &fields, tissue::MixedUpdate::newton);
        benchmark::DoNotOptimize(K(0, 0));
      }
  }
} // namespace

BENCHMARK(cell_assembly)->Args({1, 0})->Args({2, 1})->Unit(benchmark::kMicrosecond);
BENCHMARK_CAPTURE(run_block, direct, std::string("direct"))
  ->Arg(8)
  ->Arg(16)
  ->Iterations(1)
  ->Unit(benchmark::kSecond)
  ->UseRealTime();
BENCHMARK_CAPTURE(run_block, amg_cg, std::string("cg"))
  ->Arg(8)
  ->Arg(16)
  ->Iterations(1)
  ->Unit(benchmark::kSecond)
  ->UseRealTime();

int
main(int argc, char **argv)
{
  suturesim::select_blas_kernels(argv); // timed on the kernels the program uses
  const suturesim::MpiSession mpi(argc, argv); // as the program starts MPI
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
