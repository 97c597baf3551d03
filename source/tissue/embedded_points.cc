#include <suturesim/mesh/spread_kernel.h>
#include <suturesim/tissue/point_loads.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>

#include <algorithm>
#include <array>
#include <cmath>
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

  namespace
  {
    /// Adds @p w at DoF @p dof (component @p component) to @p into, through the
    /// hanging-node line of @p c if @p dof has one.
    void
    add_weight(std::map<types::global_dof_index, EmbeddedPoints::Weight> &into, const types::global_dof_index dof,
               const unsigned component, const double w, const AffineConstraints<double> &c)
    {
      const auto *entries = c.is_constrained(dof) ? c.get_constraint_entries(dof) : nullptr;
      if (entries != nullptr && !entries->empty())
        {
          // a hanging node couples a component to the same component of its parents
          for (const auto &[parent, alpha] : *entries)
            add_weight(into, parent, component, alpha * w, c);
          return;
        }
      auto &entry = into.try_emplace(dof, EmbeddedPoints::Weight{dof, component, 0.0}).first->second;
      entry.value += w;
    }
  } // namespace

  std::map<types::global_dof_index, EmbeddedPoints::Weight>
  EmbeddedPoints::local_weights(const std::size_t k, const Point<3> &X, const double rho) const
  {
    std::map<types::global_dof_index, Weight> w;
    const unsigned                             n = fe.n_dofs_per_cell();
    std::vector<types::global_dof_index>       dofs(n);
    for (const auto &cell : dof_handler.active_cell_iterators())
      {
        if (!cell->is_locally_owned())
          continue;
        const BoundingBox<3> box = cell->bounding_box();
        Point<3>             nearest;
        for (unsigned d = 0; d < 3; ++d)
          nearest[d] = std::clamp(X[d], box.get_boundary_points().first[d], box.get_boundary_points().second[d]);
        if (nearest.distance(X) >= rho)
          continue;
        // two Gauss points per subinterval, subintervals no longer than ρ/2: points no
        // further than about ρ/4 apart whatever the cell's size
        const unsigned  m = std::clamp(static_cast<unsigned>(std::ceil(2 * cell->diameter() / rho)), 1U, 16U);
        const QIterated<3> quadrature(QGauss<1>(2), m);
        FEValues<3> values(mapping, fe, quadrature, update_values | update_quadrature_points | update_JxW_values);
        values.reinit(cell);
        cell->get_dof_indices(dofs);
        std::vector<double> a(n, 0.0);
        bool                inside = false;
        for (unsigned q = 0; q < quadrature.size(); ++q)
          {
            const double s = values.quadrature_point(q).distance(X) / rho;
            if (s >= 1 || loads->cut_off(k, values.quadrature_point(q)))
              continue;
            const double phi = mesh::spread_kernel(s) * values.JxW(q);
            for (unsigned i = 0; i < n; ++i)
              a[i] += phi * values.shape_value(i, q);
            inside = true;
          }
        if (inside)
          for (unsigned i = 0; i < n; ++i)
            {
              auto &entry = w.try_emplace(dofs[i], Weight{dofs[i], fe.system_to_component_index(i).first, 0.0})
                              .first->second;
              entry.value += a[i];
            }
      }
    return w;
  }

  std::pair<DoFHandler<3>::active_cell_iterator, Point<3>>
  EmbeddedPoints::find(const Point<3> &X, bool &here) const
  {
    // A point of the boundary's triangles (the puncture's surface: two triangles per
    // quadrilateral face) lies off a warped face's bilinear surface, outside its cell by
    // up to a fraction of the warp: looked for again with a tolerance of 5 % of the cell
    // in unit coordinates, and its unit point then taken onto the cell.
    const unsigned                                           rank  = Utilities::MPI::this_mpi_process(comm);
    unsigned                                                 owner = numbers::invalid_unsigned_int;
    std::pair<DoFHandler<3>::active_cell_iterator, Point<3>> found;
    for (const double tolerance : {1e-10, 0.05})
      {
        try
          {
            found = GridTools::find_active_cell_around_point(mapping, dof_handler, X, std::vector<bool>(), tolerance);
            if (found.first.state() == IteratorState::valid && found.first->is_locally_owned())
              owner = rank;
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
        s << "embedded point (" << X << ") m lies outside the mesh";
        throw std::invalid_argument(s.str());
      }
    here         = lowest == rank;
    found.second = GeometryInfo<3>::project_to_unit_cell(found.second);
    return found;
  }

  std::vector<EmbeddedPoints::Weight>
  EmbeddedPoints::gather(const std::map<types::global_dof_index, Weight> &raw,
                         const AffineConstraints<double>                 &constraints) const
  {
    // normalised (the kernel's integral; 1 for the shape functions), folded through the
    // hanging nodes by the rank whose cells hold them, then summed over the ranks
    double total = 0;
    for (const auto &[dof, w] : raw)
      if (w.component == 0)
        total += w.value;
    total = Utilities::MPI::sum(total, comm);
    if (!(total > 0))
      return {};
    std::map<types::global_dof_index, Weight> folded;
    for (const auto &[dof, w] : raw)
      add_weight(folded, dof, w.component, w.value / total, constraints);
    std::vector<Weight> part;
    for (const auto &[dof, w] : folded)
      part.push_back(w);
    std::map<types::global_dof_index, Weight> merged;
    for (const auto &from : Utilities::MPI::all_gather(comm, part))
      for (const Weight &w : from)
        merged.try_emplace(w.dof, Weight{w.dof, w.component, 0.0}).first->second.value += w.value;
    std::vector<Weight> all;
    for (const auto &[dof, w] : merged)
      all.push_back(w);
    return all;
  }

  void
  EmbeddedPoints::locate(const PointLoads &l, const AffineConstraints<double> &constraints)
  {
    loads       = &l;
    const auto &X = l.points();
    weight.assign(X.size(), {});
    mine.assign(X.size(), false);
    spread_point.assign(X.size(), false);
    any_spread = false;
    for (std::size_t k = 0; k < X.size(); ++k)
      {
        bool         here  = false;
        const auto   found = find(X[k], here);
        const double rho   = l.spread_radius(k);
        mine[k]            = here;
        std::map<types::global_dof_index, Weight> raw;
        if (rho > 0)
          raw = local_weights(k, X[k], rho);
        else if (here)
          {
            FEValues<3> values(mapping, fe, Quadrature<3>(found.second), update_values);
            values.reinit(found.first);
            std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
            found.first->get_dof_indices(dofs);
            for (unsigned i = 0; i < dofs.size(); ++i)
              raw[dofs[i]] = Weight{dofs[i], fe.system_to_component_index(i).first, values.shape_value(i, 0)};
          }
        weight[k] = gather(raw, constraints);
        if (weight[k].empty())
          {
            std::ostringstream s;
            s << "embedded point (" << X[k] << ") m: no tissue within its spread radius " << rho << " m";
            throw std::invalid_argument(s.str());
          }
        spread_point[k] = rho > 0;
        any_spread      = any_spread || rho > 0;
      }
  }

  std::vector<Point<3>>
  EmbeddedPoints::positions(const Vector &u) const
  {
    const auto           &X = loads->points();
    const IndexSet        owned = u.locally_owned_elements();
    std::vector<double> sum(3 * X.size(), 0.0);
    for (std::size_t k = 0; k < X.size(); ++k)
      for (const Weight &e : weight[k])
        if (owned.is_element(e.dof))
          sum[3 * k + e.component] += e.value * u(e.dof);
    Utilities::MPI::sum(sum, comm, sum);
    std::vector<Point<3>> x(X);
    for (std::size_t k = 0; k < X.size(); ++k)
      for (unsigned d = 0; d < 3; ++d)
        x[k][d] += sum[3 * k + d];
    return x;
  }

  void
  EmbeddedPoints::add_point_force(const std::size_t k, const Tensor<1, 3> &f, const AffineConstraints<double> &c,
                                  Vector &rhs) const
  {
    const IndexSet owned = rhs.locally_owned_elements();
    for (const Weight &e : weight[k])
      if (owned.is_element(e.dof) && !c.is_constrained(e.dof))
        rhs(e.dof) += e.value * f[e.component];
  }

  std::vector<std::size_t>
  EmbeddedPoints::low_rank_points() const
  {
    std::vector<std::size_t> points;
    for (std::size_t k = 0; k < weight.size(); ++k)
      if (low_rank(k))
        points.push_back(k);
    return points;
  }

  bool
  EmbeddedPoints::symmetric() const
  {
    for (std::size_t k = 0; k < weight.size(); ++k)
      if (!low_rank(k) && !loads->symmetric_at(k))
        return false;
    return true;
  }

  void
  EmbeddedPoints::set_condensed(const std::vector<std::size_t> &points)
  {
    condensed.assign(weight.size(), false);
    for (const std::size_t k : points)
      condensed.at(k) = true;
  }

  void
  EmbeddedPoints::assemble(const Vector &u, const AffineConstraints<double> &c, Matrix *K, Vector &rhs,
                           Vector &full)
  {
    const std::size_t           n     = weight.size();
    const std::vector<Point<3>> x     = positions(u);
    const IndexSet              owned = rhs.locally_owned_elements();
    // Shared by a sum over the ranks, per point: f (3) and ∂f/∂x (9) from the rank that
    // evaluates the force law; Σ W_J g_J over the DoFs J fixed by c (3: AffineConstraints
    // moves K_IJ g_J to the right-hand side of the free rows); then per weight whether c
    // fixes its DoF (its owner knows).
    // the per-point block of the shared array: f at 0, ∂f/∂x (row-major) at 3, Σ W g at 12
    constexpr std::size_t block = 15, at_f = 0, at_A = 3, at_Wg = 12;
    std::vector<std::size_t> first(n + 1, block * n);
    for (std::size_t k = 0; k < n; ++k)
      first[k + 1] = first[k] + weight[k].size();
    std::vector<double> shared(first[n], 0.0);
    for (std::size_t k = 0; k < n; ++k)
      {
        if (mine[k])
          {
            Tensor<1, 3> f;
            Tensor<2, 3> A;
            loads->force(k, x[k], f, A);
            for (unsigned a = 0; a < 3; ++a)
              {
                shared[block * k + at_f + a] = f[a];
                for (unsigned b = 0; b < 3; ++b)
                  shared[block * k + at_A + 3 * a + b] = A[a][b];
              }
          }
        for (std::size_t j = 0; j < weight[k].size(); ++j)
          {
            const Weight &e = weight[k][j];
            if (!owned.is_element(e.dof) || !c.is_constrained(e.dof))
              continue;
            shared[first[k] + j] = 1;
            shared[block * k + at_Wg + e.component] += e.value * c.get_inhomogeneity(e.dof);
          }
      }
    Utilities::MPI::sum(shared, comm, shared);
    low.assign(n, Tensor<2, 3>());
    for (std::size_t k = 0; k < n; ++k)
      if (spread_point[k])
        for (unsigned a = 0; a < 3; ++a)
          for (unsigned b = 0; b < 3; ++b)
            {
              low[k][a][b] = shared[block * k + at_A + 3 * a + b];
              shared[block * k + at_A + 3 * a + b] = 0; // nothing of it in K nor its fixed columns
            }
      else if (k < condensed.size() && condensed[k])
        for (unsigned a = 0; a < 3; ++a)
          for (unsigned b = 0; b < a; ++b)
            {
              double &A_ab = shared[block * k + at_A + 3 * a + b], &A_ba = shared[block * k + at_A + 3 * b + a];
              const double s = 0.5 * (A_ab - A_ba), mean = 0.5 * (A_ab + A_ba);
              low[k][a][b]   = s;
              low[k][b][a]   = -s;
              A_ab = A_ba = mean; // the same bits in both triangles
            }

    std::vector<types::global_dof_index> rows, full_rows, columns;
    std::vector<double>                  r_rows, r_full, k_row, WJ;
    std::array<std::vector<double>, 3>   AJ; ///< per row component a: A_a,c(J) over the free J
    for (std::size_t k = 0; k < n; ++k)
      {
        const double *f = &shared[block * k + at_f], *A = &shared[block * k + at_A], *Wg = &shared[block * k + at_Wg];
        const double *fixed = &shared[first[k]];
        // the tangent's rows of this point differ only by their factor W_I and its
        // component: the free columns, their W_J and A's entries once per point; none
        // for a spread point, whose couplings K's pattern does not hold
        const bool with_K = K != nullptr && !spread_point[k];
        if (with_K)
          {
            columns.clear();
            WJ.clear();
            for (auto &a : AJ)
              a.clear();
            for (std::size_t j = 0; j < weight[k].size(); ++j)
              if (fixed[j] == 0)
                {
                  const Weight &J = weight[k][j];
                  columns.push_back(J.dof);
                  WJ.push_back(J.value);
                  for (unsigned a = 0; a < 3; ++a)
                    AJ[a].push_back(A[3 * a + J.component]);
                }
          }
        for (std::size_t i = 0; i < weight[k].size(); ++i)
          {
            const Weight &I = weight[k][i];
            if (!owned.is_element(I.dof))
              continue;
            // R_I = −W_I f in every owned row; −R in the free ones, with −K_IJ g_J =
            // W_I (A Σ W_J g_J) for the fixed columns when the tangent is assembled
            full_rows.push_back(I.dof);
            r_full.push_back(-I.value * f[I.component]);
            if (fixed[i] > 0)
              continue;
            double b = I.value * f[I.component];
            if (with_K)
              {
                for (unsigned d = 0; d < 3; ++d)
                  b += I.value * A[3 * I.component + d] * Wg[d];
                const std::vector<double> &a = AJ[I.component];
                k_row.resize(a.size());
                for (std::size_t j = 0; j < a.size(); ++j)
                  k_row[j] = -I.value * a[j] * WJ[j];
                K->add(I.dof, columns, k_row, false);
              }
            rows.push_back(I.dof);
            r_rows.push_back(b);
          }
      }
    full.add(full_rows, r_full);
    rhs.add(rows, r_rows);
  }
} // namespace suturesim::tissue
