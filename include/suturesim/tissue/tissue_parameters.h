#pragma once
/**
 * @file
 * The parameters of the accurate tissue model (tissue_model.h): the element
 * (Q_k displacement, the three-field u–p–J mixed formulation or plain displacement),
 * the Newton–Raphson solve of a load level, the linear solver, probe points and layers
 * of other moduli. Each struct declares and parses its own subsection.
 */

#include <suturesim/core/parameter_file.h>
#include <suturesim/tissue/linear_solver.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/base/point.h>

#include <string>
#include <utility>
#include <vector>

namespace suturesim::tissue
{
  /// Newton–Raphson with a slack line search on the energy's directional derivative
  /// g(α) = R(u + α Δu)·Δu (Crisfield 1991, §9.3; FEBio's line search): α is accepted
  /// when |g(α)| ≤ 0.9 |g(0)|, else moved to the zero of g's linear interpolant. The
  /// tolerances are those of the end test of TissueModel::solve_static() (free-DoF
  /// residual absolute, or relative together with the increment).
  struct NewtonParameters
  {
    unsigned max_iterations              = 25;
    double   residual_tolerance          = 1e-9;
    double   absolute_residual_tolerance = 1e-12;
    double   increment_tolerance         = 1e-9;
    bool     line_search                 = true;
    unsigned max_backtracks              = 6;

    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(const dealii::ParameterHandler &prm, const ParameterScope &scope);
  };

  struct TissueParameters
  {
    unsigned         degree          = 2;
    std::string      formulation     = "mixed";
    unsigned         pressure_degree = 1;
    /// "newton" or "exact" (cell_assembler.h, MixedUpdate)
    std::string      mixed_update    = "newton";
    NewtonParameters newton;
    LinearSolver::Parameters linear;
    std::vector<std::pair<std::string, dealii::Point<3>>> probes;
    /// A region (gmsh physical volume, by name) with its own shear and bulk moduli.
    struct RegionModuli
    {
      std::string name;
      double      shear_modulus = 0, bulk_modulus = 0; ///< Pa
    };
    std::vector<RegionModuli> region_moduli;

    /// Tear propagation by AT1 phase-field fracture on the finite-strain tissue
    /// (subsection "Phase field"; tearing/damage_field.h, tissue_model.h).
    struct PhaseField
    {
      bool   enabled            = false;
      double toughness          = 1.1e3; ///< G_c, J/m²
      double length             = 1e-3;  ///< ℓ, m
      double residual_stiffness = 1e-6;  ///< k, 1: the share of the degraded stiffness a torn point keeps
      double   tolerance  = 1e-3; ///< 1: a step's alternate minimisation ends when d changes by at most this
      unsigned max_passes = 50;   ///< and fails the step after this many damage solves
      /// A crack there from the start: d = 1 at the damage nodes in the box between these
      /// two corners (reference coordinates, m; lower then upper), none when empty.
      std::vector<dealii::Point<3>> initial_crack;
    };
    PhaseField phase_field;

    /// Declares "Element degree", "Formulation", "Pressure degree", "Mixed update",
    /// "Probes", "Region moduli" and the
    /// subsections "Newton", "Linear solver" and "Phase field" into the current subsection.
    static void
    declare(dealii::ParameterHandler &prm);
    void
    parse(dealii::ParameterHandler &prm, const ParameterScope &scope);
  };
} // namespace suturesim::tissue
