/**
 * The tissue's implicit dynamics, y = [u; v], F(t, y, ẏ) = 0 (tissue_model.h): the
 * consistent mass matrix, Rayleigh damping, the residual F, and the Jacobian
 * αF_ẏ + F_y with its exact solve by elimination, for the IDA integrator.
 */
#include <suturesim/core/error.h>
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>

#include <algorithm>
#include <array>
#include <cmath>

namespace suturesim::tissue
{
  using namespace dealii;

  void
  TissueModel::set_rayleigh_damping(const double mass_coefficient,
                                    const double stiffness_coefficient)
  {
    rayleigh_mass      = mass_coefficient;
    rayleigh_stiffness = stiffness_coefficient;
    assemble_mass_matrix();
  }

  void
  TissueModel::assemble_mass_matrix()
  {
    TimerOutput::Scope scope(timer, "assemble M");
    DynamicSparsityPattern dsp(locally_relevant_dofs);
    DoFTools::make_sparsity_pattern(dof_handler, dsp);
    SparsityTools::distribute_sparsity_pattern(dsp, locally_owned_dofs, comm,
                                               locally_relevant_dofs);
    mass_matrix.reinit(locally_owned_dofs, locally_owned_dofs, dsp, comm);
    jacobian_full.reinit(locally_owned_dofs, locally_owned_dofs, dsp, comm);
    const unsigned     n = fe.n_dofs_per_cell();
    FullMatrix<double> M(n, n);
    std::vector<types::global_dof_index> dofs(n);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell_assembler->mass(cell, material.density(), M);
          cell->get_dof_indices(dofs);
          mass_matrix.add(dofs, M);
        }
    mass_matrix.compress(VectorOperation::add);
  }

  IndexSet
  TissueModel::dirichlet_dofs() const
  {
    IndexSet set(dof_handler.n_dofs());
    for (const auto i : owned_dirichlet)
      set.add_index(i);
    set.compress();
    return set;
  }

  bool
  TissueModel::dynamic_residual(const double  t,
                                const Vector &u,
                                const Vector &v,
                                const Vector &u_dot,
                                const Vector &v_dot,
                                Vector       &F_u,
                                Vector       &F_v)
  {
    solution_ghost = u;
    Vector v_ghost(locally_owned_dofs, locally_relevant_dofs, comm);
    v_ghost = v;
    AffineConstraints<double> none;
    none.close();
    if (!assemble(t, solution_ghost, false, none, &v_ghost, true))
      return false;

    // F_v = M v̇ + a_M M v + R (+ a_K K_t v inside R); F_u = u̇ − v.
    Vector tmp(locally_owned_dofs, comm);
    tmp = v_dot;
    tmp.add(rayleigh_mass, v);
    mass_matrix.vmult(F_v, tmp);
    F_v.add(1.0, full_residual);
    F_u = u_dot;
    F_u.add(-1.0, v);

    // Dirichlet rows are algebraic: u = g(t), v = ġ(t).
    std::vector<double> g, g_dot, g_ddot;
    boundary_values(t, g, g_dot, g_ddot);
    for (std::size_t k = 0; k < owned_dirichlet.size(); ++k)
      {
        const auto i = owned_dirichlet[k];
        F_u[i]       = u[i] - g[k];
        F_v[i]       = v[i] - g_dot[k];
      }
    F_u.compress(VectorOperation::insert);
    F_v.compress(VectorOperation::insert);
    return true;
  }

  void
  TissueModel::boundary_values(const double         t,
                               std::vector<double> &g,
                               std::vector<double> &g_dot,
                               std::vector<double> &g_ddot) const
  {
    // g(t) and its time derivatives (central differences of the prescribed functions)
    // at the locally owned Dirichlet DoFs, in the order of owned_dirichlet.
    const double h = 1e-4 * std::max(1e-3, std::abs(t)) + 1e-7;
    Vector       zero(locally_owned_dofs, locally_relevant_dofs, comm);
    std::array<AffineConstraints<double>, 3> c;
    make_constraints(t - h, zero, c[0]);
    make_constraints(t, zero, c[1]);
    make_constraints(t + h, zero, c[2]);
    g.resize(owned_dirichlet.size());
    g_dot.resize(owned_dirichlet.size());
    g_ddot.resize(owned_dirichlet.size());
    for (std::size_t k = 0; k < owned_dirichlet.size(); ++k)
      {
        const auto   i  = owned_dirichlet[k];
        const double gm = c[0].get_inhomogeneity(i), g0 = c[1].get_inhomogeneity(i),
                     gp = c[2].get_inhomogeneity(i);
        g[k]      = g0;
        g_dot[k]  = (gp - gm) / (2 * h);
        g_ddot[k] = (gp - 2 * g0 + gm) / (h * h);
      }
  }

  void
  TissueModel::initial_boundary_rates(Vector &u_dot, Vector &v_dot) const
  {
    std::vector<double> g, g_dot, g_ddot;
    boundary_values(0.0, g, g_dot, g_ddot);
    for (std::size_t k = 0; k < owned_dirichlet.size(); ++k)
      {
        u_dot[owned_dirichlet[k]] = g_dot[k];
        v_dot[owned_dirichlet[k]] = g_ddot[k];
      }
    u_dot.compress(VectorOperation::insert);
    v_dot.compress(VectorOperation::insert);
  }

  bool
  TissueModel::setup_dynamic_jacobian(const double t, const Vector &u, const double alpha)
  {
    solution_ghost = u;
    AffineConstraints<double> none;
    none.close();
    if (!assemble(t, solution_ghost, true, none, nullptr, true))
      return false;
    // A = (1 + α a_K) K + (α² + α a_M) M, kept whole for the elimination of the Dirichlet
    // values in the solve, and with the Dirichlet rows and columns of the identity for
    // the factorisation (symmetric, so Cholesky applies).
    system_matrix *= (1.0 + alpha * rayleigh_stiffness);
    system_matrix.add(alpha * alpha + alpha * rayleigh_mass, mass_matrix);
    if (MatCopy(system_matrix.petsc_matrix(), jacobian_full.petsc_matrix(),
                DIFFERENT_NONZERO_PATTERN) != 0)
      throw SolverError("PETSc MatCopy failed");
    std::vector<PetscInt> rows(owned_dirichlet.begin(), owned_dirichlet.end());
    const PetscErrorCode  ierr = MatZeroRowsColumns(system_matrix.petsc_matrix(),
                                                   static_cast<PetscInt>(rows.size()),
                                                   rows.data(), 1.0, nullptr, nullptr);
    if (ierr != 0)
      throw SolverError("PETSc MatZeroRowsColumns failed");
    jacobian_alpha = alpha;
    return true;
  }

  void
  TissueModel::solve_dynamic_jacobian(const Vector &b_u,
                                      const Vector &b_v,
                                      Vector       &x_u,
                                      Vector       &x_v,
                                      const double  tolerance)
  {
    // Jacobian rows: free  α x_u − x_v = b_u,  K x_u + D x_v = b_v,  D = (α + a_M) M + a_K K;
    //                Dirichlet  x_u = b_u,  x_v = b_v.
    // With x_v = α x_u + w (w = −b_u on free, b_v − α b_u on Dirichlet DoFs) and
    // x_u = y + x_d (x_d = b_u on Dirichlet DoFs, 0 elsewhere), the free rows read
    //   A_ff y_f = b_v − D w − A x_d,   A = K + α D,
    // and D w = (α + a_M) M w + a_K K w with K = (A − α(α + a_M) M) / (1 + α a_K).
    const double alpha = jacobian_alpha;
    const double c_m   = alpha + rayleigh_mass;
    Vector       w(locally_owned_dofs, comm), x_d(locally_owned_dofs, comm);
    Vector       rhs(locally_owned_dofs, comm), Mw(locally_owned_dofs, comm),
      tmp(locally_owned_dofs, comm);
    w = b_u;
    w *= -1.0;
    for (const auto i : owned_dirichlet)
      {
        w[i]   = b_v[i] - alpha * b_u[i];
        x_d[i] = b_u[i];
      }
    w.compress(VectorOperation::insert);
    x_d.compress(VectorOperation::insert);

    mass_matrix.vmult(Mw, w);
    rhs = b_v;
    rhs.add(-c_m, Mw);
    if (rayleigh_stiffness > 0)
      {
        jacobian_full.vmult(tmp, w); // A w
        tmp.add(-alpha * c_m, Mw);   // (1 + α a_K) K w
        rhs.add(-rayleigh_stiffness / (1.0 + alpha * rayleigh_stiffness), tmp);
      }
    jacobian_full.vmult(tmp, x_d);
    rhs.add(-1.0, tmp);
    for (const auto i : owned_dirichlet)
      rhs[i] = 0;
    rhs.compress(VectorOperation::insert);

    x_u = 0;
    solver->solve(system_matrix, x_u, rhs, tolerance);
    x_u.add(1.0, x_d);
    x_v = x_u;
    x_v *= alpha;
    x_v.add(1.0, w);
  }
} // namespace suturesim::tissue
