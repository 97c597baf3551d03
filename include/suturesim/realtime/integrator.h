#pragma once
/**
 * @file
 * Time integrators of the realtime path, registered by name (Realtime/Integrator):
 *  - "quasi-static": V = F/B, P ← P + dt F/B (seed 001 §2.2, eq. 1–2 without inertia;
 *    seed 002 §4.B): no velocity carried between steps, B the damping per node;
 *  - "symplectic-euler": V ← V + dt (F/M − c V), P ← P + dt V (seed 001 eqs. 1–2, seed
 *    003's explicit Euler) with mass-proportional damping rate c;
 *  - "xpbd": extended position-based dynamics (Macklin, Müller & Chentanez 2016, Alg. 1)
 *    with every interaction a compliant constraint (seed 004).
 * The force-based two compute their stability limit from the network (stability.h),
 * report it, warn or refuse when dt exceeds it, and can limit strain after each step
 * (seed 003; SpringSet::limit_strain).
 */

#include <suturesim/core/registry.h>
#include <suturesim/core/model_parameters.h>
#include <suturesim/realtime/system.h>

#include <limits>
#include <string>

namespace suturesim::realtime
{
  class Integrator
  {
  public:
    using Registry = BasicRegistry<Integrator, ParameterDeclarations, const ParameterValues &>;
    virtual ~Integrator() = default;

    /// Sets what the integrator needs per node (damping of quasi-static integration);
    /// call once after the system is built.
    virtual void
    setup(System &)
    {}

    /// Advances the system by @p dt. Held nodes end at nodes.target.
    virtual void
    step(System &system, double dt) = 0;

    /// The largest stable dt at the current state (∞ when unconditionally stable).
    virtual double
    stability_limit(const System &) const
    {
      return std::numeric_limits<double>::infinity();
    }

    /// One line on how the limit was obtained, for messages.
    virtual std::string
    limit_description() const
    {
      return "";
    }

    /// True for the quasi-static law V = F/B (no inertia), which a released needle
    /// follows too (free_needle.h).
    virtual bool
    quasi_static() const
    {
      return false;
    }

    /// True for XPBD: interactions are constraints, contacts are projected.
    virtual bool
    position_based() const
    {
      return false;
    }

    /// True when the tissue's families are swept as constraints (XPBD); false where it
    /// moves by forces or vertex blocks ("vbd").
    virtual bool
    projects_tissue() const
    {
      return position_based();
    }

    /// For position-based integrators: the first interaction solved as a constraint,
    /// whose forces are its multipliers' (Interaction::add_constraint_forces); those
    /// before it (a primal tissue solve: "vbd") exert their elastic forces.
    virtual std::size_t
    first_constraint_interaction(const System &) const
    {
      return 0;
    }

    /// Solver iterations per step (XPBD), 0 for the force-based integrators.
    virtual unsigned
    iterations() const
    {
      return 0;
    }

    /// The solver settings in a few words for the record ("2 iterations"), empty when
    /// there are none.
    virtual std::string
    settings() const
    {
      return "";
    }
  };

  /// XPBD's parts the position-based integrators share (xpbd_integrator.cc):
  /// nodes.force = the external loads and the forces of the contacts that act by force
  /// (detected at the step's start);
  void
  external_forces(System &system);
  /// one Gauss–Seidel sweep over the interactions from @p first on and the projected
  /// contacts;
  void
  project_constraints(System &system, double dt, std::size_t first = 0);
  /// v = (1 − c dt)(x − x_prev)/dt after the sweeps (held nodes undamped);
  void
  update_velocities(Nodes &nodes, double dt, double damping_rate);
  /// "n iterations + m suture iterations" for the record.
  std::string
  sweep_settings(unsigned iterations, unsigned suture_iterations);

  /// Post-step strain limiting of every SpringSet in @p system; returns the number of
  /// springs corrected. Shared by the force-based integrators.
  std::size_t
  limit_strain(System &system, double limit, unsigned sweeps);
} // namespace suturesim::realtime
