/**
 * Implicit dynamics by SUNDIALS IDA through deal.II's wrapper: y = [u; v],
 *   F_u = u̇ − v = 0,   F_v = M v̇ + (a_M M + a_K K_t(u)) v + R(u, t) = 0,
 * Dirichlet DoFs algebraic (u = g(t), v = ġ(t)). IDA chooses order (BDF 1–5) and step
 * from its local error estimate against the relative and absolute tolerances. Rayleigh
 * damping uses the current tangent stiffness K_t.
 */
#include <suturesim/core/error.h>
#include <suturesim/core/interruption.h>
#include <suturesim/tissue/time_integrator.h>

#include <deal.II/base/parameter_handler.h>
#include <deal.II/lac/petsc_block_vector.h>
#include <deal.II/sundials/ida.h>

#include <cmath>
#include <sstream>

namespace suturesim::tissue
{
  namespace
  {
    using BlockVector = dealii::PETScWrappers::MPI::BlockVector;

    struct IdaParameters
    {
      double   relative_tolerance = 1e-4;
      double   absolute_tolerance = 1e-8;
      double   minimum_step       = 1e-9;
      unsigned maximum_order      = 5;
      double   rayleigh_mass      = 0;
      double   rayleigh_stiffness = 0;
    };

    class Ida : public TimeIntegrator
    {
    public:
      explicit Ida(const IdaParameters &p)
        : p(p)
      {}

      void
      run(TissueModel &model, const TimeParameters &time, StateObserver &observer) override
      {
        MPI_Comm comm = MPI_COMM_WORLD;
        model.set_rayleigh_damping(p.rayleigh_mass, p.rayleigh_stiffness);
        const dealii::IndexSet &owned = model.locally_owned();
        const std::vector<dealii::IndexSet> blocks{owned, owned};
        const auto n = model.n_dofs();

        using IDA = dealii::SUNDIALS::IDA<BlockVector>;
        const double output_period =
          time.output_interval > 0 ? time.output_interval : time.step_size;
        IDA::AdditionalData data(0.0,
                                 time.end_time,
                                 time.step_size,
                                 output_period,
                                 p.minimum_step,
                                 p.maximum_order,
                                 10,
                                 0.0,
                                 p.absolute_tolerance,
                                 p.relative_tolerance,
                                 true,
                                 IDA::AdditionalData::use_y_diff,
                                 IDA::AdditionalData::use_y_diff,
                                 10);
        IDA ida(data, comm);

        unsigned residuals = 0, jacobians = 0, solves = 0, outputs = 0;
        ida.reinit_vector = [&](BlockVector &v) { v.reinit(blocks, comm); };
        ida.residual = [&](const double t, const BlockVector &y, const BlockVector &y_dot,
                           BlockVector &F) -> int {
          ++residuals;
          const bool ok = model.dynamic_residual(t, y.block(0), y.block(1), y_dot.block(0),
                                                 y_dot.block(1), F.block(0), F.block(1));
          return ok ? 0 : 1; // recoverable: IDA reduces the step
        };
        ida.setup_jacobian = [&](const double t, const BlockVector &y, const BlockVector &,
                                 const double alpha) -> int {
          ++jacobians;
          return model.setup_dynamic_jacobian(t, y.block(0), alpha) ? 0 : 1;
        };
        ida.solve_with_jacobian = [&](const BlockVector &b, BlockVector &x,
                                      const double tolerance) -> int {
          ++solves;
          try
            {
              model.solve_dynamic_jacobian(b.block(0), b.block(1), x.block(0), x.block(1),
                                           tolerance > 0 ? std::min(tolerance, 1e-2) : 0);
            }
          catch (const SolverError &)
            {
              return 1;
            }
          return 0;
        };
        ida.differential_components = [&]() {
          dealii::IndexSet differential(2 * n);
          differential.add_range(owned.nth_index_in_set(0),
                                 owned.nth_index_in_set(0) + owned.n_elements());
          differential.add_range(n + owned.nth_index_in_set(0),
                                 n + owned.nth_index_in_set(0) + owned.n_elements());
          const dealii::IndexSet dirichlet = model.dirichlet_dofs();
          dealii::IndexSet       algebraic(2 * n);
          for (const auto i : dirichlet)
            {
              algebraic.add_index(i);
              algebraic.add_index(n + i);
            }
          differential.subtract_set(algebraic);
          return differential;
        };
        const unsigned expected =
          static_cast<unsigned>(std::ceil(time.end_time / output_period - 1e-9));
        double next_output = 0;
        ida.output_step = [&](const double t, const BlockVector &y, const BlockVector &y_dot,
                              const unsigned) {
          // deal.II 9.4 checks IDASolve's status only in debug builds: an IDA failure
          // shows up here as an output before the requested time.
          if (t < next_output - 1e-9 * time.end_time)
            throw SolverError("IDA could not advance past t = " + std::to_string(t) +
                              " s (error test or nonlinear solver failures at the minimum "
                              "step); last output t = " +
                              std::to_string(observer.last_accepted_time()) + " s in " +
                              observer.keep_last_accepted());
          next_output = std::min(t + output_period, time.end_time);
          model.set_displacement(y.block(0));
          observer.accepted(t,
                            {{"residual_evaluations", residuals},
                             {"jacobian_setups", jacobians},
                             {"linear_solves", solves}},
                            &y.block(1), &y_dot.block(1));
          if (t > 0)
            progress(++outputs, expected, t, time.end_time,
                     "IDA " + std::to_string(residuals) + " residuals");
          // IDA stops only at an output: there the run can stop on a signal
          if (const int signal = t < time.end_time * (1 - 1e-12) ? stop_requested() : 0)
            throw Interrupted(signal, t, observer.keep_last_accepted());
        };

        BlockVector y(blocks, comm), y_dot(blocks, comm);
        y.block(0) = model.displacement();
        model.initial_boundary_rates(y_dot.block(0), y_dot.block(1));
        try
          {
            ida.solve_dae(y, y_dot);
          }
        catch (const SolverError &)
          {
            throw;
          }
        catch (const dealii::ExceptionBase &e)
          {
            std::ostringstream info;
            e.print_info(info);
            throw SolverError("IDA failed after t = " + std::to_string(observer.last_accepted_time()) +
                              " s: " + one_line(info.str()) + "; last output " + observer.keep_last_accepted());
          }
        observer.totals({{"integrator", "ida"},
                         {"residual_evaluations", residuals},
                         {"jacobian_setups", jacobians},
                         {"linear_solves", solves}});
      }

    private:
      IdaParameters p;
    };

    const bool registered = TimeIntegrator::Registry::instance().add(
      {"ida",
       "Implicit dynamics M dv/dt + (a_M M + a_K K_t) v + R(u) = 0 by SUNDIALS IDA "
       "(variable-order BDF with adaptive error-controlled steps).",
       [](dealii::ParameterHandler &prm) {
         const IdaParameters d;
         prm.enter_subsection("ida");
         prm.declare_entry("Relative tolerance",
                           dealii::Patterns::Tools::to_string(d.relative_tolerance),
                           dealii::Patterns::Double(0, 1),
                           "IDA local error tolerance, relative. Unit: 1. Range: (0, 1).");
         prm.declare_entry("Absolute tolerance",
                           dealii::Patterns::Tools::to_string(d.absolute_tolerance),
                           dealii::Patterns::Double(0),
                           "IDA local error tolerance, absolute (on u in m and v in m/s). "
                           "Unit: m. Range: > 0.");
         prm.declare_entry("Maximum order",
                           std::to_string(d.maximum_order),
                           dealii::Patterns::Integer(1, 5),
                           "Highest BDF order. Unit: 1. Range: 1-5.");
         prm.declare_entry("Rayleigh mass coefficient",
                           "0",
                           dealii::Patterns::Double(0),
                           "a_M of the damping C = a_M M + a_K K_t. Unit: 1/s. Range: >= 0.");
         prm.declare_entry("Rayleigh stiffness coefficient",
                           "0",
                           dealii::Patterns::Double(0),
                           "a_K of the damping C = a_M M + a_K K_t. Unit: s. Range: >= 0.");
         prm.leave_subsection();
       },
       [](const dealii::ParameterHandler &prm, const ParameterScope &scope) {
         auto &prm_mut = const_cast<dealii::ParameterHandler &>(prm);
         prm_mut.enter_subsection("ida");
         IdaParameters p;
         p.relative_tolerance = prm.get_double("Relative tolerance");
         p.absolute_tolerance = prm.get_double("Absolute tolerance");
         p.maximum_order      = prm.get_integer("Maximum order");
         p.rayleigh_mass      = prm.get_double("Rayleigh mass coefficient");
         p.rayleigh_stiffness = prm.get_double("Rayleigh stiffness coefficient");
         prm_mut.leave_subsection();
         scope.subsection("ida").require(p.absolute_tolerance > 0, "Absolute tolerance",
                                         "must be > 0");
         return std::unique_ptr<TimeIntegrator>(new Ida(p));
       }});
  } // namespace
} // namespace suturesim::tissue
