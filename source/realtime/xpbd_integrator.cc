/**
 * XPBD (Macklin, Müller & Chentanez 2016, "XPBD: position-based simulation of compliant
 * constrained dynamics", Algorithm 1): predict x* = x + dt v + dt² M⁻¹ f_ext, then
 * Gauss–Seidel iterations over every constraint with Δλ = (−C − α̃λ)/(∇C M⁻¹ ∇Cᵀ + α̃),
 * α̃ = α/dt², and v = (x − x_prev)/dt. Every interaction of the system is a constraint
 * with compliance α = 1/k; contacts that can project are projected, the others (seed
 * 000's repelling force) enter as external forces. Damping: v ← (1 − c dt) v.
 *
 * Suture iterations: extra Gauss–Seidel sweeps over the suture's constraints and the
 * contacts only, after the full sweeps. A block Gauss–Seidel that visits the stiff,
 * small block more often: a 3-0 suture link (k = EA/l ≈ 2e5 N/m, w ≈ 4e7 1/kg, α̃ ≈ 5)
 * is far from converged after a sweep, whereas the tissue's (α̃ of the order of w for
 * soft tissue) gains little per sweep; the suture's hundred constraints cost about as
 * much as a hundred of the tissue's thousands (the split of seed 004's two stages).
 *
 * Warm start (`Warm start = true`): the tissue's constraints keep their multipliers from
 * step to step (Interaction::warm_multipliers) and the sweeps start from the positions
 * they imply, the prediction plus the displacement the tissue's projections made in the
 * last step, so that a few sweeps per step converge over the steps instead of restarting
 * from zero every step; the converged step is unchanged.
 *
 * Threads (`Threads` ≥ 2): the tissue's sweeps by domain decomposition (slab_sweep.h),
 * the first of each step beside the projected contacts' detection on a helper.
 * A family whose topology changes later (seed 002's subdivision) loses its blocks and is
 * swept on this thread from then on.
 */
#include <suturesim/realtime/integrator.h>
#include <suturesim/realtime/slab_sweep.h>

#include <memory>

namespace suturesim::realtime
{
  namespace
  {
    class Xpbd : public Integrator
    {
    public:
      Xpbd(const ParameterValues &p)
        : n_iterations(p.integer("Iterations"))
        , damping(p.real("Damping rate"))
        , suture_iterations(p.integer("Suture iterations"))
        , warm(p.boolean("Warm start"))
        , refresh(p.integer("Warm start refresh"))
        , slabs(p.integer("Threads") > 1 ? std::make_unique<SlabSweep>(p.integer("Threads"), p.real("Slab share"))
                                         : nullptr)
      {}

      /// Cuts the tissue into slabs (Threads > 1) before the first step, so that the
      /// reordering and its allocations happen before any reaction lists are taken.
      void
      setup(System &s) override
      {
        if (warm) // a family that cannot keep its multipliers says so now (λ = 0 kept at 0)
          for (std::size_t k = 0; k < s.first_suture_interaction; ++k)
            s.interactions[k]->warm_multipliers(s.nodes.inverse_mass, 0.0);
        if (slabs && !partitioned)
          {
            slabs->partition(s);
            partitioned = true;
          }
      }

      void
      step(System &s, const double dt) override
      {
        Nodes             &n     = s.nodes;
        const Eigen::Index count = n.size();
        n.previous               = n.x;

        // external forces: loads, and contacts that act by force
        external_forces(s);
        for (Eigen::Index i = 0; i < count; ++i)
          if (n.held[i])
            n.x.col(i) = n.target.col(i);
          else
            {
              n.v.col(i) += dt * (s.gravity + n.force.col(i) / n.mass[i]);
              n.x.col(i) += dt * n.v.col(i);
            }

        // λ scales with dt² (λ = f dt²): a changed step carries the forces over; the
        // first step, and one after nodes were added, start cold
        const bool   sized = displacement.cols() == count;
        const double scale = warm && previous_dt > 0 && sized ? (dt / previous_dt) * (dt / previous_dt) : 0.0;
        previous_dt        = dt;
        if (warm && !sized)
          displacement.setZero(3, count);
        if (!slabs) // with slabs, beside the first sweep
          {
            s.detect_contacts(n.x, System::Contacts::projected);
            start_multipliers(s, scale, dt);
          }
        for (unsigned it = 0; it < n_iterations; ++it)
          {
            sweep_tissue(s, dt, it == 0, scale);
            if (it == 0) // the contacts are found by now
              for (const auto &c : s.contacts)
                if (c->has_projection())
                  c->reset_multipliers();
            project_constraints(s, dt, s.first_suture_interaction);
          }
        if (warm && ++since_refresh >= refresh)
          refresh_displacement(s, dt);
        for (unsigned it = 0; it < suture_iterations; ++it)
          project_constraints(s, dt, s.first_suture_interaction);
        update_velocities(n, dt, damping);
      }

      bool
      position_based() const override
      {
        return true;
      }

      unsigned
      iterations() const override
      {
        return n_iterations;
      }

      std::string
      settings() const override
      {
        return sweep_settings(n_iterations, suture_iterations) + (warm ? ", warm-started" : "") +
               (slabs ? ", " + std::to_string(slabs->threads()) + " threads" : "");
      }

    private:
      /// The multipliers at the step's start: the tissue's kept from the last step and
      /// scaled by @p scale, the nodes moved by the displacement they imply (warm start;
      /// the tissue only: a stiff suture's large multipliers, applied along links that
      /// turned since, throw it off, measured: it diverges at once), or zero when
      /// @p scale is 0.
      void
      start_multipliers(System &s, const double scale, const double dt)
      {
        Nodes &n = s.nodes;
        for (std::size_t k = 0; k < s.interactions.size(); ++k)
          {
            Interaction &i = *s.interactions[k];
            if (scale > 0 && k < s.first_suture_interaction)
              i.warm_multipliers(n.inverse_mass, scale);
            else
              i.reset_multipliers();
            i.prepare_projection(dt);
          }
        if (!warm)
          return;
        // x = x̃ + M⁻¹∇Cᵀλ: the last step's displacement, which is M⁻¹ Σ ∇Cᵀ Δλ over
        // its projections, scaled as λ; none at a held node, which no sweep moves
        for (Eigen::Index i = 0; i < n.size(); ++i)
          if (scale > 0 && n.inverse_mass[i] > 0)
            n.x.col(i) += (displacement.col(i) *= scale);
          else
            displacement.col(i).setZero();
      }

      /// One sweep over the tissue's constraints (by slabs with Threads > 1), adding the
      /// nodes' displacement to the next step's warm start. The @p first of a step with
      /// slabs runs beside the contact detection and starts the multipliers (scaled by
      /// @p scale); the collision phase counts the time this thread then waited for the
      /// helpers after its own slab.
      void
      sweep_tissue(System &s, const double dt, const bool first, const double scale)
      {
        Nodes &n = s.nodes;
        if (slabs && first)
          {
            predicted         = n.x; // where a sequential step finds the contacts
            const auto before = s.detection_time;
            const auto waited = slabs->sweep_beside_detection(s, dt, predicted, [&] {
              start_multipliers(s, scale, dt);
              if (warm)
                sweep_start = n.x;
            });
            s.detection_time = before + waited;
          }
        else
          {
            if (warm)
              sweep_start = n.x;
            if (slabs)
              slabs->sweep(s, dt);
            else
              for (std::size_t k = 0; k < s.first_suture_interaction; ++k)
                s.interactions[k]->project(n.x, n.inverse_mass, dt);
          }
        if (warm)
          displacement += n.x - sweep_start;
      }

      /// The warm start's displacement recomputed from the multipliers, M⁻¹∇C(x)ᵀλ =
      /// dt² M⁻¹ f with f the constraint forces. Between refreshes it is the sweeps' own
      /// displacement, M⁻¹ Σ ∇C(x_k)ᵀ Δλ_k with each gradient where its projection found
      /// it: as the constraints turn, that sum drifts from M⁻¹∇C(x)ᵀλ, and the drift
      /// would act as a force no multiplier accounts for.
      void
      refresh_displacement(System &s, const double dt)
      {
        Nodes &n = s.nodes;
        if (slabs)
          slabs->constraint_forces(s, dt, displacement);
        else
          {
            displacement.setZero();
            for (std::size_t k = 0; k < s.first_suture_interaction; ++k)
              s.interactions[k]->add_constraint_forces(n.x, displacement, dt);
          }
        for (Eigen::Index i = 0; i < n.size(); ++i)
          displacement.col(i) *= dt * dt * n.inverse_mass[i];
        since_refresh = 0;
      }

      unsigned                   n_iterations;
      double                     damping;
      unsigned                   suture_iterations;
      bool                       warm;
      unsigned                   refresh;           ///< Warm start refresh, steps
      unsigned                   since_refresh = 0; ///< steps since refresh_displacement()
      double                     previous_dt = 0; ///< s; 0 before the first step: nothing to warm-start from
      std::unique_ptr<SlabSweep> slabs;           ///< Threads > 1
      bool                       partitioned = false;
      Matrix3Xd                  predicted; ///< the positions the helper finds contacts at
      /// the tissue's projections' displacement of the nodes in the last step (m), the
      /// warm start's M⁻¹∇Cᵀλ
      Matrix3Xd displacement;
      Matrix3Xd sweep_start; ///< the positions before a tissue sweep (warm start)
    };

  } // namespace

  void
  external_forces(System &s)
  {
    Nodes &n = s.nodes;
    n.force  = n.external;
    s.detect_contacts(n.x, System::Contacts::by_force);
    for (const auto &c : s.contacts)
      if (!c->has_projection())
        c->add_forces(n.x, n.force);
  }

  void
  project_constraints(System &s, const double dt, const std::size_t first)
  {
    Nodes &n = s.nodes;
    for (auto i = first; i < s.interactions.size(); ++i)
      s.interactions[i]->project(n.x, n.inverse_mass, dt);
    for (const auto &c : s.contacts)
      if (c->has_projection())
        c->project(n.x, n.inverse_mass, dt);
  }

  void
  update_velocities(Nodes &n, const double dt, const double damping_rate)
  {
    const double keep = std::max(0.0, 1 - damping_rate * dt);
    for (Eigen::Index i = 0; i < n.x.cols(); ++i)
      n.v.col(i) = (n.held[i] ? 1.0 : keep) * (n.x.col(i) - n.previous.col(i)) / dt;
  }

  std::string
  sweep_settings(const unsigned iterations, const unsigned suture_iterations)
  {
    return std::to_string(iterations) + " iterations" +
           (suture_iterations > 0 ? " + " + std::to_string(suture_iterations) + " suture iterations" : "");
  }

  namespace
  {
    const bool registered = Integrator::Registry::instance().add(
      {"xpbd",
       "extended position-based dynamics (Macklin et al. 2016; seed 004): every "
       "interaction a compliant constraint (alpha = 1/k), Gauss-Seidel iterations; "
       "unconditionally stable, stiffness depends on iterations and dt.",
       [](ParameterDeclarations &d) {
         d.add_integer("Iterations", 10, 1, 1000,
                       "Gauss-Seidel iterations per step. Unit: 1. Range: 1-1000.");
         d.add_integer("Suture iterations", 0, 0, 1000,
                       "Extra Gauss-Seidel sweeps per step over the suture's constraints "
                       "and the contacts only, after the full ones (the stiff suture "
                       "converges slowly, the soft tissue fast). Unit: 1. Range: 0-1000.");
         d.add_bool("Warm start", false,
                    "Start each step's sweeps from the last step's Lagrange multipliers (scaled "
                    "by (dt/dt_prev)^2) and the positions they imply, instead of from zero: one "
                    "sweep then holds a static equilibrium at the converged state, where a cold "
                    "start settles where one sweep's multipliers balance the load (softer). "
                    "Tissue springs, volume and home constraints; the suture and contacts start "
                    "cold. Unit: none.");
         d.add_integer("Warm start refresh", 8, 1, 1000,
                       "With the warm start: every this many steps the displacement the "
                       "multipliers imply, M^-1 grad C^T lambda, is recomputed from the "
                       "constraint forces (a pass over the tissue's constraints); in "
                       "between it is the tissue sweeps' own displacement, which drifts "
                       "from it as the constraints turn. 1: every step. Unit: steps. "
                       "Range: 1-1000.");
         d.add_integer("Threads", 1, 1, 64,
                       "Threads of the step: 2 or more sweep the tissue's springs and volumes "
                       "by domain decomposition (one slab of nodes per thread along the "
                       "tissue's longest extent, then the constraints between slabs); the "
                       "first helper finds the contacts before it sweeps its slab. The helpers "
                       "spin between the step's phases: give each a core of its own. Unit: 1. "
                       "Range: 1-64.");
         d.add_real("Slab share", 0.5, 0.05, 0.95,
                    "With Threads >= 2: the fraction of the tissue's nodes in the haptic "
                    "thread's slab (the helpers share the rest equally). Above 1/Threads "
                    "when the contact detection, which the first helper does before its "
                    "slab, is a large part of the step. Unit: 1. Range: 0.05-0.95.");
         d.add_real("Damping rate", 0, 0, 1e9,
                    "Velocity damping v <- (1 - c dt) v after each step. Unit: 1/s. "
                    "Range: >= 0.");
       },
       [](const ParameterValues &p) { return std::unique_ptr<Integrator>(new Xpbd(p)); }});
  } // namespace
} // namespace suturesim::realtime
