/**
 * Quasi-static integration (seed 001 §2.2): with the forces large compared to the
 * nodes' kinetic energy the velocity is V = F/B, "calculated only from the forces acting
 * on the node at that instant", and P ← P + V dt. Explicit Euler on the gradient flow
 * B ẋ = F(x): stable for dt < 2/λ_max(B^{-1/2} K B^{-1/2}) (stability.h).
 */
#include <suturesim/realtime/integrator.h>
#include <suturesim/realtime/stability.h>

#include <sstream>

namespace suturesim::realtime
{
  namespace
  {
    class QuasiStatic : public Integrator
    {
    public:
      QuasiStatic(const ParameterValues &p)
        : tissue_damping(p.real("Tissue damping"))
        , suture_damping(p.real("Suture damping"))
        , strain(p.real("Strain limit"))
        , sweeps(p.integer("Strain limit sweeps"))
      {
        p.require(tissue_damping > 0, "Tissue damping", "must be > 0 N s/m");
        p.require(suture_damping > 0, "Suture damping", "must be > 0 N s/m");
      }

      void
      setup(System &s) override
      {
        for (auto i = s.tissue.begin; i < s.tissue.end; ++i)
          s.nodes.damping[i] = tissue_damping;
        for (auto i = s.suture.begin; i < s.suture.end; ++i)
          s.nodes.damping[i] = suture_damping;
      }

      void
      step(System &s, const double dt) override
      {
        Nodes &n = s.nodes;
        s.total_forces(n.x);
        const Eigen::Index count = n.size();
        for (Eigen::Index i = 0; i < count; ++i)
          if (n.held[i])
            {
              n.v.col(i) = (n.target.col(i) - n.x.col(i)) / dt;
              n.x.col(i) = n.target.col(i);
            }
          else
            {
              n.v.col(i) = n.force.col(i) / n.damping[i];
              n.x.col(i) += dt * n.v.col(i);
            }
        if (strain > 0)
          limit_strain(s, strain, sweeps);
      }

      double
      stability_limit(const System &s) const override
      {
        const auto estimate = largest_eigenvalue(s, s.nodes.x, s.nodes.damping);
        rate                = estimate.value;
        return rate > 0 ? 2 / rate : std::numeric_limits<double>::infinity();
      }

      std::string
      limit_description() const override
      {
        std::ostringstream d;
        d << "dt_crit = 2/lambda_max(B^-1 K), lambda_max = " << rate << " 1/s";
        return d.str();
      }

    private:
      double         tissue_damping, suture_damping, strain;
      long           sweeps;
      mutable double rate = 0;
    };

    const bool registered = Integrator::Registry::instance().add(
      {"quasi-static",
       "V = F/B, P <- P + dt F/B (seed 001 sec. 2.2, seed 002 sec. 4.B): no inertia, "
       "velocity from the forces of the instant; stable for dt < 2/lambda_max(B^-1 K).",
       [](ParameterDeclarations &d) {
         d.add_real("Tissue damping", 1.0, 0, 1e12,
                    "B of the tissue nodes in V = F/B. Unit: N s/m. Range: > 0.");
         d.add_real("Suture damping", 0.1, 0, 1e12,
                    "B of the suture nodes in V = F/B. Unit: N s/m. Range: > 0.");
         d.add_real("Strain limit", 0, 0, 10,
                    "Post-step strain limiting (seed 003, Provot 1995): springs strained by "
                    "more than this are moved back to it; 0 = off. Unit: 1. Range: >= 0.");
         d.add_integer("Strain limit sweeps", 4, 1, 100,
                       "Gauss-Seidel sweeps of the strain limiting. Unit: 1. Range: 1-100.");
       },
       [](const ParameterValues &p) { return std::unique_ptr<Integrator>(new QuasiStatic(p)); }});
  } // namespace
} // namespace suturesim::realtime
