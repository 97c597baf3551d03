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
 *   element. With the phase field's degradation (assemble()), Ψ'_vol and Ψ''_vol carry
 *   volumetric_share() at each quadrature point, in p̃, R_J and K_JJ alike.
 *
 * The mixed fields enter Newton's method in one of two ways (MixedUpdate):
 * - exact: p̃ and J̃ are recomputed from u at every iterate as above, so the residual is
 *   a function of u alone (what an implicit time integrator needs). Its Newton
 *   iteration carries the whole nonlinearity of κ (J(u) − 1) with κ/μ up to 10⁴.
 * - newton: p̃ and J̃ are Newton unknowns, as in Simo, Taylor & Pister (1985) and step-44.
 *   With R_p = ∫ N (J − J̃) dV and R_J = ∫ N (Ψ'_vol(J̃) − p̃) dV, the linearised
 *   three-field system
 *      [K_uu  K_puᵀ  0   ] [Δu]     [r_u]
 *      [K_pu  0     −M   ] [Δp] = − [R_p]
 *      [0    −M     K_JJ ] [ΔJ]     [R_J]
 *   is condensed on the cell: ΔJ = M⁻¹ R_p + G Δu, Δp = M⁻¹ (R_J + K_JJ ΔJ), and
 *      (K_uu + Gᵀ K_JJ G) Δu = −(r_u + Gᵀ (R_J + K_JJ M⁻¹ R_p)),
 *   the same tangent as the exact variant, with the constraint residuals added. p̃ and
 *   J̃ then move with the linearised constraints instead of jumping with κ (J(u) − 1).
 *   At a state where R_p = R_J = 0 both variants give the same residual.
 *
 * The tangent is contracted per pair of displacement components (c, d) of the vector
 * shape functions N_a e_c, with the first elasticity tensor (Holzapfel 2000, ∂P/∂F)
 *    𝔸_cBdD = ∂P_cB/∂F_dD = F_cA ℂ_ABCD F_dC + δ_cd S_BD   (P = F S)
 * at each quadrature point: K_(a,c)(b,d) = Σ_q ∂_B N_a 𝔸_cBdD ∂_D N_b dV, six dense
 * n × n products over the n scalar shape functions, instead of one contraction
 * δE_i : ℂ : δE_j per pair of vector shape functions (less than half the operations,
 * most of them in one matrix product).
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

#include <Eigen/Core>

#include <array>
#include <utility>
#include <vector>

namespace suturesim::tissue
{
  /// Pressure/dilatation coefficients of one cell (mixed formulation), basis as above.
  using PressureCoefficients = std::array<double, 4>;

  /// How the mixed fields follow Newton's iterates (see the file's description).
  enum class MixedUpdate
  {
    exact,  ///< p̃(u), J̃(u) recomputed at every iterate
    newton, ///< p̃, J̃ Newton unknowns, condensed per cell
  };

  /// The mixed fields of one cell: p̃ (Pa) and J̃ (1) as coefficients of the P_k basis,
  /// and what the last assembly with MixedUpdate::newton left for recovering their
  /// Newton increments from the cell's displacement increment.
  struct MixedCell
  {
    PressureCoefficients p{};            ///< Pa
    PressureCoefficients J{{1, 0, 0, 0}}; ///< 1 (J̃ = 1: the reference state)

    /// From the cell's displacement increment @p du (local DoF order): ΔJ = M⁻¹ R_p +
    /// G Δu and Δp = M⁻¹ (R_J + K_JJ ΔJ), remembering the current p̃, J̃ as the base of
    /// step().
    void
    begin_update(const dealii::Vector<double> &du);

    /// p̃ = p̃₀ + α Δp, J̃ = J̃₀ + α ΔJ (a Newton step scaled by a line search).
    void
    step(double alpha);

    /// p̃ (Pa) and J̃ (1) at reference point @p X of the cell with centre @p center and
    /// diameter @p h (the basis of pressure_basis()).
    std::pair<double, double>
    at(const dealii::Point<3> &X, const dealii::Point<3> &center, double h) const;

    /// The constraint residuals of the last assembly with MixedUpdate::newton: M⁻¹ R_p
    /// (1; the coefficients of J's projection minus J̃'s) and R_J (N·m = Pa·m³).
    const PressureCoefficients &
    dilatation_residual() const
    {
      return M_inv_R_p;
    }
    const PressureCoefficients &
    pressure_residual() const
    {
      return R_J;
    }

  private:
    friend class CellAssembler;
    unsigned              n_p = 0;
    PressureCoefficients  M_inv_R_p{}, R_J{}, p0{}, J0{}, dp{}, dJ{};
    std::array<double, 16> M_inv{}, K_JJ{}; ///< row-major n_p × n_p
    std::vector<double>    G;               ///< row-major n_p × dofs per cell
  };

  /// g(d) = (1 − k)(1 − d)² + k: the share of the isochoric energy a point of the tissue
  /// keeps at phase-field damage @p d (tearing/damage_field.h), with the residual
  /// stiffness @p k that keeps the displacement unique (g(0) = 1: the undamaged tissue is
  /// the material as given).
  inline double
  degradation(const double d, const double k)
  {
    return (1 - k) * (1 - d) * (1 - d) + k;
  }

  /// The share of the volumetric energy Ψ_vol(J) a point keeps where the phase field has
  /// degraded its isochoric energy by g: g in expansion (J > 1), 1 in compression. The
  /// finite-strain form of Amor, Marigo & Maurini's (J Mech Phys Solids 57:1209, 2009)
  /// volumetric–deviatoric split: a tear opens (its volume grows at no cost) but its faces
  /// do not interpenetrate. Ψ'_vol(1) = 0, so the stress stays continuous across J = 1.
  inline bool
  volumetric_degraded(const double J)
  {
    return J > 1;
  }
  inline double
  volumetric_share(const double g, const double J)
  {
    return volumetric_degraded(J) ? g : 1.0;
  }

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

    /// A fresh assembler for the same element (one per thread of a parallel assembly:
    /// the scratch below is not shared).
    CellAssembler(const CellAssembler &other);

    /// Residual r = f_int − ∫ ρ b N dV of the cell at local displacements @p u and, if
    /// @p K is given, its tangent. Mixed formulation: with MixedUpdate::exact, p̃ and J̃
    /// are computed from u and written to @p fields if given; with MixedUpdate::newton,
    /// they are read from @p fields (required), r is the condensed residual and
    /// @p constraint_force, if given, receives its part Gᵀ (R_J + K_JJ M⁻¹ R_p), which
    /// vanishes when the constraints hold. @p degradation, if given, holds g at each
    /// quadrature point (phase-field tearing): the energy becomes
    /// g Ψ_iso + volumetric_share(g, J̃) Ψ_vol(J̃). Returns false (and leaves the outputs
    /// undefined) when J or J̃ ≤ 0 at a quadrature point: the caller treats this as a
    /// failed iterate.
    bool
    assemble(const dealii::DoFHandler<3>::active_cell_iterator &cell,
             const dealii::Vector<double>                      &u,
             const Material                                    &material,
             const dealii::Tensor<1, 3>                        &body_acceleration,
             dealii::Vector<double>                            &r,
             dealii::FullMatrix<double>                        *K,
             MixedCell                                         *fields           = nullptr,
             MixedUpdate                                        update           = MixedUpdate::exact,
             dealii::Vector<double>                            *constraint_force = nullptr,
             const std::vector<double>                         *degradation      = nullptr);

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
    /// The mixed fields of the cell (fe_values reinitialised on it, J_q filled): M⁻¹ and
    /// K_JJ; with @p from_state, the constraint residuals R_p, R_J at the fields' p̃, J̃;
    /// otherwise p̃ and J̃ computed from u into @p fields (R_p = R_J = 0). Returns false
    /// when J̃ ≤ 0 at a quadrature point.
    bool
    mixed_fields(const dealii::DoFHandler<3>::active_cell_iterator &cell,
                 const Material                                    &material,
                 const std::vector<double>                         *degradation,
                 bool                                               from_state,
                 MixedCell                                         &fields,
                 dealii::FullMatrix<double>                        &M_inv,
                 dealii::FullMatrix<double>                        &K_JJ,
                 dealii::Vector<double>                            &R_p,
                 dealii::Vector<double>                            &R_J);

    /// Adds Gᵀ K_JJ G to @p K and, with @p unknowns, the constraint part of the
    /// residual, storing in @p fields what MixedCell::begin_update() needs.
    void
    condense(MixedCell                    &fields,
             bool                          unknowns,
             const dealii::FullMatrix<double> &M_inv,
             const dealii::FullMatrix<double> &K_JJ,
             const dealii::Vector<double> &R_p,
             const dealii::Vector<double> &R_J,
             dealii::Vector<double>       &r,
             dealii::FullMatrix<double>   *K,
             dealii::Vector<double>       *constraint_force);

    /// 𝔸 dV at quadrature point @p q into A_q[q], row (3c + B), column (3d + D).
    void
    store_tangent(unsigned q, const Tensor2 &F, const SymTensor2 &S, const SymTensor4 &CC, double dV);

    /// The displacement tangent from A_q: K_(a,c)(b,d) = Σ_q ∂_B N_a 𝔸_cBdD ∂_D N_b dV.
    void
    contract_tangent(dealii::FullMatrix<double> &K);

    dealii::FEValues<3>  fe_values;
    const bool           mixed;
    const unsigned int   n_p;
    const unsigned int   dofs_per_cell;
    const unsigned int   n_scalar; ///< scalar shape functions: dofs_per_cell / 3
    std::vector<unsigned int>            component;
    std::array<std::vector<unsigned int>, 3> dof_of; ///< local DoF of N_a e_c: dof_of[c][a]
    std::vector<Tensor2>                 F_q;
    std::vector<double>                  J_q;
    std::vector<std::array<double, 4>>   Np_q;
    std::vector<std::array<double, 81>>  A_q;
    Eigen::MatrixXd                      grad_N; ///< ∂_B N_a in row a, column 3q + B
    Eigen::MatrixXd                      H, K_cd;
    dealii::FullMatrix<double>           K_pu;
  };
} // namespace suturesim::tissue
