/**
 * Quasi-static integration (seed 001 §2.2): with the forces large compared to the
 * nodes' kinetic energy the velocity is V = F/B, "calculated only from the forces acting
 * on the node at that instant", and P ← P + V dt. Explicit Euler on the gradient flow
 * B ẋ = F(x): stable for dt < 2/λ_max(B^{-1/2} K B^{-1/2}) (stability.h).
 *
 * Two laws for B. The seeds' B is one constant per node ("per node"): a finer mesh
 * then has more damping in all, so a pull's viscous lag, and a closure tension taken
 * during it, depend on the mesh (docs/interrupted_stitch.md: 3.30 N at 2 mm, 4.47 N at
 * 1.5 mm, no closure at 1 mm). "per unit mass" sets B_i = β m_i with the lumped mass
 * m_i: B = βM is the semi-discretisation of the continuum's viscous drag β ρ u̇ = ∇·σ + f,
 * so the damped flow, and its lag, converge under refinement (Rayleigh's mass-
 * proportional damping with the inertia dropped). Its price: the stable step
 * 2/λ_max(M⁻¹K)·β shrinks like h², as an explicit step's does.
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
        : per_mass(p.text("Damping") == "per unit mass")
        , strain(p.real("Strain limit"))
        , sweeps(p.integer("Strain limit sweeps"))
      {
        // the law's own keys: B per node in N s/m, or β in 1/s
        const std::string tissue = per_mass ? "Tissue damping rate" : "Tissue damping";
        const std::string suture = per_mass ? "Suture damping rate" : "Suture damping";
        const std::string unit   = per_mass ? "must be > 0 1/s" : "must be > 0 N s/m";
        tissue_damping           = p.real(tissue);
        suture_damping           = p.real(suture);
        p.require(tissue_damping > 0, tissue, unit);
        p.require(suture_damping > 0, suture, unit);
      }

      void
      setup(System &s) override
      {
        assign_damping(s);
      }

      void
      step(System &s, const double dt) override
      {
        Nodes &n = s.nodes;
        if (per_mass) // a model whose topology grows (seed 002's subdivision) moves mass
          assign_damping(s);
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

      bool
      quasi_static() const override
      {
        return true;
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
      /// B per node: the constant, or β m_i of the node's current lumped mass.
      void
      assign_damping(System &s) const
      {
        Nodes &n = s.nodes;
        for (auto i = s.tissue.begin; i < s.tissue.end; ++i)
          n.damping[i] = per_mass ? tissue_damping * n.mass[i] : tissue_damping;
        for (auto i = s.suture.begin; i < s.suture.end; ++i)
          n.damping[i] = per_mass ? suture_damping * n.mass[i] : suture_damping;
      }

      bool           per_mass;
      double         tissue_damping, suture_damping, strain;
      long           sweeps;
      mutable double rate = 0;
    };

    const bool registered = Integrator::Registry::instance().add(
      {"quasi-static",
       "V = F/B, P <- P + dt F/B (seed 001 sec. 2.2, seed 002 sec. 4.B): no inertia, "
       "velocity from the forces of the instant; stable for dt < 2/lambda_max(B^-1 K).",
       [](ParameterDeclarations &d) {
         d.add_selection("Damping", "per node", "per node|per unit mass",
                         "Law of B in V = F/B: 'per node' (seeds 001, 002) is one constant B "
                         "per node, so the total damping grows with the node count and a "
                         "pull's lag depends on the mesh; 'per unit mass' is B_i = beta m_i "
                         "(lumped mass m_i), consistent under refinement. Unit: none.");
         d.add_real("Tissue damping", 1.0, 0, 1e12,
                    "B of each tissue node in V = F/B (Damping = per node). Unit: N s/m. "
                    "Range: > 0.");
         d.add_real("Suture damping", 0.1, 0, 1e12,
                    "B of each suture node in V = F/B (Damping = per node). Unit: N s/m. "
                    "Range: > 0.");
         d.add_real("Tissue damping rate", 2e7, 0, 1e15,
                    "beta of the tissue in B_i = beta m_i (Damping = per unit mass); "
                    "beta rho is the continuum's drag per volume. The default gives a "
                    "node of 3 mg (the 1.5 mm skin pad's mean) B = 60 N s/m, the "
                    "stitch's. Unit: 1/s. Range: > 0.");
         d.add_real("Suture damping rate", 3e6, 0, 1e15,
                    "beta of the suture in B_i = beta m_i (Damping = per unit mass). The "
                    "default gives a node of 1 mm of 0.2 mm thread at 1100 kg/m^3 "
                    "(3.5e-8 kg) B = 0.1 N s/m, Suture damping's default. Unit: 1/s. "
                    "Range: > 0.");
         d.add_real("Strain limit", 0, 0, 10,
                    "Post-step strain limiting (seed 003, Provot 1995): springs strained by "
                    "more than this are moved back to it; 0 = off. Unit: 1. Range: >= 0.");
         d.add_integer("Strain limit sweeps", 4, 1, 100,
                       "Gauss-Seidel sweeps of the strain limiting. Unit: 1. Range: 1-100.");
       },
       [](const ParameterValues &p) { return std::unique_ptr<Integrator>(new QuasiStatic(p)); }});
  } // namespace
} // namespace suturesim::realtime
