/**
 * What the tissue reports per step: reaction forces on the Dirichlet boundaries,
 * displacements at the probe points, and the VTU fields (displacement, Cauchy and von
 * Mises stress, J, the largest principal stretch, pressure, material and rank per cell);
 * with the setup of the reaction DoFs and of the probes' cells.
 */
#include <suturesim/io/checked_output.h>
#include <suturesim/core/error.h>
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>
#include <deal.II/numerics/vector_tools.h>

#include <cmath>
#include <filesystem>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

namespace suturesim::tissue
{
  using namespace dealii;

  // --- output fields ------------------------------------------------------------------

  namespace
  {
    /// Cauchy stress (tensor), von Mises stress, J, largest principal stretch and
    /// pressure at the output points, from the displacement gradient (and, for the mixed
    /// formulation, the cell's condensed pressure p̃; with the phase field, the isochoric
    /// stress degraded by the damage there, (1 − k)(1 − d)² + k).
    class StressPostprocessor : public DataPostprocessor<3>
    {
    public:
      StressPostprocessor(const Material                          &material,
                          const std::vector<MixedCell> *pressure,
                          const tearing::DamageField<3> *damage, const double residual_stiffness)
        : material(material)
        , pressure(pressure)
        , damage(damage)
        , damage_values(damage != nullptr ? damage->cell_dof_values() : std::vector<dealii::Vector<double>>())
        , k(residual_stiffness)
      {}

      void
      evaluate_vector_field(const DataPostprocessorInputs::Vector<3> &in,
                            std::vector<dealii::Vector<double>>      &out) const override
      {
        const auto cell = in.template get_cell<3>();
        for (unsigned q = 0; q < in.solution_gradients.size(); ++q)
          {
            Tensor2 F = unit_symmetric_tensor<3>();
            for (unsigned i = 0; i < 3; ++i)
              F[i] += in.solution_gradients[q][i];
            const double J = determinant(F);
            // the phase field's g there (1 without): σ = g σ_iso + p I, the mixed p̃
            // already degraded in expansion, the displacement form's p here
            const double g =
              damage != nullptr
                ? degradation(
                    damage->value(damage_values[cell->active_cell_index()],
                                  mapping.transform_real_to_unit_cell(cell, in.evaluation_points[q])),
                    k)
                : 1.0;
            double p = 0;
            if (pressure != nullptr)
              p = (*pressure)[cell->active_cell_index()]
                    .at(in.evaluation_points[q], cell->center(), cell->diameter())
                    .first;
            else if (J > 0)
              p = volumetric_share(g, J) * material.volumetric().pressure(J);
            SymTensor2 sigma = J > 0 ? material.cauchy_stress(F, p) : SymTensor2();
            if (g < 1 && J > 0)
              sigma -= (1 - g) * material.cauchy_stress(F, 0);
            for (unsigned i = 0; i < 3; ++i)
              for (unsigned j = 0; j < 3; ++j)
                out[q][3 * i + j] = sigma[i][j];
            const SymTensor2 s = deviator(sigma);
            out[q][9]          = std::sqrt(1.5 * (s * s));
            out[q][10]         = J;
            const SymTensor2 C = symmetrize(transpose(F) * F);
            out[q][11]         = std::sqrt(eigenvalues(C)[0]);
            out[q][12]         = p;
          }
      }

      std::vector<std::string>
      get_names() const override
      {
        std::vector<std::string> names(9, "cauchy_stress");
        names.insert(names.end(),
                     {"von_mises_stress", "J", "max_principal_stretch", "pressure"});
        return names;
      }

      std::vector<DataComponentInterpretation::DataComponentInterpretation>
      get_data_component_interpretation() const override
      {
        std::vector<DataComponentInterpretation::DataComponentInterpretation> v(
          9, DataComponentInterpretation::component_is_part_of_tensor);
        v.insert(v.end(), 4, DataComponentInterpretation::component_is_scalar);
        return v;
      }

      UpdateFlags
      get_needed_update_flags() const override
      {
        return update_gradients | update_quadrature_points;
      }

    private:
      const Material                          &material;
      const std::vector<MixedCell> *pressure;
      const tearing::DamageField<3> *damage;
      /// d's nodal values per cell, copied before the threads of build_patches() read them
      /// (a PETSc vector is not to be read from several threads)
      std::vector<dealii::Vector<double>> damage_values;
      double                              k;
      MappingQ1<3>                   mapping;
    };
  } // namespace

  void
  TissueModel::find_reaction_dofs()
  {
    // DoFs of each Dirichlet boundary with their component, for the reactions: the
    // DoFs that boundary constrains (first listed wins, as in make_constraints), only in
    // the constrained components, found on every non-artificial cell so that the sets
    // do not depend on the partition.
    reaction_dofs.assign(bc.dirichlet.size(), {});
    std::set<types::global_dof_index> taken;
    for (std::size_t b = 0; b < bc.dirichlet.size(); ++b)
      for (unsigned c = 0; c < 3; ++c)
        if (bc.dirichlet[b].components[c])
          {
            std::vector<bool> only_c(3, false);
            only_c[c] = true;
            std::map<types::global_dof_index, double> values;
            VectorTools::interpolate_boundary_values(mapping, dof_handler, bc.dirichlet[b].id,
                                                     Functions::ZeroFunction<3>(3), values,
                                                     ComponentMask(only_c));
            for (const auto &[dof, value] : values)
              if (taken.insert(dof).second && locally_owned_dofs.is_element(dof))
                reaction_dofs[b].emplace_back(dof, c);
          }
  }

  void
  TissueModel::locate_probes()
  {
    // Probes: the lowest rank whose locally owned cell holds the point evaluates it.
    probe_locations.assign(parameters.probes.size(), {});
    const unsigned rank = Utilities::MPI::this_mpi_process(comm);
    for (std::size_t p = 0; p < parameters.probes.size(); ++p)
      {
        unsigned owner = numbers::invalid_unsigned_int;
        try
          {
            const auto found = GridTools::find_active_cell_around_point(
              mapping, dof_handler, parameters.probes[p].second);
            // On a distributed mesh a point outside this rank's cells gives an
            // invalid iterator rather than an exception.
            if (found.first.state() == IteratorState::valid && found.first->is_locally_owned())
              {
                probe_locations[p].cell       = found.first;
                probe_locations[p].unit_point = found.second;
                owner                         = rank;
              }
          }
        catch (...)
          {
            // not in this rank's part of the mesh
          }
        const unsigned lowest = Utilities::MPI::min(owner, comm);
        if (lowest == numbers::invalid_unsigned_int)
          {
            std::ostringstream s;
            s << "probe '" << parameters.probes[p].first << "' at ("
              << parameters.probes[p].second << ") m lies outside the mesh";
            throw InputError(s.str());
          }
        probe_locations[p].here = (lowest == rank);
      }
  }

  std::vector<Reaction>
  TissueModel::reactions(const double t, const Vector *velocity, const Vector *acceleration)
  {
    // R = f_int − f_ext (+ M v̇ + C v in dynamics) at the state; on Dirichlet DoFs it is
    // the force the support must exert on the tissue.
    solution_ghost = solution;
    AffineConstraints<double> none;
    none.close();
    if (velocity != nullptr && acceleration != nullptr)
      {
        Vector v_ghost(locally_owned_dofs, locally_relevant_dofs, comm);
        v_ghost = *velocity;
        assemble(t, solution_ghost, false, none, &v_ghost, true); // includes a_K K_t v
        Vector inertia(locally_owned_dofs, comm), tmp(locally_owned_dofs, comm);
        tmp = *acceleration;
        tmp.add(rayleigh_mass, *velocity);
        mass_matrix.vmult(inertia, tmp);
        full_residual.add(1.0, inertia);
      }
    else
      assemble(t, solution_ghost, false, none);
    std::vector<Reaction> result;
    for (std::size_t b = 0; b < bc.dirichlet.size(); ++b)
      {
        Tensor<1, 3> f;
        for (const auto &[dof, comp] : reaction_dofs[b])
          f[comp] += full_residual[dof];
        for (unsigned d = 0; d < 3; ++d)
          f[d] = Utilities::MPI::sum(f[d], comm);
        result.push_back({bc.dirichlet[b].name, f});
      }
    return result;
  }

  std::vector<Tensor<1, 3>>
  TissueModel::probe_displacements() const
  {
    Vector ghost(locally_owned_dofs, locally_relevant_dofs, comm);
    ghost = solution;
    std::vector<Tensor<1, 3>> result(probe_locations.size());
    for (std::size_t p = 0; p < probe_locations.size(); ++p)
      {
        Tensor<1, 3> u;
        if (probe_locations[p].here)
          {
            FEValues<3> values(mapping, fe, Quadrature<3>(probe_locations[p].unit_point),
                               update_values);
            const DoFHandler<3>::active_cell_iterator &cell = probe_locations[p].cell;
            values.reinit(cell);
            dealii::Vector<double> local(fe.n_dofs_per_cell());
            cell->get_dof_values(ghost, local);
            for (unsigned i = 0; i < local.size(); ++i)
              u[fe.system_to_component_index(i).first] += local[i] * values.shape_value(i, 0);
          }
        for (unsigned d = 0; d < 3; ++d)
          result[p][d] = Utilities::MPI::sum(u[d], comm);
      }
    return result;
  }

  std::string
  TissueModel::write_vtu(const std::string &directory, const unsigned index, const double t) const
  {
    TimerOutput::Scope scope(timer, "output");
    Vector ghost(locally_owned_dofs, locally_relevant_dofs, comm);
    ghost = solution;

    DataOut<3> data_out;
    data_out.attach_dof_handler(dof_handler);
    data_out.add_data_vector(ghost,
                             std::vector<std::string>(3, "displacement"),
                             DataOut<3>::type_dof_data,
                             std::vector<DataComponentInterpretation::DataComponentInterpretation>(
                               3, DataComponentInterpretation::component_is_part_of_vector));
    const StressPostprocessor stress(material, parameters.formulation == "mixed" ? &cell_mixed : nullptr,
                                     damage.get(), parameters.phase_field.residual_stiffness);
    data_out.add_data_vector(ghost, stress);
    if (damage)
      damage->add_to(data_out);

    dealii::Vector<float> material_id(tria.n_active_cells()), rank(tria.n_active_cells());
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          material_id[cell->active_cell_index()] = cell->material_id();
          rank[cell->active_cell_index()]        = cell->subdomain_id();
        }
    data_out.add_data_vector(material_id, "material_id", DataOut<3>::type_cell_data);
    data_out.add_data_vector(rank, "mpi_rank", DataOut<3>::type_cell_data);
    for (const auto &[name, field] : tear_fields)
      data_out.add_data_vector(field, name, DataOut<3>::type_cell_data);
    data_out.build_patches(mapping, parameters.degree);

    DataOutBase::VtkFlags flags(t, index);
    flags.compression_level = DataOutBase::VtkFlags::ZlibCompressionLevel::best_speed;
    data_out.set_flags(flags);
    std::ostringstream name;
    name << "tissue_" << std::setw(5) << std::setfill('0') << index << ".vtu";
    const std::string file = (std::filesystem::path(directory) / name.str()).string();
    try
      {
        data_out.write_vtu_in_parallel(file, comm);
      }
    catch (const ExceptionBase &)
      {
        // MPI-IO's failure (a full disk, a folder gone) as a deal.II exception
        throw io::WriteError(file + ": cannot be written (MPI-IO)");
      }
    return name.str();
  }
} // namespace suturesim::tissue
