/**
 * The tissue model's degrees of freedom, constraints and state. The assembly is in
 * tissue_assembly.cc, the Newton solve in tissue_newton.cc (and, with a condensed body, tissue_model_coupled.cc), the
 * output in tissue_output.cc, the dynamics in tissue_dynamics.cc, the parameters in
 * tissue_parameters.cc.
 */
#include <suturesim/core/error.h>
#include <suturesim/io/checkpoint.h>
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>

namespace suturesim::tissue
{
  using namespace dealii;

  TissueModel::TissueModel(MPI_Comm                                 comm,
                           const TissueParameters                  &parameters,
                           const Material                          &material,
                           const BoundaryConditions                &boundary_conditions,
                           parallel::distributed::Triangulation<3> &triangulation,
                           TimerOutput                             &timer)
    : comm(comm)
    , parameters(parameters)
    , material(material)
    , bc(boundary_conditions)
    , tria(triangulation)
    , timer(timer)
    , fe(FE_Q<3>(parameters.degree), 3)
    , dof_handler(triangulation)
    , quadrature(parameters.degree + 1)
    , face_quadrature(parameters.degree + 1)
  {}

  void
  TissueModel::setup()
  {
    TimerOutput::Scope scope(timer, "setup");
    // No renumbering: the three components of a support point stay consecutive, which
    // keeps the near-null-space of AMG simple and MUMPS does its own ordering.
    dof_handler.distribute_dofs(fe);
    locally_owned_dofs = dof_handler.locally_owned_dofs();
    DoFTools::extract_locally_relevant_dofs(dof_handler, locally_relevant_dofs);

    cell_assembler = std::make_unique<CellAssembler>(
      mapping, fe, quadrature, parameters.formulation == "mixed", parameters.pressure_degree);
    solver = std::make_unique<LinearSolver>(parameters.linear, comm);

    solution.reinit(locally_owned_dofs, comm);
    saved_solution.reinit(locally_owned_dofs, comm);
    system_rhs.reinit(locally_owned_dofs, comm);
    full_residual.reinit(locally_owned_dofs, comm);
    solution_ghost.reinit(locally_owned_dofs, locally_relevant_dofs, comm);
    constraint_force.reinit(locally_owned_dofs, comm);
    cell_mixed.assign(tria.n_active_cells(), MixedCell{});
    pressure_unknowns = parameters.formulation == "mixed" && parameters.mixed_update == "newton";
    {
      // Diagonal of the bounding box (GridTools::diameter is quadratic in the boundary
      // vertices and not implemented for refined distributed meshes).
      Point<3> lo, hi;
      for (unsigned d = 0; d < 3; ++d)
        lo[d] = std::numeric_limits<double>::max(), hi[d] = -lo[d];
      for (const auto &cell : tria.active_cell_iterators())
        if (cell->is_locally_owned())
          for (const auto v : cell->vertex_indices())
            for (unsigned d = 0; d < 3; ++d)
              {
                lo[d] = std::min(lo[d], cell->vertex(v)[d]);
                hi[d] = std::max(hi[d], cell->vertex(v)[d]);
              }
      double l2 = 0;
      for (unsigned d = 0; d < 3; ++d)
        {
          const double extent = Utilities::MPI::max(hi[d], comm) + Utilities::MPI::max(-lo[d], comm);
          l2 += extent * extent;
        }
      length_scale = std::sqrt(l2);
    }
    saved_cell_mixed = cell_mixed;
    if (parameters.phase_field.enabled)
      {
        damage = std::make_unique<tearing::DamageField<3>>(comm, tria, parameters.phase_field.toughness,
                                                           parameters.phase_field.length, parameters.degree + 1);
        if (const auto &box = parameters.phase_field.initial_crack; !box.empty())
          damage->crack([&box](const Point<3> &x) {
            constexpr double tolerance = 1e-9; // m: a node on the box's face is in it
            for (unsigned d = 0; d < 3; ++d)
              if (x[d] < box[0][d] - tolerance || x[d] > box[1][d] + tolerance)
                return false;
            return true;
          });
        update_degradation();
      }

    make_constraints(0.0, solution_ghost, constraints);
    make_system_matrix();

    owned_dirichlet.clear();
    for (const auto i : locally_owned_dofs)
      if (constraints.is_constrained(i))
        owned_dirichlet.push_back(i);

    find_reaction_dofs();

    if (parameters.linear.method != "direct")
      solver->set_near_null_space(rigid_body_modes());

    locate_probes();
  }

  void
  TissueModel::update_degradation()
  {
    const double k   = parameters.phase_field.residual_stiffness;
    cell_degradation = damage->cell_values(quadrature);
    for (auto &cell : cell_degradation)
      for (double &g : cell)
        g = tissue::degradation(g, k);
  }

  double
  TissueModel::advance_damage()
  {
    if (!damage)
      return 0;
    TimerOutput::Scope scope(timer, "phase field");
    Vector             ghost(locally_owned_dofs, locally_relevant_dofs, comm);
    ghost = solution;
    FEValues<3> values(mapping, fe, damage->quadrature(), update_gradients | update_quadrature_points);
    const FEValuesExtractors::Vector u(0);
    std::vector<Tensor<2, 3>>        grad_u(damage->quadrature().size());
    const bool                       mixed = parameters.formulation == "mixed";
    const double                     scale = 1 - parameters.phase_field.residual_stiffness;
    // ψ: the energy g degrades, Ψ_iso(C̄) and Ψ_vol(J̃) in expansion (volumetric_share())
    const double change = damage->solve([&](const tearing::DamageField<3>::Cell &cell, std::vector<double> &psi) {
      const DoFHandler<3>::active_cell_iterator here(&tria, cell->level(), cell->index(), &dof_handler);
      values.reinit(here);
      values[u].get_function_gradients(ghost, grad_u);
      for (unsigned q = 0; q < psi.size(); ++q)
        {
          const Tensor2 F       = unit_symmetric_tensor<3>() + grad_u[q];
          const double  J_tilde = mixed ? cell_mixed[here->active_cell_index()]
                                           .at(values.quadrature_point(q), here->center(), here->diameter())
                                           .second
                                       : determinant(F);
          psi[q] = material.isochoric_energy(symmetrize(transpose(F) * F));
          if (volumetric_degraded(J_tilde))
            psi[q] += material.volumetric().energy(J_tilde);
          psi[q] *= scale;
        }
    });
    update_degradation();
    return change;
  }

  std::string
  TissueModel::minimise_alternately(const std::function<std::string()> &equilibrium, std::vector<double> &changes)
  {
    changes.clear();
    if (!damage)
      return "";
    try
      {
        while (true)
          {
            const double change = advance_damage();
            changes.push_back(change);
            if (change == 0 && changes.size() == 1)
              return ""; // nothing moved: the equilibrium stands
            if (auto failure = equilibrium(); !failure.empty() || change <= parameters.phase_field.tolerance)
              return failure;
            if (changes.size() == parameters.phase_field.max_passes)
              return "the phase field's alternate minimisation did not settle in " + std::to_string(changes.size()) +
                     " damage solves (the last changed d by " + std::to_string(change) +
                     " > Tissue/Phase field/Tolerance)";
          }
      }
    catch (const SolverError &e)
      {
        return e.what();
      }
  }

  nlohmann::json
  TissueModel::damage_record(const std::vector<double> &changes) const
  {
    if (!damage)
      return nullptr;
    return {{"max", damage->range().second},
            {"growth", damage->growth()},
            {"passes", changes.size()},
            {"changes", changes},
            {"fracture_energy", damage->fracture_energy()}};
  }

  void
  TissueModel::make_system_matrix()
  {
    DynamicSparsityPattern dsp(locally_relevant_dofs);
    // Constrained rows keep their pattern (zeroed by the constraints) so that the mass
    // matrix of the dynamics shares it.
    DoFTools::make_sparsity_pattern(dof_handler, dsp, constraints, true);
    SparsityTools::distribute_sparsity_pattern(dsp, locally_owned_dofs, comm,
                                               locally_relevant_dofs);
    system_matrix.reinit(locally_owned_dofs, locally_owned_dofs, dsp, comm);
  }

  std::vector<TissueModel::Vector>
  TissueModel::rigid_body_modes() const
  {
    // Three translations and three infinitesimal rotations e_k × X.
    std::vector<Vector> modes(6);
    for (auto &m : modes)
      m.reinit(locally_owned_dofs, comm);
    const std::vector<Point<3>> support = fe.get_unit_support_points();
    FEValues<3> values(mapping, fe, Quadrature<3>(support), update_quadrature_points);
    std::vector<types::global_dof_index> dofs(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          values.reinit(cell);
          cell->get_dof_indices(dofs);
          for (unsigned i = 0; i < dofs.size(); ++i)
            if (locally_owned_dofs.is_element(dofs[i]))
              {
                const unsigned c = fe.system_to_component_index(i).first;
                const Point<3> &X = values.quadrature_point(i);
                modes[c][dofs[i]] = 1.0;
                // rotation about axis k: (e_k × X)_c
                const unsigned a = (c + 1) % 3, b = (c + 2) % 3;
                modes[3 + b][dofs[i]] = X[a];  // (e_b × X)_c = X_a for (a,b,c) cyclic
                modes[3 + a][dofs[i]] = -X[b];
              }
        }
    for (auto &m : modes)
      m.compress(VectorOperation::insert);
    return modes;
  }

  double
  TissueModel::make_constraints(const double             t,
                                const Vector            &u_ghost,
                                AffineConstraints<double> &c) const
  {
    c.clear();
    c.reinit(locally_relevant_dofs);
    // a locally refined mesh: the hanging nodes follow their coarse neighbours (before
    // the boundary values, which then skip a constrained node)
    DoFTools::make_hanging_node_constraints(dof_handler, c);
    double gap = 0;
    for (const auto &d : bc.dirichlet)
      {
        std::map<types::global_dof_index, double> values;
        const ComponentMask mask(std::vector<bool>(d.components.begin(), d.components.end()));
        if (d.prescribed)
          VectorTools::interpolate_boundary_values(mapping, dof_handler, d.id,
                                                   bc.displacement(t), values, mask);
        else
          VectorTools::interpolate_boundary_values(mapping, dof_handler, d.id,
                                                   Functions::ZeroFunction<3>(3), values,
                                                   mask);
        for (const auto &[dof, value] : values)
          if (!c.is_constrained(dof))
            {
              const double delta = value - u_ghost[dof];
              c.add_line(dof);
              c.set_inhomogeneity(dof, delta);
              if (locally_owned_dofs.is_element(dof))
                gap = std::max(gap, std::abs(delta));
            }
      }
    c.close();
    return Utilities::MPI::max(gap, comm);
  }

  void
  TissueModel::expect_symmetric_tangent(const bool symmetric, const std::string &why)
  {
    solver->set_symmetric(symmetric, why);
  }

  void
  TissueModel::set_point_loads(const PointLoads *loads)
  {
    point_loads = loads;
    if (!loads)
      {
        solver->set_symmetric(true);
        return;
      }
    if (!embedded)
      embedded = std::make_unique<EmbeddedPoints>(mapping, fe, dof_handler, comm);
    embedded->locate(*loads, constraints);
    solver->set_symmetric(embedded->symmetric(), "a point load's tangent");
    if (embedded->spread() && mass_matrix.m() > 0)
      throw InputError("a spread pierce load (Pierce points/Load radius > 0) with tissue dynamics: "
                       "the dynamics' solve does not add its low-rank tangent; use a quasi-static scene or radius 0");
  }

  Point<3>
  TissueModel::point_position(const std::size_t k) const
  {
    return embedded->positions(solution)[k];
  }

  void
  TissueModel::save_state()
  {
    saved_solution   = solution;
    saved_cell_mixed = cell_mixed;
    if (damage)
      damage->accept(); // the damage the step starts from: its lower bound
  }

  void
  TissueModel::restore_state()
  {
    solution   = saved_solution;
    cell_mixed = saved_cell_mixed;
    if (damage)
      {
        damage->restore();
        update_degradation();
      }
  }

  namespace
  {
    /// This process's cells as a checkpoint recognises them: their number and the sum
    /// of their centres (the same mesh, partition and order give the same bits).
    nlohmann::json
    cell_fingerprint(const DoFHandler<3> &dof_handler)
    {
      std::size_t cells = 0;
      Point<3>    sum;
      for (const auto &cell : dof_handler.active_cell_iterators())
        if (cell->is_locally_owned())
          {
            ++cells;
            sum += cell->center();
          }
      return {cells, sum[0], sum[1], sum[2]};
    }
  } // namespace

  nlohmann::json
  TissueModel::local_state() const
  {
    std::vector<double> u, mixed;
    for (const auto i : locally_owned_dofs)
      u.push_back(solution[i]);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto *field : {&cell_mixed[cell->active_cell_index()].p, &cell_mixed[cell->active_cell_index()].J})
          mixed.insert(mixed.end(), field->begin(), field->end());
    nlohmann::json state{{"dofs", n_dofs()},
                         {"cells", cell_fingerprint(dof_handler)},
                         {"u", io::pack_doubles(u)},
                         {"mixed", io::pack_doubles(mixed)}};
    if (damage)
      state["damage"] = io::pack_doubles(damage->owned_values());
    return state;
  }

  void
  TissueModel::restore_local_state(const nlohmann::json &state)
  {
    const std::vector<double> u = io::unpack_doubles(state.at("u")), mixed = io::unpack_doubles(state.at("mixed"));
    std::size_t               owned_cells = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      owned_cells += cell->is_locally_owned();
    // the same mesh and partition on every process, or none takes the state
    const bool fits = state.at("dofs").get<types::global_dof_index>() == n_dofs() &&
                      state.at("cells") == cell_fingerprint(dof_handler) &&
                      u.size() == locally_owned_dofs.n_elements() &&
                      mixed.size() == 2 * std::tuple_size_v<PressureCoefficients> * owned_cells;
    if (Utilities::MPI::min(int(fits), comm) == 0)
      throw InputError("--restart: the checkpoint's tissue mesh is not this one (" +
                       std::to_string(state.at("dofs").get<std::uint64_t>()) + " DoFs there, " +
                       std::to_string(n_dofs()) + " here, or other cells): was the mesh or its .geo changed?");
    // the phase field's damage, checked before anything is taken back: present as the scene
    // asks (the same on every process), and on this process's damage nodes
    const bool has_damage = state.contains("damage");
    if (has_damage != bool(damage))
      throw InputError(damage ? "--restart: the checkpoint has no damage (written without Tissue/Phase field), "
                                "this scene tears by the phase field"
                              : "--restart: the checkpoint carries a damage field (written with Tissue/Phase "
                                "field), this scene has none");
    const std::vector<double> d = damage ? io::unpack_doubles(state.at("damage")) : std::vector<double>();
    if (Utilities::MPI::min(int(!damage || d.size() == damage->dof_handler().locally_owned_dofs().n_elements()),
                            comm) == 0)
      throw InputError("--restart: the checkpoint's damage does not fit this mesh's damage nodes");
    std::size_t k = 0;
    for (const auto i : locally_owned_dofs)
      solution[i] = u[k++];
    solution.compress(VectorOperation::insert);
    solution_ghost = solution;
    k              = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (auto *field : {&cell_mixed[cell->active_cell_index()].p, &cell_mixed[cell->active_cell_index()].J})
          for (double &v : *field)
            v = mixed[k++];
    if (damage)
      {
        damage->restore_owned_values(d);
        update_degradation();
      }
  }

  void
  TissueModel::begin_mixed_update(const Vector &update)
  {
    if (!pressure_unknowns)
      return;
    Vector ghost(locally_owned_dofs, locally_relevant_dofs, comm);
    ghost = update;
    dealii::Vector<double> du(fe.n_dofs_per_cell());
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_values(ghost, du);
          cell_mixed[cell->active_cell_index()].begin_update(du);
        }
  }

  void
  TissueModel::step_mixed(const double alpha)
  {
    if (!pressure_unknowns)
      return;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        cell_mixed[cell->active_cell_index()].step(alpha);
  }

  void
  TissueModel::set_displacement(const Vector &u)
  {
    solution = u;
  }
} // namespace suturesim::tissue
