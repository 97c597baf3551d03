#include <suturesim/tissue/point_loads.h>

#include <deal.II/base/quadrature.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/petsc_vector.h>

#include <limits>
#include <sstream>
#include <stdexcept>

namespace suturesim::tissue
{
  using namespace dealii;

  EmbeddedPoints::EmbeddedPoints(const Mapping<3> &mapping, const FiniteElement<3> &fe,
                                 const DoFHandler<3> &dof_handler, MPI_Comm comm)
    : mapping(mapping)
    , fe(fe)
    , dof_handler(dof_handler)
    , comm(comm)
  {}

  void
  EmbeddedPoints::locate(const PointLoads &l)
  {
    loads = &l;
    by_cell.clear();
    const auto    &X    = l.points();
    const unsigned rank = Utilities::MPI::this_mpi_process(comm);
    where.assign(X.size(), {});
    mine.assign(X.size(), false);
    for (std::size_t k = 0; k < X.size(); ++k)
      {
        // A point of the boundary's triangles (the puncture's surface: two triangles per
        // quadrilateral face) lies off a warped face's bilinear surface, outside its cell
        // by up to a fraction of the warp: looked for again with a tolerance of 5 % of the
        // cell in unit coordinates, and its unit point then taken onto the cell.
        unsigned owner = numbers::invalid_unsigned_int;
        for (const double tolerance : {1e-10, 0.05})
          {
            try
              {
                auto found =
                  GridTools::find_active_cell_around_point(mapping, dof_handler, X[k], std::vector<bool>(), tolerance);
                if (found.first.state() == IteratorState::valid && found.first->is_locally_owned())
                  {
                    found.second = GeometryInfo<3>::project_to_unit_cell(found.second);
                    where[k]     = found;
                    owner        = rank;
                  }
              }
            catch (...)
              {
                // not in this rank's part of the mesh
              }
            if (Utilities::MPI::min(owner, comm) != numbers::invalid_unsigned_int)
              break;
          }
        const unsigned lowest = Utilities::MPI::min(owner, comm);
        if (lowest == numbers::invalid_unsigned_int)
          {
            std::ostringstream s;
            s << "embedded point (" << X[k] << ") m lies outside the mesh";
            throw std::invalid_argument(s.str());
          }
        mine[k] = lowest == rank;
        if (mine[k])
          by_cell[where[k].first->active_cell_index()].push_back({k, where[k].second});
      }
  }

  void
  EmbeddedPoints::add(const DoFHandler<3>::active_cell_iterator &cell, const dealii::Vector<double> &u_local,
                      dealii::Vector<double> &r, FullMatrix<double> *K) const
  {
    const auto found = by_cell.find(cell->active_cell_index());
    if (found == by_cell.end())
      return;
    const unsigned n = fe.n_dofs_per_cell();
    for (const auto &p : found->second)
      {
        FEValues<3> values(mapping, fe, Quadrature<3>(p.unit), update_values);
        values.reinit(cell);
        Point<3> x = loads->points()[p.k];
        for (unsigned i = 0; i < n; ++i)
          x[fe.system_to_component_index(i).first] += values.shape_value(i, 0) * u_local[i];
        Tensor<1, 3> f;
        Tensor<2, 3> df_dx;
        loads->force(p.k, x, f, df_dx);
        for (unsigned i = 0; i < n; ++i)
          {
            const unsigned ci = fe.system_to_component_index(i).first;
            const double   Ni = values.shape_value(i, 0);
            r[i] -= Ni * f[ci];
            if (K)
              for (unsigned j = 0; j < n; ++j)
                (*K)(i, j) -= Ni * df_dx[ci][fe.system_to_component_index(j).first] * values.shape_value(j, 0);
          }
      }
  }

  template <typename VectorType>
  Point<3>
  EmbeddedPoints::position(const std::size_t k, const VectorType &u) const
  {
    if (!mine[k])
      return Point<3>(std::numeric_limits<double>::quiet_NaN(), 0, 0);
    const auto &[cell, unit] = where[k];
    FEValues<3> values(mapping, fe, Quadrature<3>(unit), update_values);
    values.reinit(cell);
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    cell->get_dof_indices(dofs);
    Point<3> x = loads->points()[k];
    for (unsigned i = 0; i < dofs.size(); ++i)
      x[fe.system_to_component_index(i).first] += values.shape_value(i, 0) * u[dofs[i]];
    return x;
  }

  template <typename VectorType>
  void
  EmbeddedPoints::add_point_force(const std::size_t k, const Tensor<1, 3> &f, const AffineConstraints<double> &c,
                                  VectorType &rhs) const
  {
    if (!mine[k])
      return;
    const auto &[cell, unit] = where[k];
    FEValues<3> values(mapping, fe, Quadrature<3>(unit), update_values);
    values.reinit(cell);
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    cell->get_dof_indices(dofs);
    dealii::Vector<double> local(dofs.size());
    for (unsigned i = 0; i < dofs.size(); ++i)
      local[i] = values.shape_value(i, 0) * f[fe.system_to_component_index(i).first];
    c.distribute_local_to_global(local, dofs, rhs);
  }

  template Point<3>
  EmbeddedPoints::position(std::size_t, const PETScWrappers::MPI::Vector &) const;
  template void
  EmbeddedPoints::add_point_force(std::size_t, const Tensor<1, 3> &, const AffineConstraints<double> &,
                                  PETScWrappers::MPI::Vector &) const;
} // namespace suturesim::tissue
