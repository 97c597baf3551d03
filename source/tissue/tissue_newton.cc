/**
 * The Newton solve of one quasi-static load level of the tissue,
 * TissueModel::solve_static(), and its end test. Kept apart from tissue_model.cc, which
 * holds the degrees of freedom, the constraints and the assembly it calls.
 */
#include <suturesim/core/error.h>
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/fe/mapping_q1.h>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace suturesim::tissue
{
  using namespace dealii;

  double
  TissueModel::free_dot(const Vector &a, const Vector &b) const
  {
    double dirichlet_part = 0;
    for (const auto i : owned_dirichlet)
      dirichlet_part += a[i] * b[i];
    return (a * b) - Utilities::MPI::sum(dirichlet_part, comm);
  }

  double
  TissueModel::free_residual_norm() const
  {
    Vector r = system_rhs;
    for (const auto i : owned_dirichlet)
      r[i] = 0;
    r.compress(VectorOperation::insert);
    if (!pressure_unknowns)
      return r.l2_norm();
    // system_rhs = −(r_u + r_c) on the free DoFs
    Vector c = constraint_force;
    for (const auto i : owned_dirichlet)
      c[i] = 0;
    c.compress(VectorOperation::insert);
    const double c_norm = c.l2_norm();
    r += c;
    return std::hypot(r.l2_norm(), c_norm);
  }

  std::pair<double, types::global_dof_index>
  TissueModel::largest_free_residual() const
  {
    std::vector<types::global_dof_index> fixed = owned_dirichlet;
    std::sort(fixed.begin(), fixed.end());
    std::pair<double, types::global_dof_index> worst{0, 0};
    for (const auto i : locally_owned_dofs)
      if (const double r = system_rhs[i];
          std::abs(r) > std::abs(worst.first) && !std::binary_search(fixed.begin(), fixed.end(), i))
        worst = {r, i};
    return worst;
  }

  std::pair<Point<3>, unsigned>
  TissueModel::dof_location(const types::global_dof_index dof) const
  {
    const double                         nan = std::numeric_limits<double>::quiet_NaN();
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_indices(dofs);
          for (unsigned i = 0; i < dofs.size(); ++i)
            if (dofs[i] == dof)
              {
                const Point<3> X = MappingQ1<3>().transform_unit_to_real_cell(cell, fe.unit_support_point(i));
                return {X, fe.system_to_component_index(i).first};
              }
        }
    return {Point<3>(nan, nan, nan), 0};
  }

  bool
  TissueModel::boundary_reached(const double gap) const
  {
    return gap <= 1e-12 * std::max(solution.l2_norm(), 1e-3);
  }

  double
  TissueModel::mixed_residual() const
  {
    if (!pressure_unknowns)
      return 0;
    double worst = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          const auto  &m     = cell_mixed[cell->active_cell_index()];
          const double scale = material.bulk_modulus() * cell->measure();
          for (unsigned a = 0; a < m.dilatation_residual().size(); ++a)
            worst = std::max({worst, std::abs(m.dilatation_residual()[a]), std::abs(m.pressure_residual()[a]) / scale});
        }
    return Utilities::MPI::max(worst, comm);
  }

  bool
  TissueModel::newton_stop(const unsigned it, const double r_norm, const double r_ref, const double du_norm,
                           const double du_max, const double gap, const double force_floor,
                           NewtonReport &report) const
  {
    const NewtonParameters &np     = parameters.newton;
    const double            u_norm = solution.l2_norm();
    // An update at round-off level of the body's size ends the iteration too: the
    // residual of a very stiff (nearly incompressible) body cannot go below ε·κ·area,
    // which may exceed the absolute tolerance.
    const bool round_off = it > 0 && du_max <= 1e-13 * length_scale;
    report.iterations    = it;
    // The mixed fields' own residuals, dimensionless (a dilatation; a pressure over κ): 1e-6
    // is a stress error of κ·1e-6, far below what a step resolves, and stops the mixed
    // fields short of their solution only where the free DoFs cannot tell (the
    // all-Dirichlet block of tests/unit/tear_criterion_test.cc: 2.4e-2 there). The
    // increment tolerance (1e-9) cost the coarse stitch 16 % more iterations for a change
    // of 4e-7 in its closure tension (docs/tearing.md).
    constexpr double mixed_tolerance = 1e-6;
    if (boundary_reached(gap) && mixed_residual() <= mixed_tolerance &&
        (r_norm <= std::max(np.absolute_residual_tolerance, force_floor) || round_off ||
         (r_norm <= np.residual_tolerance * r_ref && du_norm <= np.increment_tolerance * std::max(u_norm, 1e-12))))
      {
        report.converged = true;
        return true;
      }
    if (!std::isfinite(r_norm) || r_norm > 1e10 * std::max(r_ref, 1e-300))
      {
        report.failure = "residual diverged (" + std::to_string(r_norm) + " N)";
        return true;
      }
    if (it == np.max_iterations)
      {
        std::ostringstream s;
        s << "no convergence in " << it << " iterations (residual " << std::scientific << std::setprecision(2)
          << r_norm << " N, relative " << r_norm / r_ref;
        if (const double mixed = mixed_residual(); mixed > mixed_tolerance)
          s << "; mixed fields' residual " << mixed;
        s << ")";
        report.failure = s.str();
        return true;
      }
    return false;
  }

  NewtonReport
  TissueModel::solve_static(const double t, const double force_floor)
  {
    const NewtonParameters &np = parameters.newton;
    NewtonReport            report;
    Vector                  update(locally_owned_dofs, comm), trial(locally_owned_dofs, comm);

    // the tangent without a coupled solve's condensed points (it may have left the
    // solver symmetric); spread points add theirs as a low-rank update
    solver->set_symmetric(!point_loads || embedded->symmetric(), "a point load's tangent");
    const std::vector<std::size_t> low_rank = point_loads ? embedded->low_rank_points() : std::vector<std::size_t>();
    const Eigen::MatrixXd          no_body  = Eigen::MatrixXd::Zero(3 * low_rank.size(), 3 * low_rank.size());
    solution_ghost = solution;
    double gap     = make_constraints(t, solution_ghost, constraints);
    Timer  clock;
    bool   ok = assemble(t, solution_ghost, true, constraints);
    report.assembly_seconds += clock.wall_time();
    if (!ok)
      {
        report.failure = "an element is inverted at the start of the step";
        return report;
      }
    double r_norm    = free_residual_norm();
    double r_ref     = r_norm;
    const bool line_search = np.line_search && !pressure_unknowns;
    double du_norm   = std::numeric_limits<double>::infinity();
    double du_max    = du_norm;
    report.residual_norms.push_back(r_norm);

    for (unsigned it = 0;; ++it)
      {
        if (newton_stop(it, r_norm, r_ref, du_norm, du_max, gap, force_floor, report))
          return report;
        const bool bc_moving = !boundary_reached(gap);
        clock.restart();
        {
          TimerOutput::Scope scope(timer, "linear solve");
          try
            {
              // The update need not be more accurate than the residual this step aims at.
              const double target =
                std::max({np.absolute_residual_tolerance, force_floor, np.residual_tolerance * r_ref});
              report.linear_iterations += low_rank_update(low_rank, no_body, 0.01 * target, update);
            }
          catch (const SolverError &e)
            {
              report.failure    = e.what();
              report.iterations = it;
              return report;
            }
        }
        report.solve_seconds += clock.wall_time();
        // The constrained entries of the update are the inhomogeneities g − u.
        constraints.distribute(update);
        du_norm = update.l2_norm();
        du_max  = update.linfty_norm();
        report.increment_norms.push_back(du_norm);
        begin_mixed_update(update);

        // Line search on the energy's directional derivative g(α) = R(u + αΔu)·Δu
        // (Crisfield 1991, §9.3; FEBio's line search): accept α when |g(α)| ≤ 0.9 |g(0)|,
        // else interpolate the zero of g linearly. Full steps whenever the boundary
        // values still move (the old residual says nothing about the new boundary
        // state); halve on an inverted element. Full steps, too, with the mixed fields
        // as Newton unknowns: the three-field system is a saddle point, g is then no
        // energy's derivative, and backtracking on it held the indentation block at 10–15
        // iterations per step where full steps take 4 (docs/accurate_tissue.md).
        const double g0    = -free_dot(system_rhs, update);
        double       alpha = 1.0;
        for (unsigned k = 0;; ++k)
          {
            trial = solution;
            trial.add(alpha, update);
            step_mixed(alpha);
            solution_ghost = trial;
            gap            = make_constraints(t, solution_ghost, constraints);
            clock.restart();
            ok = assemble(t, solution_ghost, true, constraints);
            report.assembly_seconds += clock.wall_time();
            if (ok)
              {
                const double g = -free_dot(system_rhs, update);
                const bool   slack_ok = std::abs(g) <= 0.9 * std::abs(g0) || g0 >= 0;
                if (slack_ok || !line_search || bc_moving || k >= np.max_backtracks)
                  {
                    r_norm = free_residual_norm();
                    break;
                  }
                // zero of the linear interpolant of g(α) through (0, g0) and (α, g)
                const double next = (g0 - g != 0) ? alpha * g0 / (g0 - g) : 0.5 * alpha;
                alpha             = std::clamp(next, 0.1 * alpha, 0.9 * alpha);
              }
            else
              {
                if (k >= np.max_backtracks)
                  {
                    report.failure    = "an element inverted in every backtracked update";
                    report.iterations = it + 1;
                    return report;
                  }
                alpha *= 0.5;
              }
            ++report.backtracks;
          }
        solution = trial;
        r_ref    = std::max(r_ref, r_norm);
        report.residual_norms.push_back(r_norm);
      }
  }
} // namespace suturesim::tissue
