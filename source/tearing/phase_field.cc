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

#include <cmath>
#include <limits>

namespace suturesim::tearing
{
  using namespace dealii;

  namespace
  {
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
    , dof_u(tria)
    , damage(comm, tria, parameters.toughness, parameters.length)
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
    owned_u = dof_u.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_u, relevant_u);

    make_displacement_constraints(0);

    DynamicSparsityPattern dsp_u(relevant_u);
    DoFTools::make_sparsity_pattern(dof_u, dsp_u, constraints_u, false);
    SparsityTools::distribute_sparsity_pattern(dsp_u, owned_u, comm, relevant_u);
    stiffness.reinit(owned_u, owned_u, dsp_u, comm);

    u.reinit(owned_u, comm);
    u_accepted.reinit(owned_u, comm);
    u_ghost.reinit(owned_u, relevant_u, comm);
    if (loading.cracked)
      damage.crack(loading.cracked);
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
  PhaseFieldFracture<dim>::solve_displacement(const double load)
  {
    make_displacement_constraints(load);
    stiffness = 0;
    PETScWrappers::MPI::Vector rhs(owned_u, comm);
    const QGauss<dim>          quadrature(2);
    const QGauss<dim - 1>      face_quadrature(2);
    FEValues<dim>              fv_u(fe_u, quadrature, update_gradients | update_JxW_values);
    FEValues<dim>              fv_d(damage.dof_handler().get_fe(), quadrature, update_values);
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
          fv_d.reinit(same_cell(cell, damage.dof_handler()));
          fv_d.get_function_values(damage.ghosted(), d_q);
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
  double
  PhaseFieldFracture<dim>::solve_damage()
  {
    FEValues<dim> fv_u(fe_u, damage.quadrature(), update_gradients);
    const FEValuesExtractors::Vector     displacement(0);
    std::vector<SymmetricTensor<2, dim>> strain(damage.quadrature().size());
    return damage.solve([&](const typename DamageField<dim>::Cell &cell, std::vector<double> &psi) {
      fv_u.reinit(typename DoFHandler<dim>::active_cell_iterator(&tria, cell->level(), cell->index(), &dof_u));
      fv_u[displacement].get_function_symmetric_gradients(u_ghost, strain);
      for (unsigned q = 0; q < psi.size(); ++q)
        psi[q] = 0.5 * lambda * trace(strain[q]) * trace(strain[q]) + mu * strain[q] * strain[q];
    });
  }

  template <int dim>
  typename PhaseFieldFracture<dim>::Step
  PhaseFieldFracture<dim>::solve(const double load, const std::function<bool()> &stop)
  {
    Step step;
    while (step.iterations < parameters.max_iterations)
      {
        ++step.iterations;
        solve_displacement(load);
        step.change = solve_damage();
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
    damage.accept();
  }

  template <int dim>
  void
  PhaseFieldFracture<dim>::restore()
  {
    u       = u_accepted;
    u_ghost = u;
    damage.restore();
  }

  template <int dim>
  double
  PhaseFieldFracture<dim>::elastic_energy() const
  {
    const QGauss<dim> quadrature(2);
    FEValues<dim>     fv_u(fe_u, quadrature, update_gradients | update_JxW_values);
    FEValues<dim>     fv_d(damage.dof_handler().get_fe(), quadrature, update_values);
    const FEValuesExtractors::Vector     displacement(0);
    std::vector<SymmetricTensor<2, dim>> strain(quadrature.size());
    std::vector<double>                  d_q(quadrature.size());
    double                               energy = 0;
    for (const auto &cell : dof_u.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          fv_u.reinit(cell);
          fv_d.reinit(same_cell(cell, damage.dof_handler()));
          fv_u[displacement].get_function_symmetric_gradients(u_ghost, strain);
          fv_d.get_function_values(damage.ghosted(), d_q);
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
    return damage.fracture_energy();
  }

  template <int dim>
  double
  PhaseFieldFracture<dim>::damage_extent(const std::function<double(const Point<dim> &)> &coordinate,
                                         const double                                     threshold) const
  {
    return damage.extent(coordinate, threshold);
  }

  template <int dim>
  std::pair<double, double>
  PhaseFieldFracture<dim>::damage_range() const
  {
    return damage.range();
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
    return damage.threshold();
  }

  template <int dim>
  types::global_dof_index
  PhaseFieldFracture<dim>::n_dofs() const
  {
    return dof_u.n_dofs() + damage.n_dofs();
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
    damage.add_to(data_out);
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
