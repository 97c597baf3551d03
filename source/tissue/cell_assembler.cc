#include <suturesim/tissue/cell_assembler.h>

#include <deal.II/lac/lapack_full_matrix.h>

namespace suturesim::tissue
{
  using namespace dealii;

  namespace
  {
    /// Adds p̃ J dV (F⁻ᵀ_cB F⁻ᵀ_dD − F⁻ᵀ_cD F⁻ᵀ_dB) to 𝔸 dV (row 3c + B, column 3d + D).
    void
    add_pressure_tangent(const Tensor2 &F_invT, const double pJV, std::array<double, 81> &A)
    {
      for (unsigned c = 0; c < 3; ++c)
        for (unsigned B = 0; B < 3; ++B)
          for (unsigned d = 0; d < 3; ++d)
            for (unsigned D = 0; D < 3; ++D)
              A[(3 * c + B) * 9 + 3 * d + D] += pJV * (F_invT[c][B] * F_invT[d][D] - F_invT[c][D] * F_invT[d][B]);
    }
  } // namespace

  std::array<double, 4>
  pressure_basis(const Point<3> &X, const Point<3> &center, const double h)
  {
    const Tensor<1, 3> d = (X - center) / h;
    return {{1.0, d[0], d[1], d[2]}};
  }

  std::pair<double, double>
  MixedCell::at(const Point<3> &X, const Point<3> &center, const double h) const
  {
    const auto N = pressure_basis(X, center, h);
    double     p_at = 0, J_at = 0;
    for (unsigned a = 0; a < N.size(); ++a)
      {
        p_at += N[a] * p[a];
        J_at += N[a] * J[a];
      }
    return {p_at, J_at};
  }

  CellAssembler::CellAssembler(const Mapping<3>       &mapping,
                               const FiniteElement<3> &fe,
                               const Quadrature<3>    &quadrature,
                               const bool              mixed,
                               const unsigned int      pressure_degree)
    : fe_values(mapping,
                fe,
                quadrature,
                update_values | update_gradients | update_JxW_values |
                  update_quadrature_points)
    , mixed(mixed)
    , n_p(mixed ? (pressure_degree == 0 ? 1 : 4) : 0)
    , dofs_per_cell(fe.n_dofs_per_cell())
    , n_scalar(dofs_per_cell / 3)
    , component(dofs_per_cell)
    , F_q(quadrature.size())
    , J_q(quadrature.size())
    , Np_q(quadrature.size())
    , A_q(quadrature.size())
    , grad_N(n_scalar, 3 * quadrature.size())
    , H(n_scalar, 3 * quadrature.size())
    , K_cd(n_scalar, n_scalar)
  {
    // a displacement element: three copies of one scalar element, N_a e_c
    AssertThrow(fe.n_components() == 3 && fe.is_primitive() && fe.n_base_elements() == 1,
                ExcMessage("CellAssembler needs FESystem(scalar element, 3)"));
    for (auto &d : dof_of)
      d.resize(n_scalar);
    for (unsigned int i = 0; i < dofs_per_cell; ++i)
      {
        const auto [c, a] = fe.system_to_component_index(i);
        component[i]      = c;
        dof_of[c][a]      = i;
      }
    if (mixed)
      K_pu.reinit(n_p, dofs_per_cell);
  }

  void
  MixedCell::begin_update(const Vector<double> &du)
  {
    const unsigned n = du.size();
    p0               = p;
    J0               = J;
    for (unsigned a = 0; a < n_p; ++a)
      {
        dJ[a] = M_inv_R_p[a];
        for (unsigned i = 0; i < n; ++i)
          dJ[a] += G[a * n + i] * du[i];
      }
    PressureCoefficients b = R_J;
    for (unsigned a = 0; a < n_p; ++a)
      for (unsigned c = 0; c < n_p; ++c)
        b[a] += K_JJ[a * n_p + c] * dJ[c];
    for (unsigned a = 0; a < n_p; ++a)
      {
        dp[a] = 0;
        for (unsigned c = 0; c < n_p; ++c)
          dp[a] += M_inv[a * n_p + c] * b[c];
      }
  }

  void
  MixedCell::step(const double alpha)
  {
    for (unsigned a = 0; a < n_p; ++a)
      {
        p[a] = p0[a] + alpha * dp[a];
        J[a] = J0[a] + alpha * dJ[a];
      }
  }

  CellAssembler::CellAssembler(const CellAssembler &other)
    : CellAssembler(other.fe_values.get_mapping(),
                    other.fe_values.get_fe(),
                    other.fe_values.get_quadrature(),
                    other.mixed,
                    other.n_p == 1 ? 0 : 1)
  {}

  bool
  CellAssembler::mixed_fields(const DoFHandler<3>::active_cell_iterator &cell,
                              const Material                            &material,
                              const std::vector<double>                 *degradation,
                              const bool                                 from_state,
                              MixedCell                                 &fields,
                              FullMatrix<double>                        &M_inv,
                              FullMatrix<double>                        &K_JJ,
                              dealii::Vector<double>                    &R_p,
                              dealii::Vector<double>                    &R_J)
  {
    const unsigned n_q    = fe_values.n_quadrature_points;
    const Point<3> center = cell->center();
    const double   h      = cell->diameter();
    FullMatrix<double>     M(n_p, n_p);
    dealii::Vector<double> JN(n_p), pN(n_p), NpN(n_p);
    for (unsigned q = 0; q < n_q; ++q)
      {
        Np_q[q]         = pressure_basis(fe_values.quadrature_point(q), center, h);
        const double dV = fe_values.JxW(q);
        for (unsigned a = 0; a < n_p; ++a)
          {
            JN[a] += Np_q[q][a] * J_q[q] * dV;
            for (unsigned b = 0; b < n_p; ++b)
              M(a, b) += Np_q[q][a] * Np_q[q][b] * dV;
          }
      }
    M_inv.reinit(n_p, n_p);
    M_inv.invert(M);
    if (!from_state)
      for (unsigned a = 0; a < n_p; ++a)
        {
          fields.J[a] = 0;
          for (unsigned b = 0; b < n_p; ++b)
            fields.J[a] += M_inv(a, b) * JN[b];
        }
    K_JJ.reinit(n_p, n_p);
    for (unsigned q = 0; q < n_q; ++q)
      {
        double J_tilde = 0, p_tilde = 0;
        for (unsigned a = 0; a < n_p; ++a)
          {
            J_tilde += Np_q[q][a] * fields.J[a];
            p_tilde += Np_q[q][a] * fields.p[a];
          }
        if (!(J_tilde > 0))
          return false;
        const double dV  = fe_values.JxW(q);
        const double gv  = degradation != nullptr ? volumetric_share((*degradation)[q], J_tilde) : 1.0;
        const double dp  = gv * material.volumetric().pressure(J_tilde);
        const double ddp = gv * material.volumetric().pressure_derivative(J_tilde);
        for (unsigned a = 0; a < n_p; ++a)
          {
            pN[a] += Np_q[q][a] * dp * dV;
            NpN[a] += Np_q[q][a] * (J_q[q] - J_tilde) * dV;
            R_J[a] += Np_q[q][a] * (dp - p_tilde) * dV;
            for (unsigned b = 0; b < n_p; ++b)
              K_JJ(a, b) += Np_q[q][a] * ddp * Np_q[q][b] * dV;
          }
      }
    if (from_state)
      {
        R_p = NpN;
        return true;
      }
    // stationarity: p̃ = M⁻¹ ∫ N g_v Ψ'(J̃), J̃ = M⁻¹ ∫ N J, both constraints exact
    for (unsigned a = 0; a < n_p; ++a)
      {
        fields.p[a] = 0;
        for (unsigned b = 0; b < n_p; ++b)
          fields.p[a] += M_inv(a, b) * pN[b];
      }
    R_p = 0;
    R_J = 0;
    return true;
  }

  bool
  CellAssembler::assemble(const DoFHandler<3>::active_cell_iterator &cell,
                          const Vector<double>                      &u,
                          const Material                            &material,
                          const Tensor<1, 3>                        &body_acceleration,
                          Vector<double>                            &r,
                          FullMatrix<double>                        *K,
                          MixedCell                                 *fields,
                          const MixedUpdate                          update,
                          dealii::Vector<double>                    *constraint_force,
                          const std::vector<double>                 *degradation)
  {
    const bool unknowns = mixed && update == MixedUpdate::newton;
    Assert(!unknowns || fields != nullptr, ExcMessage("MixedUpdate::newton needs the cell's fields"));
    fe_values.reinit(cell);
    const unsigned int n_q = fe_values.n_quadrature_points;
    r                      = 0;
    if (K != nullptr)
      *K = 0;

    // Deformation gradient at every quadrature point first: the mixed fields need J on
    // the whole cell before any stress can be evaluated.
    for (unsigned int q = 0; q < n_q; ++q)
      {
        Tensor2 F = unit_symmetric_tensor<3>();
        for (unsigned int i = 0; i < dofs_per_cell; ++i)
          {
            const Tensor<1, 3> &g = fe_values.shape_grad(i, q);
            for (unsigned int B = 0; B < 3; ++B)
              F[component[i]][B] += u[i] * g[B];
          }
        F_q[q] = F;
        J_q[q] = determinant(F);
        if (!(J_q[q] > 0)) // also catches NaN
          return false;
      }

    // Mixed fields: M⁻¹, K_JJ = ∫N g_v Ψ''(J̃) Nᵀ and either p̃, J̃ from u (exact) or the
    // constraint residuals at the given p̃, J̃ (newton).
    MixedCell              local;
    MixedCell             &mf = fields != nullptr ? *fields : local;
    FullMatrix<double>     M_inv, K_JJ;
    dealii::Vector<double> R_p(n_p), R_J(n_p);
    if (mixed)
      {
        if (!mixed_fields(cell, material, degradation, unknowns, mf, M_inv, K_JJ, R_p, R_J))
          return false;
        K_pu = 0;
      }
    const PressureCoefficients &p_coef = mf.p;

    SymTensor2 S;
    SymTensor4 CC;
    for (unsigned int q = 0; q < n_q; ++q)
      {
        const Tensor2   &F  = F_q[q];
        const double     J  = J_q[q];
        const SymTensor2 C  = symmetrize(transpose(F) * F);
        const double     dV = fe_values.JxW(q);
        if (mixed)
          {
            double p = 0;
            for (unsigned int a = 0; a < n_p; ++a)
              p += Np_q[q][a] * p_coef[a];
            material.isochoric_response(C, S, CC);
            if (degradation != nullptr)
              {
                S *= (*degradation)[q];
                CC *= (*degradation)[q];
              }
            if (K != nullptr)
              store_tangent(q, F, S, CC, dV);
            // S += p̃ J C⁻¹. Its part of 𝔸, ∂(p̃ J F⁻ᵀ)/∂F at fixed p̃, is
            // p̃ J (F⁻ᵀ_cB F⁻ᵀ_dD − F⁻ᵀ_cD F⁻ᵀ_dB): the δ_cd (p̃ J C⁻¹)_BD of the geometric
            // term cancels against ℂ's −2 p̃ J C⁻¹ ⊙ C⁻¹.
            const Tensor2 F_invT = transpose(invert(F));
            S += p * J * invert(C);
            if (K != nullptr)
              add_pressure_tangent(F_invT, p * J * dV, A_q[q]);
            // K_pu: J C⁻¹ : δE = J F⁻ᵀ_cB ∂_B N_a for δu = N_a e_c
            for (unsigned int a = 0; a < n_p; ++a)
              for (unsigned int i = 0; i < dofs_per_cell; ++i)
                K_pu(a, i) +=
                  Np_q[q][a] * J * (F_invT[component[i]] * fe_values.shape_grad(i, q)) * dV;
          }
        else
          {
            material.response(C, S, CC);
            if (degradation != nullptr)
              {
                // g Ψ_iso + g_v Ψ_vol = g_v Ψ + (g − g_v) Ψ_iso; the isochoric part
                // alone only in compression, where g_v = 1 ≠ g
                const double g  = (*degradation)[q];
                const double gv = volumetric_share(g, J);
                if (gv != 1) // undamaged or in compression it keeps the whole volumetric part
                  {
                    S *= gv;
                    CC *= gv;
                  }
                if (g != gv)
                  {
                    SymTensor2 S_iso;
                    SymTensor4 CC_iso;
                    material.isochoric_response(C, S_iso, CC_iso);
                    S += (g - gv) * S_iso;
                    CC += (g - gv) * CC_iso;
                  }
              }
            if (K != nullptr)
              store_tangent(q, F, S, CC, dV);
          }

        // r_(a,c) = P_cB ∂_B N_a dV with P = F S (= S : δE for δu = N_a e_c)
        const Tensor2 P = F * Tensor2(S);
        for (unsigned int i = 0; i < dofs_per_cell; ++i)
          {
            const unsigned int c = component[i];
            r[i] += (P[c] * fe_values.shape_grad(i, q)) * dV;
            if (body_acceleration.norm_square() > 0)
              r[i] -= material.density() * body_acceleration[c] *
                      fe_values.shape_value(i, q) * dV;
          }
      }
    if (K != nullptr)
      contract_tangent(*K);

    if (mixed)
      condense(mf, unknowns, M_inv, K_JJ, R_p, R_J, r, K, constraint_force);
    return true;
  }

  void
  CellAssembler::store_tangent(const unsigned q, const Tensor2 &F, const SymTensor2 &S,
                               const SymTensor4 &CC, const double dV)
  {
    // T_cBCD = F_cA ℂ_ABCD, then 𝔸_cBdD = T_cBCD F_dC + δ_cd S_BD
    double cc[3][3][3][3], T[3][3][3][3];
    for (unsigned A = 0; A < 3; ++A)
      for (unsigned B = 0; B < 3; ++B)
        for (unsigned C = 0; C < 3; ++C)
          for (unsigned D = 0; D < 3; ++D)
            cc[A][B][C][D] = CC[A][B][C][D];
    for (unsigned c = 0; c < 3; ++c)
      for (unsigned B = 0; B < 3; ++B)
        for (unsigned C = 0; C < 3; ++C)
          for (unsigned D = 0; D < 3; ++D)
            T[c][B][C][D] = F[c][0] * cc[0][B][C][D] + F[c][1] * cc[1][B][C][D] + F[c][2] * cc[2][B][C][D];
    std::array<double, 81> &A = A_q[q];
    for (unsigned c = 0; c < 3; ++c)
      for (unsigned B = 0; B < 3; ++B)
        for (unsigned d = 0; d < 3; ++d)
          for (unsigned D = 0; D < 3; ++D)
            A[(3 * c + B) * 9 + 3 * d + D] =
              dV * (T[c][B][0][D] * F[d][0] + T[c][B][1][D] * F[d][1] + T[c][B][2][D] * F[d][2] +
                    (c == d ? S[B][D] : 0.0));
  }

  void
  CellAssembler::contract_tangent(FullMatrix<double> &K)
  {
    const unsigned n_q = fe_values.n_quadrature_points;
    for (unsigned q = 0; q < n_q; ++q)
      for (unsigned a = 0; a < n_scalar; ++a)
        {
          const Tensor<1, 3> &g = fe_values.shape_grad(dof_of[0][a], q);
          for (unsigned B = 0; B < 3; ++B)
            grad_N(a, 3 * q + B) = g[B];
        }
    for (unsigned c = 0; c < 3; ++c)
      for (unsigned d = c; d < 3; ++d)
        {
          // H = ∂N 𝔸^cd, point by point (𝔸^cd is block diagonal over q), then K^cd = H ∂Nᵀ
          for (unsigned q = 0; q < n_q; ++q)
            {
              const std::array<double, 81> &A = A_q[q];
              for (unsigned D = 0; D < 3; ++D)
                {
                  const double A0 = A[(3 * c) * 9 + 3 * d + D], A1 = A[(3 * c + 1) * 9 + 3 * d + D],
                               A2 = A[(3 * c + 2) * 9 + 3 * d + D];
                  H.col(3 * q + D) =
                    A0 * grad_N.col(3 * q) + A1 * grad_N.col(3 * q + 1) + A2 * grad_N.col(3 * q + 2);
                }
            }
          K_cd.noalias() = H * grad_N.transpose();
          // a diagonal block from its lower triangle, so that K is symmetric to the bit
          for (unsigned a = 0; a < n_scalar; ++a)
            for (unsigned b = 0; b < (c == d ? a + 1 : n_scalar); ++b)
              {
                K(dof_of[c][a], dof_of[d][b]) = K_cd(a, b);
                K(dof_of[d][b], dof_of[c][a]) = K_cd(a, b);
              }
        }
  }

  void
  CellAssembler::condense(MixedCell                    &mf,
                          const bool                    unknowns,
                          const FullMatrix<double>     &M_inv,
                          const FullMatrix<double>     &K_JJ,
                          const dealii::Vector<double> &R_p,
                          const dealii::Vector<double> &R_J,
                          dealii::Vector<double>       &r,
                          FullMatrix<double>           *K,
                          dealii::Vector<double>       *constraint_force)
  {
    // G = M⁻¹ K_pu; K += Gᵀ K_JJ G.
    FullMatrix<double> G(n_p, dofs_per_cell);
    M_inv.mmult(G, K_pu);
    if (K != nullptr)
      {
        FullMatrix<double> KG(n_p, dofs_per_cell);
        K_JJ.mmult(KG, G);
        G.Tmmult(*K, KG, true);
      }
    if (!unknowns)
      return;
    // r += Gᵀ (R_J + K_JJ M⁻¹ R_p); keep what the recovery of Δp̃, ΔJ̃ needs.
    dealii::Vector<double> a(n_p), b(n_p), c(dofs_per_cell);
    M_inv.vmult(a, R_p);
    K_JJ.vmult(b, a);
    b += R_J;
    G.Tvmult(c, b);
    r += c;
    if (constraint_force != nullptr)
      *constraint_force = c;
    mf.n_p = n_p;
    mf.G.resize(n_p * dofs_per_cell);
    for (unsigned x = 0; x < n_p; ++x)
      {
        mf.M_inv_R_p[x] = a[x];
        mf.R_J[x]       = R_J[x];
        for (unsigned y = 0; y < n_p; ++y)
          {
            mf.M_inv[x * n_p + y] = M_inv(x, y);
            mf.K_JJ[x * n_p + y]  = K_JJ(x, y);
          }
        for (unsigned i = 0; i < dofs_per_cell; ++i)
          mf.G[x * dofs_per_cell + i] = G(x, i);
      }
  }

  void
  CellAssembler::mass(const DoFHandler<3>::active_cell_iterator &cell,
                      const double                               density,
                      FullMatrix<double>                        &M)
  {
    fe_values.reinit(cell);
    M = 0;
    for (unsigned int q = 0; q < fe_values.n_quadrature_points; ++q)
      for (unsigned int i = 0; i < dofs_per_cell; ++i)
        for (unsigned int j = 0; j < dofs_per_cell; ++j)
          if (component[i] == component[j])
            M(i, j) += density * fe_values.shape_value(i, q) * fe_values.shape_value(j, q) *
                       fe_values.JxW(q);
  }
} // namespace suturesim::tissue
