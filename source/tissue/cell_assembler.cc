#include <suturesim/tissue/cell_assembler.h>

#include <deal.II/lac/lapack_full_matrix.h>

namespace suturesim::tissue
{
  using namespace dealii;

  std::array<double, 4>
  pressure_basis(const Point<3> &X, const Point<3> &center, const double h)
  {
    const Tensor<1, 3> d = (X - center) / h;
    return {{1.0, d[0], d[1], d[2]}};
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
    , component(dofs_per_cell)
    , F_q(quadrature.size())
    , J_q(quadrature.size())
    , Np_q(quadrature.size())
    , dE(dofs_per_cell)
    , CC_dE(dofs_per_cell)
  {
    for (unsigned int i = 0; i < dofs_per_cell; ++i)
      component[i] = fe.system_to_component_index(i).first;
    if (mixed)
      K_pu.reinit(n_p, dofs_per_cell);
  }

  bool
  CellAssembler::mixed_fields(const DoFHandler<3>::active_cell_iterator &cell,
                              const Material                            &material,
                              std::array<double, 4>                     &p_coef,
                              FullMatrix<double>                        &M_inv,
                              FullMatrix<double>                        &K_JJ)
  {
    const unsigned int n_q    = fe_values.n_quadrature_points;
    const Point<3>     center = cell->center();
    const double       h      = cell->diameter();
    FullMatrix<double> M(n_p, n_p);
    Vector<double>     JN(n_p);
    for (unsigned int q = 0; q < n_q; ++q)
      {
        Np_q[q]         = pressure_basis(fe_values.quadrature_point(q), center, h);
        const double dV = fe_values.JxW(q);
        for (unsigned int a = 0; a < n_p; ++a)
          {
            JN[a] += Np_q[q][a] * J_q[q] * dV;
            for (unsigned int b = 0; b < n_p; ++b)
              M(a, b) += Np_q[q][a] * Np_q[q][b] * dV;
          }
      }
    M_inv.reinit(n_p, n_p);
    M_inv.invert(M);
    Vector<double> J_coef(n_p), pN(n_p);
    M_inv.vmult(J_coef, JN);
    K_JJ.reinit(n_p, n_p);
    for (unsigned int q = 0; q < n_q; ++q)
      {
        double J_tilde = 0;
        for (unsigned int a = 0; a < n_p; ++a)
          J_tilde += Np_q[q][a] * J_coef[a];
        if (!(J_tilde > 0))
          return false;
        const double dV  = fe_values.JxW(q);
        const double dp  = material.volumetric().pressure(J_tilde);
        const double ddp = material.volumetric().pressure_derivative(J_tilde);
        for (unsigned int a = 0; a < n_p; ++a)
          {
            pN[a] += Np_q[q][a] * dp * dV;
            for (unsigned int b = 0; b < n_p; ++b)
              K_JJ(a, b) += Np_q[q][a] * ddp * Np_q[q][b] * dV;
          }
      }
    for (unsigned int a = 0; a < n_p; ++a)
      for (unsigned int b = 0; b < n_p; ++b)
        p_coef[a] += M_inv(a, b) * pN[b];
    return true;
  }

  bool
  CellAssembler::assemble(const DoFHandler<3>::active_cell_iterator &cell,
                          const Vector<double>                      &u,
                          const Material                            &material,
                          const Tensor<1, 3>                        &body_acceleration,
                          Vector<double>                            &r,
                          FullMatrix<double>                        *K,
                          PressureCoefficients                      *pressure)
  {
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

    // Mixed fields: J̃ = M⁻¹∫N J, p̃ = M⁻¹∫N Ψ'(J̃), K_JJ = ∫N Ψ''(J̃) Nᵀ.
    std::array<double, 4> p_coef{};
    FullMatrix<double>    M_inv, K_JJ;
    if (mixed)
      {
        if (!mixed_fields(cell, material, p_coef, M_inv, K_JJ))
          return false;
        if (pressure != nullptr)
          *pressure = p_coef;
        K_pu = 0;
      }

    SymTensor2 S;
    SymTensor4 CC;
    for (unsigned int q = 0; q < n_q; ++q)
      {
        const Tensor2   &F     = F_q[q];
        const double     J     = J_q[q];
        const SymTensor2 C     = symmetrize(transpose(F) * F);
        const double     dV    = fe_values.JxW(q);
        if (mixed)
          {
            double p = 0;
            for (unsigned int a = 0; a < n_p; ++a)
              p += Np_q[q][a] * p_coef[a];
            material.isochoric_response(C, S, CC);
            const SymTensor2 C_inv = invert(C);
            S += p * J * C_inv;
            if (K != nullptr)
              CC += p * J * (outer_product(C_inv, C_inv) - 2.0 * symmetric_product(C_inv));
          }
        else
          material.response(C, S, CC);

        // δE_i = sym(Fᵀ ∇δu_i) for the vector shape function i = N_i e_c.
        for (unsigned int i = 0; i < dofs_per_cell; ++i)
          {
            const Tensor<1, 3> &g = fe_values.shape_grad(i, q);
            const unsigned int  c = component[i];
            SymTensor2          e;
            for (unsigned int A = 0; A < 3; ++A)
              for (unsigned int B = A; B < 3; ++B)
                e[A][B] = 0.5 * (F[c][A] * g[B] + F[c][B] * g[A]);
            dE[i] = e;
            r[i] += (S * e) * dV;
            if (body_acceleration.norm_square() > 0)
              r[i] -= material.density() * body_acceleration[c] *
                      fe_values.shape_value(i, q) * dV;
          }
        if (mixed)
          {
            const SymTensor2 JC_inv = J * invert(C);
            for (unsigned int a = 0; a < n_p; ++a)
              for (unsigned int i = 0; i < dofs_per_cell; ++i)
                K_pu(a, i) += Np_q[q][a] * (JC_inv * dE[i]) * dV;
          }
        if (K == nullptr)
          continue;

        for (unsigned int j = 0; j < dofs_per_cell; ++j)
          CC_dE[j] = CC * dE[j];
        for (unsigned int i = 0; i < dofs_per_cell; ++i)
          {
            const Tensor<1, 3> S_gi = S * fe_values.shape_grad(i, q);
            for (unsigned int j = 0; j <= i; ++j)
              {
                double k = dE[i] * CC_dE[j];
                if (component[i] == component[j])
                  k += S_gi * fe_values.shape_grad(j, q);
                (*K)(i, j) += k * dV;
              }
          }
      }

    if (K == nullptr)
      return true;
    for (unsigned int i = 0; i < dofs_per_cell; ++i)
      for (unsigned int j = i + 1; j < dofs_per_cell; ++j)
        (*K)(i, j) = (*K)(j, i);

    if (mixed)
      {
        // K += Gᵀ K_JJ G with G = M⁻¹ K_pu.
        FullMatrix<double> G(n_p, dofs_per_cell), KG(n_p, dofs_per_cell);
        M_inv.mmult(G, K_pu);
        K_JJ.mmult(KG, G);
        G.Tmmult(*K, KG, true);
      }
    return true;
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
