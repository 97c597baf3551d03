// AT1 phase-field fracture (issue 29, item 5) on homogeneous states, where the damage is
// known in closed form: a block stretched uniaxially (plane strain in 2-D, the lateral
// faces held in 3-D) to an undamaged energy density ψ0 has
//   d = 0 while ψ0 ≤ ψ_c = 3 G_c / (16 ℓ), and d = 1 − ψ_c / ψ0 above it,
// whatever the mesh: so the elastic phase (the bound d ≥ 0 active), the damage law, the
// irreversibility (d ≥ the accepted d when unloaded) and hanging nodes (their rows hold
// their constraints in the bound-constrained solve) are each checked to round-off. The
// energies follow: g(d) ψ0 |Ω| and G_c / c_w · d / ℓ · |Ω|.
#include <suturesim/core/error.h>
#include <suturesim/tearing/phase_field.h>

#include "run_scene.h"

#include <deal.II/grid/grid_generator.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

using namespace suturesim;
using namespace dealii;

namespace
{
  tearing::PhaseFieldParameters
  material()
  {
    tearing::PhaseFieldParameters p;
    p.youngs_modulus = 6.5e6;
    p.poissons_ratio = 0.3;
    p.toughness      = 1.1e3;
    p.length         = 1e-3;
    p.tolerance      = 1e-10;
    return p;
  }

  /// A unit-length block of side L, stretched by the load (m) along y with the faces
  /// x = 0, y = 0 (and both z faces in 3-D) on rollers; one corner cell refined when
  /// @p hanging, so that hanging nodes are present.
  template <int dim>
  struct Block
  {
    static constexpr double L = 0.01;
    parallel::distributed::Triangulation<dim> tria{MPI_COMM_WORLD};
    std::unique_ptr<tearing::PhaseFieldFracture<dim>> model;

    explicit Block(const bool hanging)
    {
      GridGenerator::hyper_cube(tria, 0, L, true); // ids: x-, x+, y-, y+, z-, z+
      tria.refine_global(2);
      if (hanging)
        {
          for (const auto &cell : tria.active_cell_iterators())
            if (cell->is_locally_owned() && cell->center().norm() < 0.3 * L)
              cell->set_refine_flag();
          tria.execute_coarsening_and_refinement();
        }
      typename tearing::PhaseFieldFracture<dim>::Loading loading;
      std::vector<bool> x(dim, false), y(dim, false), z(dim, false);
      x[0] = true;
      y[1] = true;
      z[dim - 1] = true;
      Tensor<1, dim> stretch;
      stretch[1] = L; // load = the strain ε_yy
      loading.supports = {{0, ComponentMask(x)}, {2, ComponentMask(y)}, {3, ComponentMask(y), stretch}};
      if (dim == 3) // uniaxial strain: every lateral face held
        for (const auto &[face, mask] : {std::pair{1, x}, {4, z}, {5, z}})
          loading.supports.push_back({static_cast<types::boundary_id>(face), ComponentMask(mask)});
      model = std::make_unique<tearing::PhaseFieldFracture<dim>>(MPI_COMM_WORLD, material(), tria, loading);
    }

    /// ψ0 of the strain ε_yy = @p strain: uniaxial strain in 3-D (all lateral faces
    /// held), uniaxial stress in plane strain in 2-D.
    static double
    energy_density(const double strain)
    {
      const auto   p = material();
      const double E = p.youngs_modulus, nu = p.poissons_ratio;
      const double modulus = dim == 2 ? E / (1 - nu * nu) : E * (1 - nu) / ((1 + nu) * (1 - 2 * nu));
      return 0.5 * modulus * strain * strain;
    }

    /// The strain at which ψ0 = @p ratio × ψ_c.
    double
    strain_at(const double ratio) const
    {
      return std::sqrt(ratio * model->damage_threshold() / energy_density(1.0));
    }

  };

  /// The damage at every node is @p expected (to 1e-9).
  template <int dim>
  void
  expect_uniform(const Block<dim> &block, const double expected)
  {
    const auto [lo, hi] = block.model->damage_range();
    EXPECT_NEAR(lo, expected, 1e-9);
    EXPECT_NEAR(hi, expected, 1e-9);
  }

  template <int dim>
  void
  check_homogeneous_states(const bool hanging)
  {
    Block<dim>   block(hanging);
    auto        &model  = *block.model;
    const double volume = std::pow(Block<dim>::L, dim);
    const double psi_c  = model.damage_threshold();
    EXPECT_NEAR(psi_c, 3 * 1.1e3 / (16 * 1e-3), 1e-9);

    // the elastic phase: ψ0 = ψ_c / 2, no damage
    auto step = model.solve(block.strain_at(0.5));
    EXPECT_TRUE(step.converged);
    expect_uniform(block, 0.0);
    EXPECT_NEAR(model.elastic_energy(), (1 + 1e-6) * 0.5 * psi_c * volume, 1e-9 * psi_c * volume);
    EXPECT_NEAR(model.fracture_energy(), 0, 1e-12);
    model.accept();

    // above the limit: d = 1 − ψ_c / ψ0
    for (const double ratio : {2.0, 4.0})
      {
        step = model.solve(block.strain_at(ratio));
        EXPECT_TRUE(step.converged);
        const double d = 1 - 1 / ratio;
        expect_uniform(block, d);
        const double g = (1 - d) * (1 - d) + 1e-6;
        EXPECT_NEAR(model.elastic_energy(), g * ratio * psi_c * volume, 1e-8 * psi_c * volume);
        EXPECT_NEAR(model.fracture_energy(), 1.1e3 / (8.0 / 3.0) * d / 1e-3 * volume, 1e-8 * psi_c * volume);
        model.accept();
      }

    // unloaded to ψ0 = 2 ψ_c, the damage of 4 ψ_c stays (irreversibility)
    step = model.solve(block.strain_at(2.0));
    EXPECT_TRUE(step.converged);
    expect_uniform(block, 0.75);

    // restore() returns to the accepted state
    model.solve(block.strain_at(9.0));
    expect_uniform(block, 1 - 1 / 9.0);
    model.restore();
    expect_uniform(block, 0.75);
  }
} // namespace

TEST(PhaseField, HomogeneousStretchDamagesAsTheClosedFormIn2D)
{
  check_homogeneous_states<2>(false);
}

TEST(PhaseField, HomogeneousStretchDamagesAsTheClosedFormWithHangingNodes)
{
  check_homogeneous_states<2>(true);
  check_homogeneous_states<3>(true);
}

TEST(PhaseField, EffectiveToughnessIsBourdinsCorrection)
{
  Block<2> block(false);
  // G_c (1 + 3 h / (8 ℓ)) (Bourdin, Francfort & Marigo 2008, §8.1.1, AT1)
  EXPECT_DOUBLE_EQ(block.model->effective_toughness(2e-4), 1.1e3 * (1 + 3 * 2e-4 / (8 * 1e-3)));
  EXPECT_NEAR(block.model->smallest_cell_size(), Block<2>::L / 4, 1e-15);
}

// benchmarks/sent_phase_field at half its a/l (a/l = 25, l/h = 3.84 as shipped, a coarser
// bisection; 90 s instead of the shipped scene's 5-14 min): the critical traction of the
// single-edge-notched plate within the 5 % of LEFM with the discretised
// toughness (reference.json; measured -3.3 % here, -0.8 % at the shipped a/l = 50); the
// bracket holds it, the crack ran from the notch along the ligament.
TEST(PhaseField, SingleEdgeNotchedTensionBreaksAtTheLefmLoad)
{
  using namespace suturesim::test_support;
  const auto ref = benchmark_reference("sent_phase_field");
  const auto run = run_suturesim(
    "sent_phase_field",
    {benchmark_scene("sent_phase_field"), "--set", "Fracture specimen/Internal length=1.2e-4", "--set",
     "Fracture specimen/Path refinements=5", "--set", "Fracture specimen/Path half-width=4e-4", "--set",
     "Fracture specimen/Load increment=4e4", "--set", "Fracture specimen/Bisection tolerance=1e-2", "--set",
     "Fracture specimen/Runaway length=5e-4"});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto  &m        = run.summary["metrics"]["fracture"];
  const double critical = m["critical_traction"], lefm = m["lefm_critical_traction"];
  std::printf("SENT: critical traction %.6g Pa (%.6g - %.6g), LEFM %.6g Pa, %+.2f %%\n", critical,
              m["critical_traction_range"][0].get<double>(), m["critical_traction_range"][1].get<double>(), lefm,
              100 * (critical / lefm - 1));
  EXPECT_LT(std::abs(critical / lefm - 1), ref["acceptance"]["relative_error"].get<double>());
  EXPECT_LT(m["critical_traction_range"][0].get<double>(), m["critical_traction_range"][1].get<double>());
  // the last row: the crack at the runaway load has passed the runaway length
  const auto rows = read_forces(run);
  ASSERT_GE(rows.size(), 2u);
  const double a = std::stod(run_parameter(run, "Fracture specimen/Notch length"));
  EXPECT_GT(rows.back()[1], a + std::stod(run_parameter(run, "Fracture specimen/Runaway length")));
  EXPECT_EQ(rows.back()[6], 0.0);
  EXPECT_TRUE(std::filesystem::exists(run.directory + "/specimen.pvd"));
}

// The specimen's inputs: one line naming the entry, exit 2.
TEST(PhaseField, BadSpecimensAreRefusedInOneLine)
{
  using namespace suturesim::test_support;
  const auto scene = benchmark_scene("sent_phase_field");
  for (const auto &[setting, key] :
       std::vector<std::pair<std::string, std::string>>{{"Fracture specimen/Notch length=0.0035", "Notch length"},
                                                         {"Fracture specimen/Notch length=0.007", "Notch length"},
                                                         {"Fracture specimen/Height=0.005", "Height"},
                                                         {"Fracture specimen/Load increment=1", "Load increment"},
                                                         {"Fracture specimen/Path refinements=12", "Path refinements"},
                                                         {"Model=realtime", "Bodies"}})
    {
      const auto run = run_suturesim("sent_bad", {scene, "--validate", "--set", setting});
      EXPECT_EQ(run.exit_code, 2) << setting << ": " << run.output;
      EXPECT_NE(run.output.find(key), std::string::npos) << setting << ": " << run.output;
      EXPECT_EQ(std::count(run.output.begin(), run.output.end(), '\n'), 1) << setting << ": " << run.output;
    }
}
