#include <suturesim/core/error.h>
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/dofs/dof_tools.h>
#include <deal.II/fe/fe_q.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/grid/grid_tools.h>
#include <deal.II/lac/dynamic_sparsity_pattern.h>
#include <deal.II/lac/sparsity_tools.h>
#include <deal.II/numerics/data_out.h>
#include <deal.II/numerics/data_postprocessor.h>
#include <deal.II/numerics/vector_tools.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <iomanip>
#include <sstream>

namespace suturesim::tissue
{
  using namespace dealii;

  // --- parameters ---------------------------------------------------------------------

  void
  NewtonParameters::declare(ParameterHandler &prm)
  {
    const NewtonParameters d;
    prm.declare_entry("Max iterations",
                      std::to_string(d.max_iterations),
                      Patterns::Integer(1, 1000),
                      "Newton iterations per load step before the step is cut back. Unit: "
                      "1. Range: 1-1000.");
    prm.declare_entry("Residual tolerance",
                      Patterns::Tools::to_string(d.residual_tolerance),
                      Patterns::Double(0, 1),
                      "Convergence when the free-DoF residual norm falls below this "
                      "fraction of the largest residual of the step (and the increment "
                      "test holds). Unit: 1. Range: (0, 1).");
    prm.declare_entry("Absolute residual tolerance",
                      Patterns::Tools::to_string(d.absolute_residual_tolerance),
                      Patterns::Double(0),
                      "Convergence whenever the free-DoF residual norm is below this force. "
                      "Unit: N. Range: >= 0.");
    prm.declare_entry("Increment tolerance",
                      Patterns::Tools::to_string(d.increment_tolerance),
                      Patterns::Double(0, 1),
                      "Convergence needs |du| below this fraction of |u|. Unit: 1. Range: "
                      "(0, 1).");
    prm.declare_entry("Line search",
                      d.line_search ? "true" : "false",
                      Patterns::Bool(),
                      "Slack line search on the energy's directional derivative "
                      "R(u + a du).du: accept when it is at most 0.9 of its value at a = 0 "
                      "(Crisfield 1991, FEBio), else interpolate. Unit: none.");
    prm.declare_entry("Max backtracks",
                      std::to_string(d.max_backtracks),
                      Patterns::Integer(0, 30),
                      "Line-search reductions of a Newton update per iteration. Unit: 1. Range: 0-30.");
  }

  void
  NewtonParameters::parse(const ParameterHandler &prm, const ParameterScope &)
  {
    max_iterations              = prm.get_integer("Max iterations");
    residual_tolerance          = prm.get_double("Residual tolerance");
    absolute_residual_tolerance = prm.get_double("Absolute residual tolerance");
    increment_tolerance         = prm.get_double("Increment tolerance");
    line_search                 = prm.get_bool("Line search");
    max_backtracks              = prm.get_integer("Max backtracks");
  }

  namespace
  {
    const Patterns::Map probe_pattern(Patterns::Anything(),
                                      Patterns::List(Patterns::Double(), 3, 3, ","),
                                      0,
                                      Patterns::Map::max_int_value,
                                      ";",
                                      ":");
  }

  void
  TissueParameters::declare(ParameterHandler &prm)
  {
    prm.declare_entry("Element degree",
                      "2",
                      Patterns::Integer(1, 4),
                      "Polynomial degree of the Lagrange (Q_k) displacement element. Unit: "
                      "1. Range: 1-4.");
    prm.declare_entry("Formulation",
                      "mixed",
                      Patterns::Selection("mixed|displacement"),
                      "'mixed': three-field u-p-J (Simo-Taylor-Pister 1985, deal.II "
                      "step-44) with discontinuous pressure and dilatation condensed per "
                      "cell, free of volumetric locking up to nu = 0.4999; 'displacement': "
                      "plain Q_k, which locks for nearly incompressible tissue.");
    prm.declare_entry("Pressure degree",
                      "-1",
                      Patterns::Integer(-1, 1),
                      "Degree of the discontinuous pressure/dilatation of the mixed "
                      "formulation: 0 (mean dilatation), 1, or -1 for element degree - 1 "
                      "(Q2-P1, Q1-P0). Unit: 1. Range: -1-1.");
    prm.declare_entry("Probes",
                      "",
                      probe_pattern,
                      "Named points in the reference configuration whose displacement is "
                      "recorded, 'name: x, y, z; name: x, y, z'. Unit: m.");
    prm.declare_entry("Region moduli",
                      "",
                      Patterns::Map(Patterns::Anything(), Patterns::List(Patterns::Double(0), 2, 2, ","),
                                    0, Patterns::Map::max_int_value, ";", ":"),
                      "Layers of other tissue: 'name: mu, K; ...', the gmsh physical volume "
                      "'name' taking shear modulus mu and bulk modulus K in place of the "
                      "Material's (e.g. hypodermis under dermis, Tran et al. 2007: mu = "
                      "0.84e3, K = 36e3). Realtime path only for now. Unit: Pa. Range: "
                      "0 < mu < 1.5 K.");
    prm.enter_subsection("Newton");
    NewtonParameters::declare(prm);
    prm.leave_subsection();
    prm.enter_subsection("Linear solver");
    LinearSolver::Parameters::declare(prm);
    prm.leave_subsection();
  }

  void
  TissueParameters::parse(ParameterHandler &prm, const ParameterScope &scope)
  {
    degree      = prm.get_integer("Element degree");
    formulation = prm.get("Formulation");
    const int p = prm.get_integer("Pressure degree");
    pressure_degree = p < 0 ? std::min<unsigned>(degree - 1, 1) : static_cast<unsigned>(p);

    // The pattern has validated the text; split it here to keep the order of the file
    // (a std::map would sort the probes and merge duplicates silently).
    probes.clear();
    for (const auto &item : Utilities::split_string_list(prm.get("Probes"), ';'))
      {
        const auto colon = item.find(':');
        const std::string name = Utilities::trim(item.substr(0, colon));
        const auto x = Utilities::string_to_double(
          Utilities::split_string_list(item.substr(colon + 1), ','));
        for (const auto &[other, point] : probes)
          scope.require(other != name, "Probes", "probe '" + name + "' is named twice");
        probes.emplace_back(name, Point<3>(x[0], x[1], x[2]));
      }

    region_moduli.clear();
    for (const auto &[name, v] : get_named_values(prm, "Region moduli"))
      {
        scope.require(v[0] > 0 && v[1] > 0 && v[0] < 1.5 * v[1], "Region moduli",
                      "region '" + name + "': needs 0 < mu < 1.5 K (Poisson's ratio in (0, 0.5))");
        for (const auto &r : region_moduli)
          scope.require(r.name != name, "Region moduli", "region '" + name + "' is named twice");
        region_moduli.push_back({name, v[0], v[1]});
      }

    prm.enter_subsection("Newton");
    newton.parse(prm, scope.subsection("Newton"));
    prm.leave_subsection();
    prm.enter_subsection("Linear solver");
    linear.parse(prm, scope.subsection("Linear solver"));
    prm.leave_subsection();
  }

  // --- output fields ------------------------------------------------------------------

  namespace
  {
    /// Cauchy stress (tensor), von Mises stress, J, largest principal stretch and
    /// pressure at the output points, from the displacement gradient (and, for the mixed
    /// formulation, the cell's condensed pressure p̃).
    class StressPostprocessor : public DataPostprocessor<3>
    {
    public:
      StressPostprocessor(const Material                          &material,
                          const std::vector<PressureCoefficients> *pressure)
        : material(material)
        , pressure(pressure)
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
            double       p = 0;
            if (pressure != nullptr)
              {
                const auto  N = pressure_basis(in.evaluation_points[q], cell->center(),
                                              cell->diameter());
                const auto &c = (*pressure)[cell->active_cell_index()];
                for (unsigned a = 0; a < 4; ++a)
                  p += N[a] * c[a];
              }
            else if (J > 0)
              p = material.volumetric().pressure(J);
            const SymTensor2 sigma =
              J > 0 ? material.cauchy_stress(F, p) : SymTensor2();
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
      const std::vector<PressureCoefficients> *pressure;
    };
  } // namespace

  // --- model --------------------------------------------------------------------------

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
    cell_pressure.assign(tria.n_active_cells(), PressureCoefficients{});
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
    saved_cell_pressure = cell_pressure;

    make_constraints(0.0, solution_ghost, constraints);
    DynamicSparsityPattern dsp(locally_relevant_dofs);
    // Constrained rows keep their pattern (zeroed by the constraints) so that the mass
    // matrix of the dynamics shares it.
    DoFTools::make_sparsity_pattern(dof_handler, dsp, constraints, true);
    SparsityTools::distribute_sparsity_pattern(dsp, locally_owned_dofs, comm,
                                               locally_relevant_dofs);
    system_matrix.reinit(locally_owned_dofs, locally_owned_dofs, dsp, comm);

    owned_dirichlet.clear();
    for (const auto i : locally_owned_dofs)
      if (constraints.is_constrained(i))
        owned_dirichlet.push_back(i);

    // DoFs of each Dirichlet boundary with their component, for the reactions: the
    // DoFs that boundary constrains (first listed wins, as in make_constraints), only in
    // the constrained components, found on every non-artificial cell so that the sets
    // do not depend on the partition.
    reaction_dofs.assign(bc.dirichlet.size(), {});
    {
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

    if (parameters.linear.method != "direct")
      solver->set_near_null_space(rigid_body_modes());

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

  bool
  TissueModel::assemble(const double                     t,
                        const Vector                    &u_ghost,
                        const bool                       with_matrix,
                        const AffineConstraints<double> &c,
                        const Vector                    *velocity_ghost)
  {
    TimerOutput::Scope scope(timer, with_matrix ? "assemble K and R" : "assemble R");
    if (with_matrix)
      system_matrix = 0;
    system_rhs    = 0;
    full_residual = 0;

    const unsigned     n = fe.n_dofs_per_cell();
    FullMatrix<double> K(n, n);
    dealii::Vector<double> r(n), u_local(n), v_local(n), Kv(n);
    std::vector<types::global_dof_index> dofs(n);
    FEFaceValues<3> face_values(mapping, fe, face_quadrature,
                                update_values | update_JxW_values | update_quadrature_points);
    dealii::Vector<double> traction(3);
    const Function<3>     &traction_function = bc.traction(t); // set the time once
    const bool damping = velocity_ghost != nullptr && rayleigh_stiffness > 0;

    unsigned bad_cells = 0;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell->get_dof_values(u_ghost, u_local);
          const bool need_K = with_matrix || damping;
          if (!cell_assembler->assemble(cell, u_local, material, bc.gravity, r,
                                        need_K ? &K : nullptr,
                                        &cell_pressure[cell->active_cell_index()]))
            {
              ++bad_cells;
              continue;
            }
          if (damping)
            {
              cell->get_dof_values(*velocity_ghost, v_local);
              K.vmult(Kv, v_local);
              r.add(rayleigh_stiffness, Kv);
            }
          if (!bc.traction_boundaries.empty())
            for (const auto f : cell->face_indices())
              if (cell->face(f)->at_boundary() &&
                  bc.traction_boundaries.count(cell->face(f)->boundary_id()))
                {
                  face_values.reinit(cell, f);
                  for (unsigned q = 0; q < face_values.n_quadrature_points; ++q)
                    {
                      traction_function.vector_value(face_values.quadrature_point(q), traction);
                      for (unsigned i = 0; i < n; ++i)
                        {
                          const unsigned comp = fe.system_to_component_index(i).first;
                          r[i] -= face_values.shape_value(i, q) * traction[comp] *
                                  face_values.JxW(q);
                        }
                    }
                }
          if (point_loads != nullptr)
            embedded->add(cell, u_local, r, with_matrix ? &K : nullptr);
          cell->get_dof_indices(dofs);
          full_residual.add(dofs, r);
          r *= -1.0;
          if (with_matrix)
            c.distribute_local_to_global(K, r, dofs, system_matrix, system_rhs);
          else
            c.distribute_local_to_global(r, dofs, system_rhs);
        }
    if (with_matrix)
      system_matrix.compress(VectorOperation::add);
    system_rhs.compress(VectorOperation::add);
    full_residual.compress(VectorOperation::add);
    return Utilities::MPI::sum(bad_cells, comm) == 0;
  }

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
    return r.l2_norm();
  }

  bool
  TissueModel::boundary_reached(const double gap) const
  {
    return gap <= 1e-12 * std::max(solution.l2_norm(), 1e-3);
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
    if (boundary_reached(gap) &&
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
          << r_norm << " N, relative " << r_norm / r_ref << ")";
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
          update = 0;
          try
            {
              // The update need not be more accurate than the residual this step aims at.
              const double target =
                std::max({np.absolute_residual_tolerance, force_floor, np.residual_tolerance * r_ref});
              solver->solve(system_matrix, update, system_rhs, 0, 0.01 * target);
            }
          catch (const SolverError &e)
            {
              report.failure    = e.what();
              report.iterations = it;
              return report;
            }
          report.linear_iterations += solver->statistics().iterations;
        }
        report.solve_seconds += clock.wall_time();
        // The constrained entries of the update are the inhomogeneities g − u.
        constraints.distribute(update);
        du_norm = update.l2_norm();
        du_max  = update.linfty_norm();
        report.increment_norms.push_back(du_norm);

        // Line search on the energy's directional derivative g(α) = R(u + αΔu)·Δu
        // (Crisfield 1991, §9.3; FEBio's line search): accept α when |g(α)| ≤ 0.9 |g(0)|,
        // else interpolate the zero of g linearly. Full steps whenever the boundary
        // values still move (the old residual says nothing about the new boundary
        // state); halve on an inverted element.
        const double g0    = -free_dot(system_rhs, update);
        double       alpha = 1.0;
        for (unsigned k = 0;; ++k)
          {
            trial = solution;
            trial.add(alpha, update);
            solution_ghost = trial;
            gap            = make_constraints(t, solution_ghost, constraints);
            clock.restart();
            ok = assemble(t, solution_ghost, true, constraints);
            report.assembly_seconds += clock.wall_time();
            if (ok)
              {
                const double g = -free_dot(system_rhs, update);
                const bool   slack_ok = std::abs(g) <= 0.9 * std::abs(g0) || g0 >= 0;
                if (slack_ok || !np.line_search || bc_moving || k >= np.max_backtracks)
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

  void
  TissueModel::set_point_loads(const PointLoads *loads)
  {
    point_loads = loads;
    if (!loads)
      return;
    if (!embedded)
      embedded = std::make_unique<EmbeddedPoints>(mapping, fe, dof_handler, comm);
    embedded->locate(*loads);
  }

  Point<3>
  TissueModel::point_position(const std::size_t k) const
  {
    Vector ghost(locally_owned_dofs, locally_relevant_dofs, comm);
    ghost = solution;
    const Point<3> mine = embedded->position(k, ghost);
    // the owner's value; NaN elsewhere
    Point<3> x;
    const bool here = !std::isnan(mine[0]);
    for (unsigned d = 0; d < 3; ++d)
      x[d] = Utilities::MPI::sum(here ? mine[d] : 0.0, comm);
    return x;
  }

  void
  TissueModel::save_state()
  {
    saved_solution      = solution;
    saved_cell_pressure = cell_pressure;
  }

  void
  TissueModel::restore_state()
  {
    solution      = saved_solution;
    cell_pressure = saved_cell_pressure;
  }

  void
  TissueModel::set_displacement(const Vector &u)
  {
    solution = u;
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
        assemble(t, solution_ghost, false, none, &v_ghost); // includes a_K K_t v
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
    const StressPostprocessor stress(material,
                                     parameters.formulation == "mixed" ? &cell_pressure : nullptr);
    data_out.add_data_vector(ghost, stress);

    dealii::Vector<float> material_id(tria.n_active_cells()), rank(tria.n_active_cells());
    for (const auto &cell : tria.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          material_id[cell->active_cell_index()] = cell->material_id();
          rank[cell->active_cell_index()]        = cell->subdomain_id();
        }
    data_out.add_data_vector(material_id, "material_id", DataOut<3>::type_cell_data);
    data_out.add_data_vector(rank, "mpi_rank", DataOut<3>::type_cell_data);
    data_out.build_patches(mapping, parameters.degree);

    DataOutBase::VtkFlags flags(t, index);
    flags.compression_level = DataOutBase::VtkFlags::ZlibCompressionLevel::best_speed;
    data_out.set_flags(flags);
    std::ostringstream name;
    name << "tissue_" << std::setw(5) << std::setfill('0') << index << ".vtu";
    data_out.write_vtu_in_parallel((std::filesystem::path(directory) / name.str()).string(),
                                   comm);
    return name.str();
  }

  // --- dynamics -----------------------------------------------------------------------

  void
  TissueModel::set_rayleigh_damping(const double mass_coefficient,
                                    const double stiffness_coefficient)
  {
    rayleigh_mass      = mass_coefficient;
    rayleigh_stiffness = stiffness_coefficient;
    assemble_mass_matrix();
  }

  void
  TissueModel::assemble_mass_matrix()
  {
    TimerOutput::Scope scope(timer, "assemble M");
    DynamicSparsityPattern dsp(locally_relevant_dofs);
    DoFTools::make_sparsity_pattern(dof_handler, dsp);
    SparsityTools::distribute_sparsity_pattern(dsp, locally_owned_dofs, comm,
                                               locally_relevant_dofs);
    mass_matrix.reinit(locally_owned_dofs, locally_owned_dofs, dsp, comm);
    jacobian_full.reinit(locally_owned_dofs, locally_owned_dofs, dsp, comm);
    const unsigned     n = fe.n_dofs_per_cell();
    FullMatrix<double> M(n, n);
    std::vector<types::global_dof_index> dofs(n);
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        {
          cell_assembler->mass(cell, material.density(), M);
          cell->get_dof_indices(dofs);
          mass_matrix.add(dofs, M);
        }
    mass_matrix.compress(VectorOperation::add);
  }

  IndexSet
  TissueModel::dirichlet_dofs() const
  {
    IndexSet set(dof_handler.n_dofs());
    for (const auto i : owned_dirichlet)
      set.add_index(i);
    set.compress();
    return set;
  }

  bool
  TissueModel::dynamic_residual(const double  t,
                                const Vector &u,
                                const Vector &v,
                                const Vector &u_dot,
                                const Vector &v_dot,
                                Vector       &F_u,
                                Vector       &F_v)
  {
    solution_ghost = u;
    Vector v_ghost(locally_owned_dofs, locally_relevant_dofs, comm);
    v_ghost = v;
    AffineConstraints<double> none;
    none.close();
    if (!assemble(t, solution_ghost, false, none, &v_ghost))
      return false;

    // F_v = M v̇ + a_M M v + R (+ a_K K_t v inside R); F_u = u̇ − v.
    Vector tmp(locally_owned_dofs, comm);
    tmp = v_dot;
    tmp.add(rayleigh_mass, v);
    mass_matrix.vmult(F_v, tmp);
    F_v.add(1.0, full_residual);
    F_u = u_dot;
    F_u.add(-1.0, v);

    // Dirichlet rows are algebraic: u = g(t), v = ġ(t).
    std::vector<double> g, g_dot, g_ddot;
    boundary_values(t, g, g_dot, g_ddot);
    for (std::size_t k = 0; k < owned_dirichlet.size(); ++k)
      {
        const auto i = owned_dirichlet[k];
        F_u[i]       = u[i] - g[k];
        F_v[i]       = v[i] - g_dot[k];
      }
    F_u.compress(VectorOperation::insert);
    F_v.compress(VectorOperation::insert);
    return true;
  }

  void
  TissueModel::boundary_values(const double         t,
                               std::vector<double> &g,
                               std::vector<double> &g_dot,
                               std::vector<double> &g_ddot) const
  {
    // g(t) and its time derivatives (central differences of the prescribed functions)
    // at the locally owned Dirichlet DoFs, in the order of owned_dirichlet.
    const double h = 1e-4 * std::max(1e-3, std::abs(t)) + 1e-7;
    Vector       zero(locally_owned_dofs, locally_relevant_dofs, comm);
    std::array<AffineConstraints<double>, 3> c;
    make_constraints(t - h, zero, c[0]);
    make_constraints(t, zero, c[1]);
    make_constraints(t + h, zero, c[2]);
    g.resize(owned_dirichlet.size());
    g_dot.resize(owned_dirichlet.size());
    g_ddot.resize(owned_dirichlet.size());
    for (std::size_t k = 0; k < owned_dirichlet.size(); ++k)
      {
        const auto   i  = owned_dirichlet[k];
        const double gm = c[0].get_inhomogeneity(i), g0 = c[1].get_inhomogeneity(i),
                     gp = c[2].get_inhomogeneity(i);
        g[k]      = g0;
        g_dot[k]  = (gp - gm) / (2 * h);
        g_ddot[k] = (gp - 2 * g0 + gm) / (h * h);
      }
  }

  void
  TissueModel::initial_boundary_rates(Vector &u_dot, Vector &v_dot) const
  {
    std::vector<double> g, g_dot, g_ddot;
    boundary_values(0.0, g, g_dot, g_ddot);
    for (std::size_t k = 0; k < owned_dirichlet.size(); ++k)
      {
        u_dot[owned_dirichlet[k]] = g_dot[k];
        v_dot[owned_dirichlet[k]] = g_ddot[k];
      }
    u_dot.compress(VectorOperation::insert);
    v_dot.compress(VectorOperation::insert);
  }

  bool
  TissueModel::setup_dynamic_jacobian(const double t, const Vector &u, const double alpha)
  {
    solution_ghost = u;
    AffineConstraints<double> none;
    none.close();
    if (!assemble(t, solution_ghost, true, none))
      return false;
    // A = (1 + α a_K) K + (α² + α a_M) M, kept whole for the elimination of the Dirichlet
    // values in the solve, and with the Dirichlet rows and columns of the identity for
    // the factorisation (symmetric, so Cholesky applies).
    system_matrix *= (1.0 + alpha * rayleigh_stiffness);
    system_matrix.add(alpha * alpha + alpha * rayleigh_mass, mass_matrix);
    if (MatCopy(system_matrix.petsc_matrix(), jacobian_full.petsc_matrix(),
                DIFFERENT_NONZERO_PATTERN) != 0)
      throw SolverError("PETSc MatCopy failed");
    std::vector<PetscInt> rows(owned_dirichlet.begin(), owned_dirichlet.end());
    const PetscErrorCode  ierr = MatZeroRowsColumns(system_matrix.petsc_matrix(),
                                                   static_cast<PetscInt>(rows.size()),
                                                   rows.data(), 1.0, nullptr, nullptr);
    if (ierr != 0)
      throw SolverError("PETSc MatZeroRowsColumns failed");
    jacobian_alpha = alpha;
    return true;
  }

  void
  TissueModel::solve_dynamic_jacobian(const Vector &b_u,
                                      const Vector &b_v,
                                      Vector       &x_u,
                                      Vector       &x_v,
                                      const double  tolerance)
  {
    // Jacobian rows: free  α x_u − x_v = b_u,  K x_u + D x_v = b_v,  D = (α + a_M) M + a_K K;
    //                Dirichlet  x_u = b_u,  x_v = b_v.
    // With x_v = α x_u + w (w = −b_u on free, b_v − α b_u on Dirichlet DoFs) and
    // x_u = y + x_d (x_d = b_u on Dirichlet DoFs, 0 elsewhere), the free rows read
    //   A_ff y_f = b_v − D w − A x_d,   A = K + α D,
    // and D w = (α + a_M) M w + a_K K w with K = (A − α(α + a_M) M) / (1 + α a_K).
    const double alpha = jacobian_alpha;
    const double c_m   = alpha + rayleigh_mass;
    Vector       w(locally_owned_dofs, comm), x_d(locally_owned_dofs, comm);
    Vector       rhs(locally_owned_dofs, comm), Mw(locally_owned_dofs, comm),
      tmp(locally_owned_dofs, comm);
    w = b_u;
    w *= -1.0;
    for (const auto i : owned_dirichlet)
      {
        w[i]   = b_v[i] - alpha * b_u[i];
        x_d[i] = b_u[i];
      }
    w.compress(VectorOperation::insert);
    x_d.compress(VectorOperation::insert);

    mass_matrix.vmult(Mw, w);
    rhs = b_v;
    rhs.add(-c_m, Mw);
    if (rayleigh_stiffness > 0)
      {
        jacobian_full.vmult(tmp, w); // A w
        tmp.add(-alpha * c_m, Mw);   // (1 + α a_K) K w
        rhs.add(-rayleigh_stiffness / (1.0 + alpha * rayleigh_stiffness), tmp);
      }
    jacobian_full.vmult(tmp, x_d);
    rhs.add(-1.0, tmp);
    for (const auto i : owned_dirichlet)
      rhs[i] = 0;
    rhs.compress(VectorOperation::insert);

    x_u = 0;
    solver->solve(system_matrix, x_u, rhs, tolerance);
    x_u.add(1.0, x_d);
    x_v = x_u;
    x_v *= alpha;
    x_v.add(1.0, w);
  }
} // namespace suturesim::tissue
