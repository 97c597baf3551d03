#include <suturesim/core/error.h>
#include <suturesim/io/checked_output.h>
#include <suturesim/tearing/phase_field.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_q.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/petsc_solver.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/base/function.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/vector_tools.h>

#include <petscsnes.h>

#include <cmath>
#include <limits>

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

    /// The damage problem's residual F(d) = A d − b (A's hanging rows hold their constraints).
    struct DamageProblem
    {
      Mat A;
      Vec b;
    };

    PetscErrorCode
    damage_residual(SNES, Vec x, Vec f, void *context)
    {
      const auto *problem = static_cast<const DamageProblem *>(context);
      PetscErrorCode code = MatMult(problem->A, x, f);
      if (code == 0)
        code = VecAXPY(f, -1.0, problem->b);
      return code;
    }

    PetscErrorCode
    damage_jacobian(SNES, Vec, Mat, Mat, void *)
    {
      return 0; // A is constant: the problem is quadratic in d
    }

    /// The cell of @p other on the same triangulation as @p cell.
    template <int dim>
    typename DoFHandler<dim>::active_cell_iterator
    same_cell(const typename DoFHandler<dim>::active_cell_iterator &cell, const DoFHandler<dim> &other)
    {
      return typename DoFHandler<dim>::active_cell_iterator(&cell->get_triangulation(), cell->level(), cell->index(),
                                                            &other);
    }
  } // namespace

  template <int dim>
  PhaseFieldFracture<dim>::PhaseFieldFracture(MPI_Comm comm, const PhaseFieldParameters &parameters,
                                              const parallel::distributed::Triangulation<dim> &tria, Loading loading)
    : comm(comm)
    , parameters(parameters)
    , tria(tria)
    , loading(std::move(loading))
    , lambda(parameters.youngs_modulus * parameters.poissons_ratio /
             ((1 + parameters.poissons_ratio) * (1 - 2 * parameters.poissons_ratio)))
    , mu(parameters.youngs_modulus / (2 * (1 + parameters.poissons_ratio)))
    , fe_u(FE_Q<dim>(1), dim)
    , fe_d(1)
    , dof_u(tria)
    , dof_d(tria)
  {
    setup();
  }

  template <int dim>
  PhaseFieldFracture<dim>::~PhaseFieldFracture() = default;

  template <int dim>
  void
  PhaseFieldFracture<dim>::setup()
  {
    dof_u.distribute_dofs(fe_u);
    dof_d.distribute_dofs(fe_d);
    owned_u = dof_u.locally_owned_dofs();
    owned_d = dof_d.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_u, relevant_u);
    DoFTools::extract_locally_relevant_dofs(dof_d, relevant_d);

    make_displacement_constraints(0);

    constraints_d.reinit(relevant_d);
    DoFTools::make_hanging_node_constraints(dof_d, constraints_d);
    constraints_d.close();

    DynamicSparsityPattern dsp_u(relevant_u);
    DoFTools::make_sparsity_pattern(dof_u, dsp_u, constraints_u, false);
    SparsityTools::distribute_sparsity_pattern(dsp_u, owned_u, comm, relevant_u);
    stiffness.reinit(owned_u, owned_u, dsp_u, comm);
    // the damage rows of hanging nodes hold their constraint equations (set_bounds()), so
    // the pattern keeps their couplings
    DynamicSparsityPattern dsp_d(relevant_d);
    DoFTools::make_sparsity_pattern(dof_d, dsp_d, constraints_d, true);
    SparsityTools::distribute_sparsity_pattern(dsp_d, owned_d, comm, relevant_d);
    damage_matrix.reinit(owned_d, owned_d, dsp_d, comm);

    u.reinit(owned_u, comm);
    u_accepted.reinit(owned_u, comm);
    u_ghost.reinit(owned_u, relevant_u, comm);
    d.reinit(owned_d, comm);
    d_accepted.reinit(owned_d, comm);
    d_ghost.reinit(owned_d, relevant_d, comm);
    damage_rhs.reinit(owned_d, comm);
    lower.reinit(owned_d, comm);
    upper.reinit(owned_d, comm);

    // the initial crack
    std::map<types::global_dof_index, Point<dim>> support_points;
    DoFTools::map_dofs_to_support_points(MappingQ<dim>(1), dof_d, support_points);
    for (const auto &[index, point] : support_points)
      if (owned_d.is_element(index) && loading.cracked && loading.cracked(point) &&
          !constraints_d.is_constrained(index))
        d(index) = 1;
    d.compress(VectorOperation::insert);
    d_accepted = d;
    set_bounds();
  }

  template <int dim>
  void
  PhaseFieldFracture<dim>::make_displacement_constraints(const double load)
  {
    constraints_u.clear();
    constraints_u.reinit(relevant_u);
    DoFTools::make_hanging_node_constraints(dof_u, constraints_u);
    unsigned pinned = 0;
    for (const auto &pin : loading.pins)
      {
        unsigned found = 0;
        for (const auto &cell : dof_u.active_cell_iterators())
          if (cell->is_locally_owned())
            for (const unsigned v : cell->vertex_indices())
              if (cell->vertex(v).distance(pin.point) < 1e-9 * cell->diameter())
                {
                  found = 1;
                  for (unsigned c = 0; c < dim; ++c)
                    if (pin.components[c])
                      {
                        const auto i = cell->vertex_dof_index(v, c);
                        if (!constraints_u.is_constrained(i))
                          constraints_u.add_line(i);
                      }
                }
        pinned += Utilities::MPI::max(found, comm);
      }
    if (pinned != loading.pins.size())
      throw InputError("phase field: a pinned point is not a vertex of the mesh");
    for (const auto &support : loading.supports)
      {
        Vector<double> value(dim);
        for (unsigned c = 0; c < dim; ++c)
          value[c] = load * support.displacement[c];
        VectorTools::interpolate_boundary_values(dof_u, support.boundary, Functions::ConstantFunction<dim>(value),
                                                 constraints_u, support.components);
      }
    constraints_u.close();
  }

  template <int dim>
  void
  PhaseFieldFracture<dim>::set_bounds()
  {
    // lower: the accepted damage (the crack never heals); upper: 1. A hanging node is free
    // of bounds: its row is its constraint, and it is a mean of bounded values.
    lower = d_accepted;
    upper = 1.0;
    for (const auto i : owned_d)
      if (constraints_d.is_constrained(i))
        {
          lower(i) = PETSC_NINFINITY;
          upper(i) = PETSC_INFINITY;
        }
    lower.compress(VectorOperation::insert);
    upper.compress(VectorOperation::insert);
  }

  template <int dim>
  void
  PhaseFieldFracture<dim>::solve_displacement(const double load)
  {
    make_displacement_constraints(load);
    stiffness = 0;
    PETScWrappers::MPI::Vector rhs(owned_u, comm);
    const QGauss<dim>          quadrature(2);
    const QGauss<dim - 1>      face_quadrature(2);
    FEValues<dim>              fv_u(fe_u, quadrature, update_gradients | update_JxW_values);
    FEValues<dim>              fv_d(fe_d, quadrature, update_values);
    FEFaceValues<dim>          fv_face(fe_u, face_quadrature, update_values | update_JxW_values);
    const FEValuesExtractors::Vector displacement(0);
    const unsigned                   n = fe_u.n_dofs_per_cell();
    FullMatrix<double>               cell_matrix(n, n);
    Vector<double>                   cell_rhs(n);
    std::vector<types::global_dof_index> indices(n);
    std::vector<double>                  d_q(quadrature.size());
    std::vector<SymmetricTensor<2, dim>> eps(n);
    const double                         k = parameters.residual_stiffness;

    for (const auto &cell : dof_u.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fv_u.reinit(cell);
          fv_d.reinit(same_cell(cell, dof_d));
          fv_d.get_function_values(d_ghost, d_q);
          cell_matrix = 0;
          cell_rhs    = 0;
          for (const unsigned q : fv_u.quadrature_point_indices())
            {
              const double g = (1 - d_q[q]) * (1 - d_q[q]) + k;
              for (unsigned i = 0; i < n; ++i)
                eps[i] = fv_u[displacement].symmetric_gradient(i, q);
              for (unsigned i = 0; i < n; ++i)
                {
                  // σ(ε_i) = λ tr ε_i I + 2 μ ε_i
                  const SymmetricTensor<2, dim> sigma =
                    lambda * trace(eps[i]) * unit_symmetric_tensor<dim>() + 2 * mu * eps[i];
                  for (unsigned j = 0; j <= i; ++j)
                    cell_matrix(i, j) += g * (sigma * eps[j]) * fv_u.JxW(q);
                }
            }
          for (unsigned i = 0; i < n; ++i)
            for (unsigned j = i + 1; j < n; ++j)
              cell_matrix(i, j) = cell_matrix(j, i);
          for (const auto &face : cell->face_iterators())
            if (face->at_boundary() && loading.tractions.count(face->boundary_id()))
              {
                fv_face.reinit(cell, face);
                const Tensor<1, dim> t = load * loading.tractions.at(face->boundary_id());
                for (const unsigned q : fv_face.quadrature_point_indices())
                  for (unsigned i = 0; i < n; ++i)
                    cell_rhs(i) += t * fv_face[displacement].value(i, q) * fv_face.JxW(q);
              }
          cell->get_dof_indices(indices);
          constraints_u.distribute_local_to_global(cell_matrix, cell_rhs, indices, stiffness, rhs);
        }
    stiffness.compress(VectorOperation::add);
    rhs.compress(VectorOperation::add);

    SolverControl                    control(1, 0);
    PETScWrappers::SparseDirectMUMPS direct(control, comm);
    direct.set_symmetric_mode(true);
    direct.solve(stiffness, u, rhs);
    constraints_u.distribute(u);
    u_ghost = u;
  }

  template <int dim>
  void
  PhaseFieldFracture<dim>::solve_damage()
  {
    damage_matrix = 0;
    damage_rhs    = 0;
    const QGauss<dim> quadrature(2);
    FEValues<dim>     fv_u(fe_u, quadrature, update_gradients);
    FEValues<dim>     fv_d(fe_d, quadrature, update_values | update_gradients | update_JxW_values);
    const FEValuesExtractors::Vector displacement(0);
    const unsigned                   n = fe_d.n_dofs_per_cell();
    FullMatrix<double>               cell_matrix(n, n);
    Vector<double>                   cell_rhs(n);
    std::vector<types::global_dof_index> indices(n);
    std::vector<SymmetricTensor<2, dim>> strain(quadrature.size());
    const double gc = parameters.toughness, ell = parameters.length;

    for (const auto &cell : dof_d.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fv_d.reinit(cell);
          fv_u.reinit(same_cell(cell, dof_u));
          fv_u[displacement].get_function_symmetric_gradients(u_ghost, strain);
          cell_matrix = 0;
          cell_rhs    = 0;
          for (const unsigned q : fv_d.quadrature_point_indices())
            {
              const double psi = 0.5 * lambda * trace(strain[q]) * trace(strain[q]) + mu * strain[q] * strain[q];
              // ∂/∂d of (1 − d)² ψ + G_c/c_w (d/ℓ + ℓ |∇d|²) in the direction φ_i
              for (unsigned i = 0; i < n; ++i)
                {
                  const double phi_i = fv_d.shape_value(i, q);
                  for (unsigned j = 0; j < n; ++j)
                    cell_matrix(i, j) += (2 * psi * phi_i * fv_d.shape_value(j, q) +
                                          2 * gc * ell / c_w * (fv_d.shape_grad(i, q) * fv_d.shape_grad(j, q))) *
                                         fv_d.JxW(q);
                  cell_rhs(i) += (2 * psi - gc / (c_w * ell)) * phi_i * fv_d.JxW(q);
                }
            }
          cell->get_dof_indices(indices);
          constraints_d.distribute_local_to_global(cell_matrix, cell_rhs, indices, damage_matrix, damage_rhs);
        }
    damage_matrix.compress(VectorOperation::add);
    damage_rhs.compress(VectorOperation::add);
    // a hanging node's row: d_i − Σ c_ij d_j = 0
    for (const auto i : owned_d)
      if (const auto *entries = constraints_d.get_constraint_entries(i))
        {
          damage_matrix.set(i, i, 1.0);
          for (const auto &[j, c] : *entries)
            damage_matrix.set(i, j, -c);
        }
    damage_matrix.compress(VectorOperation::insert);

    DamageProblem problem{damage_matrix.petsc_matrix(), damage_rhs};
    PETScWrappers::MPI::Vector residual(owned_d, comm);
    SNES snes;
    check(SNESCreate(comm, &snes), "SNESCreate");
    try
      {
        check(SNESSetType(snes, SNESVINEWTONRSLS), "SNESSetType");
        check(SNESSetFunction(snes, residual, damage_residual, &problem), "SNESSetFunction");
        check(SNESSetJacobian(snes, problem.A, problem.A, damage_jacobian, nullptr), "SNESSetJacobian");
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
  }

  template <int dim>
  typename PhaseFieldFracture<dim>::Step
  PhaseFieldFracture<dim>::solve(const double load, const std::function<bool()> &stop)
  {
    Step                       step;
    PETScWrappers::MPI::Vector previous(owned_d, comm);
    d_ghost = d;
    while (step.iterations < parameters.max_iterations)
      {
        ++step.iterations;
        solve_displacement(load);
        previous = d;
        solve_damage();
        previous -= d;
        step.change = previous.linfty_norm();
        if (step.change <= parameters.tolerance)
          {
            // u of the converged damage, so that the state is a pair of minimisers
            solve_displacement(load);
            step.converged = true;
            return step;
          }
        if (stop && stop())
          {
            step.stopped = true;
            return step;
          }
      }
    throw SolverError("phase field: the alternate minimisation did not converge in " +
                      std::to_string(parameters.max_iterations) + " iterations at load factor " + std::to_string(load) +
                      " (largest damage change " + std::to_string(step.change) + ")");
  }

  template <int dim>
  void
  PhaseFieldFracture<dim>::accept()
  {
    u_accepted = u;
    d_accepted = d;
    set_bounds();
  }

  template <int dim>
  void
  PhaseFieldFracture<dim>::restore()
  {
    u       = u_accepted;
    d       = d_accepted;
    u_ghost = u;
    d_ghost = d;
  }

  template <int dim>
  double
  PhaseFieldFracture<dim>::elastic_energy() const
  {
    const QGauss<dim> quadrature(2);
    FEValues<dim>     fv_u(fe_u, quadrature, update_gradients | update_JxW_values);
    FEValues<dim>     fv_d(fe_d, quadrature, update_values);
    const FEValuesExtractors::Vector     displacement(0);
    std::vector<SymmetricTensor<2, dim>> strain(quadrature.size());
    std::vector<double>                  d_q(quadrature.size());
    double                               energy = 0;
    for (const auto &cell : dof_u.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fv_u.reinit(cell);
          fv_d.reinit(same_cell(cell, dof_d));
          fv_u[displacement].get_function_symmetric_gradients(u_ghost, strain);
          fv_d.get_function_values(d_ghost, d_q);
          for (const unsigned q : fv_u.quadrature_point_indices())
            energy += ((1 - d_q[q]) * (1 - d_q[q]) + parameters.residual_stiffness) *
                      (0.5 * lambda * trace(strain[q]) * trace(strain[q]) + mu * strain[q] * strain[q]) * fv_u.JxW(q);
        }
    return Utilities::MPI::sum(energy, comm);
  }

  template <int dim>
  double
  PhaseFieldFracture<dim>::fracture_energy() const
  {
    const QGauss<dim>           quadrature(2);
    FEValues<dim>               fv_d(fe_d, quadrature, update_values | update_gradients | update_JxW_values);
    std::vector<double>         d_q(quadrature.size());
    std::vector<Tensor<1, dim>> grad(quadrature.size());
    double                      energy = 0;
    const double                ell    = parameters.length;
    for (const auto &cell : dof_d.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fv_d.reinit(cell);
          fv_d.get_function_values(d_ghost, d_q);
          fv_d.get_function_gradients(d_ghost, grad);
          for (const unsigned q : fv_d.quadrature_point_indices())
            energy += (d_q[q] / ell + ell * grad[q] * grad[q]) * fv_d.JxW(q);
        }
    return parameters.toughness / c_w * Utilities::MPI::sum(energy, comm);
  }

  template <int dim>
  double
  PhaseFieldFracture<dim>::damage_extent(const std::function<double(const Point<dim> &)> &coordinate,
                                         const double                                     threshold) const
  {
    double extent = -std::numeric_limits<double>::infinity();
    for (const auto &cell : dof_d.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const unsigned v : cell->vertex_indices())
          if (d_ghost(cell->vertex_dof_index(v, 0)) >= threshold)
            extent = std::max(extent, coordinate(cell->vertex(v)));
    return Utilities::MPI::max(extent, comm);
  }

  template <int dim>
  std::pair<double, double>
  PhaseFieldFracture<dim>::damage_range() const
  {
    PetscReal lo = 0, hi = 0;
    check(VecMin(d, nullptr, &lo), "VecMin");
    check(VecMax(d, nullptr, &hi), "VecMax");
    return {lo, hi};
  }

  template <int dim>
  Tensor<1, dim>
  PhaseFieldFracture<dim>::displacement_at(const Point<dim> &point) const
  {
    Tensor<1, dim> value;
    unsigned       found = 0;
    for (const auto &cell : dof_u.active_cell_iterators())
      if (cell->is_locally_owned() && found == 0)
        for (const unsigned v : cell->vertex_indices())
          if (found == 0 && cell->vertex(v).distance(point) < 1e-9 * cell->diameter())
            {
              found = 1;
              for (unsigned c = 0; c < dim; ++c)
                value[c] = u_ghost(cell->vertex_dof_index(v, c));
            }
    // the lowest rank that has it speaks for all
    const unsigned rank  = found ? Utilities::MPI::this_mpi_process(comm) : Utilities::MPI::n_mpi_processes(comm);
    const unsigned owner = Utilities::MPI::min(rank, comm);
    if (owner == Utilities::MPI::n_mpi_processes(comm))
      throw InputError("phase field: a probed point is not a vertex of the mesh");
    if (rank != owner)
      value = 0;
    for (unsigned c = 0; c < dim; ++c)
      value[c] = Utilities::MPI::sum(value[c], comm);
    return value;
  }

  template <int dim>
  double
  PhaseFieldFracture<dim>::smallest_cell_size(const std::function<bool(const Point<dim> &)> &where) const
  {
    double h = std::numeric_limits<double>::infinity();
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned() && (!where || where(cell->center())))
        h = std::min(h, std::pow(cell->measure(), 1.0 / dim));
    return Utilities::MPI::min(h, comm);
  }

  template <int dim>
  double
  PhaseFieldFracture<dim>::effective_toughness(const double h) const
  {
    return parameters.toughness * (1 + 3 * h / (8 * parameters.length));
  }

  template <int dim>
  double
  PhaseFieldFracture<dim>::damage_threshold() const
  {
    return 3 * parameters.toughness / (16 * parameters.length);
  }

  template <int dim>
  types::global_dof_index
  PhaseFieldFracture<dim>::n_dofs() const
  {
    return dof_u.n_dofs() + dof_d.n_dofs();
  }

  template <int dim>
  void
  PhaseFieldFracture<dim>::write_vtu(const std::string &file, const double time, const unsigned index) const
  {
    DataOut<dim> data_out;
    data_out.attach_triangulation(tria);
    data_out.add_data_vector(dof_u, u_ghost, std::vector<std::string>(dim, "displacement"),
                             std::vector<DataComponentInterpretation::DataComponentInterpretation>(
                               dim, DataComponentInterpretation::component_is_part_of_vector));
    data_out.add_data_vector(dof_d, d_ghost, "damage");
    data_out.build_patches();
    DataOutBase::VtkFlags flags(time, index);
    data_out.set_flags(flags);
    try
      {
        data_out.write_vtu_in_parallel(file, comm);
      }
    catch (const ExceptionBase &)
      {
        throw io::WriteError(file + ": cannot be written (MPI-IO)");
      }
  }

  template class PhaseFieldFracture<2>;
  template class PhaseFieldFracture<3>;
} // namespace suturesim::tearing
