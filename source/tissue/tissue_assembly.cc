/**
 * Assembly of the tissue's residual and tangent, TissueModel::assemble(): the cells in
 * parallel over the process's threads (deal.II WorkStream), their contributions added in
 * the cells' order, so that the sums (and results) are the same with any thread count.
 */
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/base/work_stream.h>
#include <deal.II/grid/filtered_iterator.h>

namespace suturesim::tissue
{
  using namespace dealii;

  namespace
  {
    /// One thread's scratch: its own cell assembler and face values.
    struct Scratch
    {
      Scratch(const CellAssembler &cell, const Mapping<3> &mapping, const FiniteElement<3> &fe,
              const Quadrature<2> &face_quadrature)
        : assembler(cell)
        , face_values(mapping, fe, face_quadrature, update_values | update_JxW_values | update_quadrature_points)
      {}
      Scratch(const Scratch &other)
        : assembler(other.assembler)
        , face_values(other.face_values.get_mapping(), other.face_values.get_fe(),
                      other.face_values.get_quadrature(), other.face_values.get_update_flags())
      {}
      CellAssembler   assembler;
      FEFaceValues<3> face_values;
    };

    /// One cell's contribution, added to the global objects in the cells' order.
    struct Contribution
    {
      explicit Contribution(const unsigned n)
        : K(n, n)
        , r(n)
        , r_c(n)
        , u(n)
        , v(n)
        , Kv(n)
        , dofs(n)
      {}
      bool                                ok = false;
      DoFHandler<3>::active_cell_iterator cell;
      // the copier (given a const reference by WorkStream) negates r for the right-hand
      // side
      mutable FullMatrix<double>           K;
      mutable dealii::Vector<double>       r;
      dealii::Vector<double>               r_c, u, v, Kv; ///< v, Kv: Rayleigh damping's

      std::vector<types::global_dof_index> dofs;
    };

    /// The values of a ghosted vector at the locally relevant DoFs (in the order of
    /// @p relevant): threads read these instead of the PETSc vector, whose element
    /// access is not thread-safe.
    std::vector<double>
    relevant_values(const TissueModel::Vector &v, const IndexSet &relevant)
    {
      std::vector<types::global_dof_index> indices;
      indices.reserve(relevant.n_elements());
      for (const auto i : relevant)
        indices.push_back(i);
      std::vector<double> values(indices.size());
      v.extract_subvector_to(indices.begin(), indices.end(), values.begin());
      return values;
    }

    void
    gather(const std::vector<double> &values, const IndexSet &relevant,
           const std::vector<types::global_dof_index> &dofs, dealii::Vector<double> &local)
    {
      for (unsigned i = 0; i < dofs.size(); ++i)
        local[i] = values[relevant.index_within_set(dofs[i])];
    }
  } // namespace

  bool
  TissueModel::assemble(const double                     t,
                        const Vector                    &u_ghost,
                        const bool                       with_matrix,
                        const AffineConstraints<double> &c,
                        const Vector                    *velocity_ghost,
                        const bool                       exact_mixed)
  {
    const MixedUpdate update = pressure_unknowns && !exact_mixed ? MixedUpdate::newton : MixedUpdate::exact;
    TimerOutput::Scope scope(timer, with_matrix ? "assemble K and R" : "assemble R");
    if (with_matrix)
      system_matrix = 0;
    system_rhs    = 0;
    full_residual = 0;
    if (update == MixedUpdate::newton)
      constraint_force = 0;

    const unsigned             n       = fe.n_dofs_per_cell();
    const std::vector<double>  u_val   = relevant_values(u_ghost, locally_relevant_dofs);
    const bool                 damping = velocity_ghost != nullptr && rayleigh_stiffness > 0;
    const std::vector<double>  v_val   = damping ? relevant_values(*velocity_ghost, locally_relevant_dofs)
                                                 : std::vector<double>();
    const Function<3>         &traction_function = bc.traction(t); // set the time once
    const bool                 need_K            = with_matrix || damping;

    const auto worker = [&](const DoFHandler<3>::active_cell_iterator &cell, Scratch &scratch, Contribution &out) {
      out.cell = cell;
      cell->get_dof_indices(out.dofs);
      gather(u_val, locally_relevant_dofs, out.dofs, out.u);
      out.ok = scratch.assembler.assemble(cell, out.u, material, bc.gravity, out.r, need_K ? &out.K : nullptr,
                                          &cell_mixed[cell->active_cell_index()], update, &out.r_c,
                                          damage ? &cell_degradation[cell->active_cell_index()] : nullptr);
      if (!out.ok)
        return;
      if (damping)
        {
          gather(v_val, locally_relevant_dofs, out.dofs, out.v);
          out.K.vmult(out.Kv, out.v);
          out.r.add(rayleigh_stiffness, out.Kv);
        }
      add_traction(cell, traction_function, scratch.face_values, out.r);
    };

    unsigned   bad_cells = 0;
    const auto copier    = [&](const Contribution &in) {
      if (!in.ok)
        {
          ++bad_cells;
          return;
        }
      full_residual.add(in.dofs, in.r);
      if (update == MixedUpdate::newton)
        constraint_force.add(in.dofs, in.r_c);
      in.r *= -1.0;
      if (with_matrix)
        c.distribute_local_to_global(in.K, in.r, in.dofs, system_matrix, system_rhs);
      else
        c.distribute_local_to_global(in.r, in.dofs, system_rhs);
    };

    using Owned = FilteredIterator<DoFHandler<3>::active_cell_iterator>;
    WorkStream::run(Owned(IteratorFilters::LocallyOwnedCell(), dof_handler.begin_active()),
                    Owned(IteratorFilters::LocallyOwnedCell(), dof_handler.end()),
                    worker,
                    copier,
                    Scratch(*cell_assembler, mapping, fe, face_quadrature),
                    Contribution(n));

    // the point loads after the cells, on this thread: their force laws need not be
    // thread-safe, and a spread point's weights span several cells
    if (point_loads != nullptr)
      embedded->assemble(u_ghost, c, with_matrix ? &system_matrix : nullptr, system_rhs, full_residual);
    if (with_matrix)
      system_matrix.compress(VectorOperation::add);
    system_rhs.compress(VectorOperation::add);
    full_residual.compress(VectorOperation::add);
    if (update == MixedUpdate::newton)
      constraint_force.compress(VectorOperation::add);
    return Utilities::MPI::sum(bad_cells, comm) == 0;
  }

  void
  TissueModel::add_traction(const DoFHandler<3>::active_cell_iterator &cell,
                            const Function<3>                         &traction,
                            FEFaceValues<3>                           &face_values,
                            dealii::Vector<double>                    &r) const
  {
    if (bc.traction_boundaries.empty())
      return;
    dealii::Vector<double> t0(3);
    for (const auto f : cell->face_indices())
      if (cell->face(f)->at_boundary() && bc.traction_boundaries.count(cell->face(f)->boundary_id()))
        {
          face_values.reinit(cell, f);
          for (unsigned q = 0; q < face_values.n_quadrature_points; ++q)
            {
              traction.vector_value(face_values.quadrature_point(q), t0);
              for (unsigned i = 0; i < r.size(); ++i)
                r[i] -= face_values.shape_value(i, q) * t0[fe.system_to_component_index(i).first] *
                        face_values.JxW(q);
            }
        }
  }
} // namespace suturesim::tissue
