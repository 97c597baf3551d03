#include <suturesim/core/error.h>
#include <suturesim/tearing/damage_field.h>

#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>

#include <petscsnes.h>

#include <limits>
#include <stdexcept>
#include <string>

namespace suturesim::tearing
{
  using namespace dealii;

  namespace
  {
    /// c_w of AT1, 4 ∫₀¹ √w(d) dd with w(d) = d
    constexpr double c_w = 8.0 / 3.0;

    void
    check(const PetscErrorCode code, const char *call)
    {
      if (code != 0)
        throw SolverError(std::string("phase field: PETSc's ") + call + " failed (error " + std::to_string(code) + ")");
    }

    /// The residual F(d) = A d − b (A's hanging rows hold their constraints).
    struct Problem
    {
      Mat A;
      Vec b;
    };

    PetscErrorCode
    residual(SNES, Vec x, Vec f, void *context)
    {
      const auto    *problem = static_cast<const Problem *>(context);
      PetscErrorCode code    = MatMult(problem->A, x, f);
      if (code == 0)
        code = VecAXPY(f, -1.0, problem->b);
      return code;
    }

    PetscErrorCode
    jacobian(SNES, Vec, Mat, Mat, void *)
    {
      return 0; // A is constant: the problem is quadratic in d
    }
  } // namespace

  template <int dim>
  DamageField<dim>::DamageField(MPI_Comm comm, const parallel::distributed::Triangulation<dim> &tria,
                                const double toughness, const double length, const unsigned quadrature_points)
    : comm(comm)
    , gc(toughness)
    , ell(length)
    , fe_d(1)
    , dof_d(tria)
    , quadrature_d(quadrature_points)
  {
    dof_d.distribute_dofs(fe_d);
    owned = dof_d.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_d, relevant);
    constraints.reinit(relevant);
    DoFTools::make_hanging_node_constraints(dof_d, constraints);
    constraints.close();
    // the rows of hanging nodes hold their constraint equations (solve()), so the pattern
    // keeps their couplings
    DynamicSparsityPattern dsp(relevant);
    DoFTools::make_sparsity_pattern(dof_d, dsp, constraints, true);
    SparsityTools::distribute_sparsity_pattern(dsp, owned, comm, relevant);
    matrix.reinit(owned, owned, dsp, comm);
    d.reinit(owned, comm);
    d_accepted.reinit(owned, comm);
    d_ghost.reinit(owned, relevant, comm);
    rhs.reinit(owned, comm);
    lower.reinit(owned, comm);
    upper.reinit(owned, comm);
    d          = 0;
    d_accepted = 0;
    d_ghost    = d; // a ghosted vector is not zeroed when created
    set_bounds();
  }

  template <int dim>
  DamageField<dim>::~DamageField() = default;

  template <int dim>
  void
  DamageField<dim>::crack(const std::function<bool(const Point<dim> &)> &cracked)
  {
    std::map<types::global_dof_index, Point<dim>> support_points;
    DoFTools::map_dofs_to_support_points(MappingQ<dim>(1), dof_d, support_points);
    for (const auto &[index, point] : support_points)
      if (owned.is_element(index) && cracked(point) && !constraints.is_constrained(index))
        d(index) = 1;
    d.compress(VectorOperation::insert);
    accept();
    d_ghost = d;
  }

  template <int dim>
  void
  DamageField<dim>::set_bounds()
  {
    lower = d_accepted;
    upper = 1.0;
    for (const auto i : owned)
      if (constraints.is_constrained(i))
        {
          lower(i) = PETSC_NINFINITY;
          upper(i) = PETSC_INFINITY;
        }
    lower.compress(VectorOperation::insert);
    upper.compress(VectorOperation::insert);
  }

  template <int dim>
  double
  DamageField<dim>::solve(const Driving &psi)
  {
    matrix = 0;
    rhs    = 0;
    FEValues<dim>     fv(fe_d, quadrature_d, update_values | update_gradients | update_JxW_values);
    const unsigned    n = fe_d.n_dofs_per_cell();
    FullMatrix<double> cell_matrix(n, n);
    Vector<double>     cell_rhs(n);
    std::vector<types::global_dof_index> indices(n);
    std::vector<double>                  psi_q(quadrature_d.size());
    for (const auto &cell : dof_d.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fv.reinit(cell);
          psi(Cell(&cell->get_triangulation(), cell->level(), cell->index()), psi_q);
          cell_matrix = 0;
          cell_rhs    = 0;
          for (const unsigned q : fv.quadrature_point_indices())
            // ∂/∂d of (1 − d)² ψ + G_c/c_w (d/ℓ + ℓ |∇d|²) in the direction φ_i
            for (unsigned i = 0; i < n; ++i)
              {
                const double phi_i = fv.shape_value(i, q);
                for (unsigned j = 0; j < n; ++j)
                  cell_matrix(i, j) += (2 * psi_q[q] * phi_i * fv.shape_value(j, q) +
                                        2 * gc * ell / c_w * (fv.shape_grad(i, q) * fv.shape_grad(j, q))) *
                                       fv.JxW(q);
                cell_rhs(i) += (2 * psi_q[q] - gc / (c_w * ell)) * phi_i * fv.JxW(q);
              }
          cell->get_dof_indices(indices);
          constraints.distribute_local_to_global(cell_matrix, cell_rhs, indices, matrix, rhs);
        }
    matrix.compress(VectorOperation::add);
    rhs.compress(VectorOperation::add);
    // a hanging node's row: d_i − Σ c_ij d_j = 0
    for (const auto i : owned)
      if (const auto *entries = constraints.get_constraint_entries(i))
        {
          matrix.set(i, i, 1.0);
          for (const auto &[j, c] : *entries)
            matrix.set(i, j, -c);
        }
    matrix.compress(VectorOperation::insert);

    PETScWrappers::MPI::Vector previous(owned, comm);
    previous = d;
    Problem                    problem{matrix.petsc_matrix(), rhs};
    PETScWrappers::MPI::Vector f(owned, comm);
    SNES                       snes;
    check(SNESCreate(comm, &snes), "SNESCreate");
    try
      {
        check(SNESSetType(snes, SNESVINEWTONRSLS), "SNESSetType");
        check(SNESSetFunction(snes, f, residual, &problem), "SNESSetFunction");
        check(SNESSetJacobian(snes, problem.A, problem.A, jacobian, nullptr), "SNESSetJacobian");
        check(SNESVISetVariableBounds(snes, lower, upper), "SNESVISetVariableBounds");
        check(SNESSetTolerances(snes, 1e-14, 1e-10, 1e-14, 100, 1000), "SNESSetTolerances");
        KSP ksp;
        PC  pc;
        check(SNESGetKSP(snes, &ksp), "SNESGetKSP");
        check(KSPSetType(ksp, KSPPREONLY), "KSPSetType");
        check(KSPGetPC(ksp, &pc), "KSPGetPC");
        check(PCSetType(pc, PCLU), "PCSetType");
        check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), "PCFactorSetMatSolverType");
        check(SNESSolve(snes, nullptr, d), "SNESSolve");
        SNESConvergedReason reason;
        check(SNESGetConvergedReason(snes, &reason), "SNESGetConvergedReason");
        if (reason < 0)
          throw SolverError(std::string("phase field: the damage problem did not converge (PETSc's SNES: ") +
                            SNESConvergedReasons[reason] + ")");
      }
    catch (...)
      {
        SNESDestroy(&snes);
        throw;
      }
    SNESDestroy(&snes);
    d_ghost = d;
    return distance_to(previous);
  }

  template <int dim>
  void
  DamageField<dim>::accept()
  {
    d_accepted = d;
    set_bounds();
  }

  template <int dim>
  void
  DamageField<dim>::restore()
  {
    d       = d_accepted;
    d_ghost = d;
  }

  template <int dim>
  std::vector<double>
  DamageField<dim>::owned_values() const
  {
    std::vector<double> values;
    values.reserve(owned.n_elements());
    for (const auto i : owned)
      values.push_back(d(i));
    return values;
  }

  template <int dim>
  void
  DamageField<dim>::restore_owned_values(const std::vector<double> &values)
  {
    if (values.size() != owned.n_elements())
      throw std::invalid_argument("the damage has " + std::to_string(values.size()) + " values for " +
                                  std::to_string(owned.n_elements()) + " nodes");
    std::size_t k = 0;
    for (const auto i : owned)
      d(i) = values[k++];
    d.compress(VectorOperation::insert);
    accept();
    d_ghost = d;
  }

  template <int dim>
  std::vector<std::vector<double>>
  DamageField<dim>::cell_values(const Quadrature<dim> &quadrature) const
  {
    std::vector<std::vector<double>> values(dof_d.get_triangulation().n_active_cells());
    FEValues<dim>                    fv(fe_d, quadrature, update_values);
    for (const auto &cell : dof_d.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fv.reinit(cell);
          auto &v = values[cell->active_cell_index()];
          v.resize(quadrature.size());
          fv.get_function_values(d_ghost, v);
        }
    return values;
  }

  template <int dim>
  std::vector<dealii::Vector<double>>
  DamageField<dim>::cell_dof_values() const
  {
    std::vector<dealii::Vector<double>> values(dof_d.get_triangulation().n_active_cells());
    for (const auto &cell : dof_d.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          auto &v = values[cell->active_cell_index()];
          v.reinit(fe_d.n_dofs_per_cell());
          cell->get_dof_values(d_ghost, v);
        }
    return values;
  }

  template <int dim>
  double
  DamageField<dim>::value(const dealii::Vector<double> &dof_values, const Point<dim> &unit) const
  {
    double d_at = 0;
    for (unsigned i = 0; i < dof_values.size(); ++i)
      d_at += dof_values[i] * fe_d.shape_value(i, unit);
    return d_at;
  }

  template <int dim>
  double
  DamageField<dim>::fracture_energy() const
  {
    FEValues<dim>               fv(fe_d, quadrature_d, update_values | update_gradients | update_JxW_values);
    std::vector<double>         d_q(quadrature_d.size());
    std::vector<Tensor<1, dim>> grad(quadrature_d.size());
    double                      energy = 0;
    for (const auto &cell : dof_d.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fv.reinit(cell);
          fv.get_function_values(d_ghost, d_q);
          fv.get_function_gradients(d_ghost, grad);
          for (const unsigned q : fv.quadrature_point_indices())
            energy += (d_q[q] / ell + ell * grad[q] * grad[q]) * fv.JxW(q);
        }
    return gc / c_w * Utilities::MPI::sum(energy, comm);
  }

  template <int dim>
  std::pair<double, double>
  DamageField<dim>::range() const
  {
    PetscReal lo = 0, hi = 0;
    check(VecMin(d, nullptr, &lo), "VecMin");
    check(VecMax(d, nullptr, &hi), "VecMax");
    return {lo, hi};
  }

  template <int dim>
  double
  DamageField<dim>::growth() const
  {
    return distance_to(d_accepted);
  }

  template <int dim>
  double
  DamageField<dim>::distance_to(const PETScWrappers::MPI::Vector &other) const
  {
    PETScWrappers::MPI::Vector difference(owned, comm);
    difference = d;
    difference -= other;
    return difference.linfty_norm();
  }

  template <int dim>
  double
  DamageField<dim>::extent(const std::function<double(const Point<dim> &)> &coordinate, const double at_least) const
  {
    double value = -std::numeric_limits<double>::infinity();
    for (const auto &cell : dof_d.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned v : cell->vertex_indices())
          if (d_ghost(cell->vertex_dof_index(v, 0)) >= at_least)
            value = std::max(value, coordinate(cell->vertex(v)));
    return Utilities::MPI::max(value, comm);
  }

  template <int dim>
  double
  DamageField<dim>::threshold() const
  {
    return 3 * gc / (16 * ell);
  }

  template <int dim>
  void
  DamageField<dim>::add_to(DataOut<dim> &out) const
  {
    out.add_data_vector(dof_d, d_ghost, "damage");
  }

  template class DamageField<2>;
  template class DamageField<3>;
} // namespace suturesim::tearing
