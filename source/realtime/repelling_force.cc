/**
 * Seed 000's repelling force for knot tying, eq. (1): F = k_c exp(k_o (2d − o_ij)),
 * "k_c the repulsion factor, k_o the nonlinear-growing factor, d the width of suture,
 * o_ij the distance between line segments": as the distance shrinks the force grows
 * exponentially. Applied along the line between the segments' closest points, shared
 * by the segment end nodes in proportion to the closest-point parameters (so the force
 * and its moment about the pair are kept). Cut off at o_ij = 2d + ln(1000)/k_o, where it
 * has fallen to 10⁻³ k_c, so that distant segments cost nothing.
 *
 * Its potential: F = −dE/do_ij of E = (k_c/k_o) exp(k_o (2d − o_ij)) per pair; the
 * closest points minimise the distance, so (envelope theorem) ∂o_ij/∂x of a segment's
 * end node is its closest-point weight times the unit normal, and the shared force above
 * is exactly −∂E/∂x (tests/realtime/interaction_test.cc checks it).
 */
#include <suturesim/realtime/self_collision.h>

#include <cmath>

namespace suturesim::realtime
{
  namespace
  {
    /// o_ij where the force has fallen to 10⁻³ k_c, m.
    double
    cutoff_of(const double width, const double growth)
    {
      return 2 * width + std::log(1000.0) / growth;
    }

    class RepellingForce : public SelfCollision
    {
    public:
      RepellingForce(const ParameterValues &p, const SelfCollisionSetup &s)
        : SelfCollision(s, cutoff_of(2 * s.radius, p.real("Growth factor")))
        , factor(p.real("Repulsion factor"))
        , growth(p.real("Growth factor"))
        , width(2 * s.radius)
        , cutoff(cutoff_of(width, growth))
      {
        p.require(growth > 0, "Growth factor", "must be > 0 1/m");
      }

      std::string
      name() const override
      {
        return "repelling force (seed 000 eq. 1)";
      }

      void
      detect(const Matrix3Xd &x) override
      {
        find_pairs(x, cutoff);
        count_pairs();
      }

      std::optional<double>
      energy(const Matrix3Xd &x) const override
      {
        double e = 0;
        for (const auto &c : pairs)
          e += factor / growth * std::exp(growth * (2 * width - distance(x, c.a, c.b)));
        return e;
      }

      void
      add_forces(const Matrix3Xd &, Matrix3Xd &f) const override
      {
        const std::uint32_t b0 = setup.suture.begin;
        for (const auto &c : pairs)
          {
            const Vector3d F = factor * std::exp(growth * (2 * width - c.distance)) * c.normal;
            f.col(b0 + c.a) += (1 - c.s) * F;
            f.col(b0 + c.a + 1) += c.s * F;
            f.col(b0 + c.b) -= (1 - c.t) * F;
            f.col(b0 + c.b + 1) -= c.t * F;
          }
      }

    private:
      double factor, growth, width, cutoff;
    };

    const bool registered = SelfCollision::Registry::instance().add(
      {"repelling-force",
       "F = k_c exp(k_o (2d - o_ij)) between non-adjacent segments at distance o_ij, d the "
       "suture width (seed 000 eq. 1).",
       [](ParameterDeclarations &d) {
         d.add_real("Repulsion factor", 1e-3, 0, 1e6,
                    "k_c of seed 000 eq. (1): the force at o_ij = 2d. Unit: N. Range: >= 0.");
         d.add_real("Growth factor", 2e4, 0, 1e12,
                    "k_o of seed 000 eq. (1). Unit: 1/m. Range: > 0.");
       },
       [](const ParameterValues &p, const SelfCollisionSetup &s) {
         return std::unique_ptr<SelfCollision>(new RepellingForce(p, s));
       }});
  } // namespace
} // namespace suturesim::realtime
