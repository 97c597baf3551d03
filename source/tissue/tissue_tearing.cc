/**
 * The tear criteria on the FE tissue: each criterion's measure at every quadrature point
 * (F from the displacement gradient, σ and Ψ from the material, with the cell's p̃ and J̃
 * in the mixed formulation and the phase field's degradation), accumulated over the
 * process zones that hold the point and reduced over the ranks; and per cell the mean of
 * m / m_c for the VTU.
 */
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/base/mpi.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>

#include <tuple>

namespace suturesim::tissue
{
  using namespace dealii;

  namespace
  {
    tearing::Point3
    point3(const Tensor<1, 3> &x)
    {
      return {{x[0], x[1], x[2]}};
    }

    /// Every rank's partial sums of one zone, merged (the same result on every rank).
    tearing::ZoneSample
    reduce(const tearing::ZoneSample &local, const MPI_Comm comm)
    {
      tearing::ZoneSample whole;
      for (const auto &part : Utilities::MPI::all_gather(comm, local))
        whole.merge(part);
      return whole;
    }
  } // namespace

  std::vector<std::vector<tearing::ZoneSample>>
  TissueModel::evaluate_tearing(const tearing::TearCriteria &criteria, const tearing::ProcessZones &zones)
  {
    TimerOutput::Scope scope(timer, "tearing");
    Vector             ghost(locally_owned_dofs, locally_relevant_dofs, comm);
    ghost = solution;

    const bool         mixed = parameters.formulation == "mixed";
    const QGauss<3>    quadrature(parameters.degree + 1);
    FEValues<3>        values(mapping, fe, quadrature, update_gradients | update_quadrature_points | update_JxW_values);
    const FEValuesExtractors::Vector u(0);
    std::vector<Tensor<2, 3>>        grad_u(quadrature.size());
    std::vector<unsigned int>        inside;

    const std::size_t n_criteria = criteria.criteria.size();
    std::vector<std::vector<tearing::ZoneSample>> samples(n_criteria, std::vector<tearing::ZoneSample>(zones.size()));
    tear_fields.assign(n_criteria, {});
    std::vector<double> critical(n_criteria);
    for (std::size_t c = 0; c < n_criteria; ++c)
      {
        tear_fields[c] = {"tear_" + criteria.criteria[c].first, dealii::Vector<float>(tria.n_active_cells())};
        critical[c]    = criteria.criteria[c].second->critical_value(zones.radius());
      }

    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          values.reinit(cell);
          values[u].get_function_gradients(ghost, grad_u);
          std::vector<double> cell_ratio(n_criteria, 0.0);
          double              cell_volume = 0;
          for (unsigned int q = 0; q < quadrature.size(); ++q)
            {
              tearing::MaterialPointState state;
              state.F        = unit_symmetric_tensor<3>() + grad_u[q];
              const double J = determinant(state.F);
              if (!(J > 0))
                continue; // an inverted point has no state (the solver never accepts one)
              const SymTensor2 C = symmetrize(transpose(state.F) * state.F);
              // g < 1 where the phase field has torn the tissue: σ = g σ_iso + p I and
              // Ψ = g Ψ_iso(C̄) + g_v Ψ_vol(J̃), the energy the mixed (Hu–Washizu) form stores;
              // the mixed p̃ already carries g_v
              const double g = degradation(cell->active_cell_index(), q);
              double       p = volumetric_share(g, J) * material.volumetric().pressure(J), J_tilde = J;
              if (mixed)
                std::tie(p, J_tilde) =
                  cell_mixed[cell->active_cell_index()].at(values.quadrature_point(q), cell->center(), cell->diameter());
              state.cauchy_stress = material.cauchy_stress(state.F, p);
              if (g < 1)
                state.cauchy_stress -= (1 - g) * material.cauchy_stress(state.F, 0);
              state.energy =
                g * material.isochoric_energy(C) + volumetric_share(g, J_tilde) * material.volumetric().energy(J_tilde);

              const auto X = point3(values.quadrature_point(q));
              zones.zones_containing(X, inside);
              cell_volume += values.JxW(q);
              for (std::size_t c = 0; c < n_criteria; ++c)
                {
                  const auto m = criteria.criteria[c].second->measure(state);
                  cell_ratio[c] += values.JxW(q) * m.value / critical[c];
                  for (const unsigned int z : inside)
                    samples[c][z].add(values.JxW(q), m.value, X, point3(m.direction));
                }
            }
          for (std::size_t c = 0; c < n_criteria; ++c)
            tear_fields[c].second[cell->active_cell_index()] =
              cell_volume > 0 ? static_cast<float>(cell_ratio[c] / cell_volume) : 0.0f;
        }

    for (auto &per_zone : samples)
      for (auto &sample : per_zone)
        sample = reduce(sample, comm);
    return samples;
  }
} // namespace suturesim::tissue
