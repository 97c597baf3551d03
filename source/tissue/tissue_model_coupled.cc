/**
 * The tissue solved together with a body condensed onto its point loads
 * (tissue/condensed_body.h): TissueModel::solve_coupled(). Kept apart from
 * tissue_newton.cc, which holds the tissue's own solve.
 */
#include <suturesim/core/error.h>
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/base/mpi.h>

#include <Eigen/LU>

#include <algorithm>

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>

namespace suturesim::tissue
{
  using namespace dealii;

  std::vector<Point<3>>
  TissueModel::point_values(const Vector &v, const bool displacement) const
  {
    if (!point_loads)
      return {};
    std::vector<Point<3>> values = embedded->positions(v);
    if (!displacement)
      for (std::size_t k = 0; k < values.size(); ++k)
        values[k] -= Tensor<1, 3>(point_loads->points()[k]);
    return values;
  }

  namespace
  {
    /// EmbeddedPoints::set_condensed() for the coupled points while a coupled solve
    /// runs (every return path lets go); symmetric: whether the tangent then is.
    struct Condensing
    {
      EmbeddedPoints *points = nullptr;
      bool            symmetric = true;

      Condensing(const std::unique_ptr<EmbeddedPoints> &embedded, const PointLoads *loads,
                 const std::vector<std::size_t> &coupled)
      {
        if (!embedded || !loads)
          return;
        points = embedded.get();
        points->set_condensed(coupled);
        symmetric = points->symmetric();
      }
      ~Condensing()
      {
        if (points)
          points->set_condensed({});
      }
      Condensing(const Condensing &) = delete;
      Condensing &
      operator=(const Condensing &) = delete;
    };
  } // namespace

  unsigned
  TissueModel::low_rank_update(const std::vector<std::size_t> &all_points, const Eigen::MatrixXd &G,
                               const double tolerance, Vector &update)
  {
    // G with the parts of the points' own tangents that K leaves out, G_S; a point whose
    // rows and columns of G_S are zero (a wound-contact pair apart, a suture contact
    // point not touching) adds nothing to Nᵀ G_S N, and its columns would cost three
    // solves: only the others enter the update
    Eigen::MatrixXd G_all = G;
    for (std::size_t j = 0; j < all_points.size(); ++j)
      for (unsigned a = 0; a < 3; ++a)
        for (unsigned b = 0; b < 3; ++b)
          G_all(3 * j + a, 3 * j + b) -= embedded->low_rank_tangent(all_points[j])[a][b];
    std::vector<Eigen::Index> rows;
    std::vector<std::size_t>  points;
    for (std::size_t j = 0; j < all_points.size(); ++j)
      {
        const auto at = static_cast<Eigen::Index>(3 * j);
        if (G_all.middleRows(at, 3).isZero(0) && G_all.middleCols(at, 3).isZero(0))
          continue;
        points.push_back(all_points[j]);
        for (Eigen::Index d = 0; d < 3; ++d)
          rows.push_back(at + d);
      }
    const Eigen::MatrixXd G_S = G_all(rows, rows);

    // Nᵀ's columns U: unit forces at the points
    const std::size_t   m = points.size();
    std::vector<Vector> unit_forces(3 * m, Vector(locally_owned_dofs, comm));
    for (std::size_t j = 0; j < m; ++j)
      for (unsigned d = 0; d < 3; ++d)
        {
          Tensor<1, 3> unit;
          unit[d] = 1;
          embedded->add_point_force(points[j], unit, constraints, unit_forces[3 * j + d]);
          unit_forces[3 * j + d].compress(VectorOperation::add);
        }
    Vector g(locally_owned_dofs, comm), ghost(locally_owned_dofs, locally_relevant_dofs, comm);
    constraints.distribute(g);
    // N v: a distributed vector's values at the points
    const auto at_points = [&](const Vector &v) {
      ghost           = v;
      const auto at   = point_values(ghost, false);
      Eigen::VectorXd Nv(3 * m);
      for (std::size_t j = 0; j < m; ++j)
        for (unsigned d = 0; d < 3; ++d)
          Nv[3 * j + d] = at[points[j]][d];
      return Nv;
    };

    // With a kept factorisation: (K + U G Uᵀ) Δu = −R − U G N g by GMRES (the rows of a
    // solved Δu's constrained DoFs are overwritten by distribute(), so N Δu = Uᵀ Δu + N g)
    if (solver->can_reuse())
      {
        const Eigen::VectorXd c = G_S * at_points(g);
        Vector                b(system_rhs);
        for (std::size_t k = 0; k < 3 * m; ++k)
          b.add(-c[k], unit_forces[k]);
        if (solver->solve_reusing(system_matrix, unit_forces, G_S, b, update, tolerance))
          return solver->statistics().iterations;
      }

    // z0 = K⁻¹ (−R), then Z = K⁻¹ Nᵀ with the same factorisation
    update = 0;
    solver->solve(system_matrix, update, system_rhs, 0, tolerance);
    const unsigned iterations = solver->statistics().iterations;
    if (m == 0)
      {
        solver->keep_columns({}, {});
        return iterations;
      }
    // the points read the cells' DoFs, hanging ones among them on a locally refined mesh:
    // z0 takes its constrained values (the boundary's motion too), each column of Z the
    // homogeneous ones, P z (a solve leaves a constrained row at its right-hand side's
    // value, not at the interpolation of its parents); distribute(z) = P z + g
    constraints.distribute(update);
    const Eigen::VectorXd Nz0 = at_points(update);
    // U's columns solved in one call, kept as solved for a later solve_reusing()
    std::vector<Vector> Z(3 * m, Vector(locally_owned_dofs, comm));
    solver->solve_columns(system_matrix, Z, unit_forces, 1e-14);
    solver->keep_columns(unit_forces, Z);
    Eigen::MatrixXd NZ(3 * m, 3 * m);
    for (std::size_t k = 0; k < 3 * m; ++k)
      {
        constraints.distribute(Z[k]);
        Z[k].add(-1, g);
        ghost          = Z[k];
        const auto zat = point_values(ghost, false);
        for (std::size_t i = 0; i < m; ++i)
          for (unsigned e = 0; e < 3; ++e)
            NZ(3 * i + e, k) = zat[points[i]][e];
      }
    // Woodbury: (K + Nᵀ G N)⁻¹ b = z0 − Z (I + G N Z)⁻¹ G N z0
    const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(3 * m, 3 * m);
    const Eigen::VectorXd c = (I + G_S * NZ).partialPivLu().solve(G_S * Nz0);
    for (std::size_t k = 0; k < 3 * m; ++k)
      update.add(-c[k], Z[k]);
    return iterations;
  }

  NewtonReport
  TissueModel::solve_coupled(const double t, const double force_floor, CondensedBody &body)
  {
    const NewtonParameters &np = parameters.newton;
    NewtonReport            report;
    Vector                  update(locally_owned_dofs, comm), trial(locally_owned_dofs, comm);
    const std::vector<std::size_t> coupled = body.coupled_points();
    // The coupled points' ∂f/∂x enters K by its symmetric part and the Woodbury update
    // by its skew part S (low_rank_update()): the same system, and a symmetric K for
    // Cholesky (half LU's work) when no other point's tangent is non-symmetric.
    const Condensing condensing(embedded, point_loads, coupled);
    solver->set_symmetric(condensing.symmetric, "a point load's tangent");
    // the update's points: the coupled ones (their body's G first), then the other
    // points whose tangent K leaves out (spread ones), with no body
    std::vector<std::size_t> low_rank = coupled;
    if (point_loads)
      for (const std::size_t k : embedded->low_rank_points())
        if (std::find(coupled.begin(), coupled.end(), k) == coupled.end())
          low_rank.push_back(k);
    Eigen::MatrixXd G, G_all = Eigen::MatrixXd::Zero(3 * low_rank.size(), 3 * low_rank.size());
    double          r_ref = 0, du_norm = std::numeric_limits<double>::infinity(), du_max = du_norm;
    Timer           clock;

    // the state of an iterate: the body in equilibrium with the points where it puts
    // them (its response condensed onto them), then the tissue's residual, and its
    // tangent only while the boundary still moves (the iteration then goes on); false
    // (with report.failure) when the body's solve fails or an element inverts. Once the
    // boundary is reached, the tangent waits for the convergence test (tangent()): the
    // last iterate of every solve and every rejected trial need the residual alone, at
    // a sixth of the tangent's cost (docs/interrupted_stitch.md, "Scale").
    double     r_norm = 0, gap = 0;
    bool       has_tangent = false;
    const auto assemble_at = [&](const bool with_matrix) {
      clock.restart();
      const bool ok = assemble(t, solution_ghost, with_matrix, constraints);
      report.assembly_seconds += clock.wall_time();
      has_tangent = ok && with_matrix;
      if (!ok)
        report.failure = "an element is inverted";
      return ok;
    };
    const auto state = [&](const Vector &u) {
      solution_ghost = u;
      std::string failure;
      if (!body.equilibrate(point_values(solution_ghost, true), G, failure))
        {
          report.failure = failure;
          return false;
        }
      gap = make_constraints(t, solution_ghost, constraints);
      if (!assemble_at(!boundary_reached(gap)))
        return false;
      r_norm = free_residual_norm();
      return true;
    };
    constexpr double not_reached = std::numeric_limits<double>::quiet_NaN();
    const bool       started     = state(solution);
    body.observe({0, 0, 0, started ? r_norm : not_reached, started, 0});
    if (!started)
      return report;
    for (unsigned it = 0;; ++it)
      {
        r_ref = std::max(r_ref, r_norm);
        report.residual_norms.push_back(r_norm);
        if (newton_stop(it, r_norm, r_ref, du_norm, du_max, gap, force_floor, report))
          {
            if (!report.converged)
              report.failure = "coupled Newton: " + report.failure;
            return report;
          }
        // full steps while the boundary values still move: the old residual says
        // nothing about the new boundary state
        const bool bc_moving = !boundary_reached(gap);

        if (!has_tangent && !assemble_at(true))
          {
            report.iterations = it;
            return report;
          }
        clock.restart();
        {
          TimerOutput::Scope scope(timer, "linear solve");
          try
            {
              const double target =
                std::max({np.absolute_residual_tolerance, force_floor, np.residual_tolerance * r_ref});
              G_all.topLeftCorner(G.rows(), G.cols()) = G;
              report.linear_iterations += low_rank_update(low_rank, G_all, 0.01 * target, update);
            }
          catch (const SolverError &e)
            {
              report.failure    = e.what();
              report.iterations = it;
              return report;
            }
        }
        report.solve_seconds += clock.wall_time();
        constraints.distribute(update);
        du_norm = update.l2_norm();
        du_max  = update.linfty_norm();
        report.increment_norms.push_back(du_norm);
        begin_mixed_update(update);

        // Backtracking on the residual's norm: the tangent is exact where the friction
        // law is smooth, but a point at its stick–slip kink sends full steps round a
        // cycle of two (seen at the stitch's tightening: 0.182, 0.211, 0.182 N, ...).
        // Each trial brings the body to equilibrium again.
        const double r_start   = r_norm;
        double       alpha     = 1;
        for (unsigned k = 0;; ++k)
          {
            trial = solution;
            trial.add(alpha, update);
            step_mixed(alpha);
            const bool ok   = state(trial);
            const bool take = ok && (bc_moving || r_norm <= (1 - 1e-4 * alpha) * r_start || k >= np.max_backtracks);
            body.observe({it + 1, k, alpha, ok ? r_norm : not_reached, take, alpha * du_max});
            if (take)
              break;
            if (!ok && k >= np.max_backtracks)
              {
                report.iterations = it + 1;
                return report;
              }
            alpha *= 0.5;
            ++report.backtracks;
          }
        solution = trial;
      }
  }
} // namespace suturesim::tissue
