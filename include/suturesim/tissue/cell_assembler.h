#pragma once
/**
 * @file
 * Residual and consistent tangent of one hexahedral cell, Total Lagrangian, for two
 * formulations selectable per scene:
 *
 * - "displacement": Π(u) = ∫ Ψ(C) dV; locks for ν → 0.5 with low-order elements.
 * - "mixed": the three-field Hu–Washizu form of Simo, Taylor & Pister (1985) and of
 *   deal.II step-44, Π(u, p̃, J̃) = ∫ Ψ_iso(C̄) + Ψ_vol(J̃) + p̃(J − J̃) dV, with p̃ and J̃
 *   discontinuous polynomials of degree k ∈ {0, 1} per cell (basis {1, (X − X_c)/h}, i.e.
 *   non-parametric P_k). Both are condensed on the cell, so the global system has
 *   displacements only. Stationarity in p̃ and J̃ gives
 *      J̃ = M⁻¹ ∫ N J dV,   p̃ = M⁻¹ ∫ N Ψ'_vol(J̃) dV,   M = ∫ N Nᵀ dV,
 *   so Π is a function of u alone with residual ∫ (S_iso + p̃ J C⁻¹) : δE dV and the
 *   symmetric condensed tangent
 *      K = K_uu(p̃) + Gᵀ K_JJ G,   G = M⁻¹ K_pu,   K_JJ = ∫ N Ψ''_vol(J̃) Nᵀ dV,
 *      K_pu = ∫ N (J C⁻¹ : δE) dV.
 *   Q2 with k = 1 is the stable step-44 pair; Q1 with k = 0 is the mean-dilatation
 *   element.
 *
 * Verified against central finite differences of the residual in
 * tests/unit/cell_assembler_test.cc.
 */

#include <suturesim/tissue/material.h>

#include <deal.II/dofs/dof_handler.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping.h>
#include <deal.II/lac/full_matrix.h>
#include <deal.II/lac/vector.h>

#include <array>
#include <vector>

namespace suturesim::tissue
{
  /// Pressure/dilatation coefficients of one cell (mixed formulation), basis as above.
  using PressureCoefficients = std::array<double, 4>;

  /// The P_k basis {1, (X − X_c)/h} of the mixed fields at reference point @p X.
  std::array<double, 4>
  pressure_basis(const dealii::Point<3> &X, const dealii::Point<3> &center, double h);

  class CellAssembler
  {
  public:
    /// @p pressure_degree is ignored unless @p mixed.
    CellAssembler(const dealii::Mapping<3>          &mapping,
                  const dealii::FiniteElement<3>    &fe,
                  const dealii::Quadrature<3>       &quadrature,
                  bool                               mixed,
                  unsigned int                       pressure_degree);

    /// Residual r = f_int − ∫ ρ b N dV of the cell at local displacements @p u and, if
    /// @p K is given, its derivative. Writes the mixed pressure coefficients to
    /// @p pressure if given. Returns false (and leaves r, K undefined) when J ≤ 0 at a
    /// quadrature point: the caller treats this as a failed iterate.
    bool
    assemble(const dealii::DoFHandler<3>::active_cell_iterator &cell,
             const dealii::Vector<double>                      &u,
             const Material                                    &material,
             const dealii::Tensor<1, 3>                        &body_acceleration,
             dealii::Vector<double>                            &r,
             dealii::FullMatrix<double>                        *K,
             PressureCoefficients                              *pressure = nullptr);

    /// Consistent mass matrix ρ ∫ N_i N_j δ_{c_i c_j} dV.
    void
    mass(const dealii::DoFHandler<3>::active_cell_iterator &cell,
         double                                             density,
         dealii::FullMatrix<double>                        &M);

    bool
    is_mixed() const
    {
      return mixed;
    }

    unsigned int
    n_pressure() const
    {
      return n_p;
    }

  private:
    /// The condensed mixed fields of the cell (fe_values reinitialised on it, J_q
    /// filled): p̃'s coefficients @p p_coef, M⁻¹ and K_JJ (see the file's description).
    /// Returns false when J̃ ≤ 0 at a quadrature point.
    bool
    mixed_fields(const dealii::DoFHandler<3>::active_cell_iterator &cell,
                 const Material                                    &material,
                 std::array<double, 4>                             &p_coef,
                 dealii::FullMatrix<double>                        &M_inv,
                 dealii::FullMatrix<double>                        &K_JJ);

    dealii::FEValues<3>  fe_values;
    const bool           mixed;
    const unsigned int   n_p;
    const unsigned int   dofs_per_cell;
    std::vector<unsigned int>            component;
    std::vector<Tensor2>                 F_q;
    std::vector<double>                  J_q;
    std::vector<std::array<double, 4>>   Np_q;
    std::vector<SymTensor2>              dE;
    std::vector<SymTensor2>              CC_dE;
    dealii::FullMatrix<double>           K_pu;
  };
} // namespace suturesim::tissue
