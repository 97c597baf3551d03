/**
 * Symplectic (semi-implicit) Euler, seed 001 eqs. 1–2 and seed 003's explicit Euler:
 * V_i = V_{i−1} + dt (F_i/M − c V_{i−1}), P_i = P_{i−1} + dt V_i, the damping force
 * −B V with B = c M (mass proportional, so that every mode sees the same rate c).
 * Stable for dt < (√(c² + 4ω²_max) − c)/ω²_max (= 2/ω_max without damping), ω²_max the
 * largest eigenvalue of M^{-1/2} K M^{-1/2} (stability.h).
 */
#include <suturesim/realtime/integrator.h>
#include <suturesim/realtime/stability.h>

#include <cmath>
#include <sstream>

namespace suturesim::realtime
{
  namespace
  {
    class SymplecticEuler : public Integrator
    {
    public:
      SymplecticEuler(const ParameterValues &p)
        : damping(p.real("Damping rate"))
        , strain(p.real("Strain limit"))
        , sweeps(p.integer("Strain limit sweeps"))
      {}

      void
      step(System &s, const double dt) override
      {
        Nodes &n = s.nodes;
        s.total_forces(n.x);
        const Eigen::Index count = n.size();
        const double       keep  = 1 - damping * dt;
        if (strain > 0)
          n.previous = n.x;
        for (Eigen::Index i = 0; i < count; ++i)
          if (n.held[i])
            {
              n.v.col(i) = (n.target.col(i) - n.x.col(i)) / dt;
              n.x.col(i) = n.target.col(i);
            }
          else
            {
              n.v.col(i) = keep * n.v.col(i) + (dt / n.mass[i]) * n.force.col(i);
              n.x.col(i) += dt * n.v.col(i);
            }
        if (strain > 0 && limit_strain(s, strain, sweeps) > 0)
          // the corrected positions define the velocity of the step (Provot 1995)
          for (Eigen::Index i = 0; i < count; ++i)
            if (!n.held[i])
              n.v.col(i) = (n.x.col(i) - n.previous.col(i)) / dt;
      }

      double
      stability_limit(const System &s) const override
      {
        const auto estimate = largest_eigenvalue(s, s.nodes.x, s.nodes.mass);
        omega               = std::sqrt(std::max(0.0, estimate.value));
        return symplectic_euler_limit(omega, damping);
      }

      std::string
      limit_description() const override
      {
        std::ostringstream d;
        d << "dt_crit = (sqrt(c^2 + 4 w^2) - c)/w^2 with w_max = " << omega
          << " rad/s, c = " << damping << " 1/s";
        return d.str();
      }

    private:
      double         damping, strain;
      long           sweeps;
      mutable double omega = 0;
    };

    const bool registered = Integrator::Registry::instance().add(
      {"symplectic-euler",
       "V <- V + dt (F/M - c V), P <- P + dt V (seed 001 eqs. 1-2, seed 003): explicit, "
       "stable for dt < (sqrt(c^2 + 4 w_max^2) - c)/w_max^2, w_max from the network.",
       [](ParameterDeclarations &d) {
         d.add_real("Damping rate", 0, 0, 1e9,
                    "Mass-proportional damping c (damping force -c M V). Unit: 1/s. "
                    "Range: >= 0.");
         d.add_real("Strain limit", 0, 0, 10,
                    "Post-step strain limiting (seed 003, Provot 1995): springs strained by "
                    "more than this are moved back to it; 0 = off. Unit: 1. Range: >= 0.");
         d.add_integer("Strain limit sweeps", 4, 1, 100,
                       "Gauss-Seidel sweeps of the strain limiting. Unit: 1. Range: 1-100.");
       },
       [](const ParameterValues &p) { return std::unique_ptr<Integrator>(new SymplecticEuler(p)); }});
  } // namespace
} // namespace suturesim::realtime
