#pragma once
/**
 * @file
 * An open overhand knot (trefoil) in a naturally straight Cosserat rod, pulled tight by
 * its ends: the accurate path's tightening curve (issue 30).
 *
 * The knot is laid along the trefoil (sin t + 2 sin 2t, cos t − 2 cos 2t, −sin 3t)·a, cut
 * open at the tip of a lobe (t = π) and given straight tails along the tangent there.
 * The rod is stress free in that shape at first; the tying is a continuation:
 *   1. an end tension F₀ is ramped up on the stress-free knot (the first end pinned, the
 *      last one free along the tails' axis x), so that nothing in the knot is slack;
 *   2. the rest shape is straightened under F₀: the elements' rest rotations and chords
 *      are the knot's scaled by s, from s = 1 to s = 0 (a naturally straight rod);
 *   3. the last end is then held where F₀ left it and pulled along x, step by step.
 * Every stage, and every pull step, is solved to equilibrium through pseudo-time steps
 * with a small viscous drag (viscous_drag.h), which keeps each Newton solve well posed
 * however slack the knot, until no node's drag exceeds 10⁻⁵ B/h²; a stage or step whose
 * solve fails is halved. The first end's twist is held (it removes
 * the rigid rotation about the tails' axis), the last end's is free, so that no twist
 * is stored in the rod.
 *
 * At each state it reports what Audoly, Clauvelin & Neukirch (PRL 99, 164301, 2007)
 * relate: the end tension F (the first end's reaction along x) and the radius of
 * curvature R where the rope leaves the braid (1/max κ between the first and the last
 * node in contact). Their law for a trefoil, in ε = √(h/R), h the rod's radius and B
 * its bending stiffness:
 *   F h²/B = ε⁴/2 + μ σ ε³,  σ = 0.492,
 * leading order in ε and in the friction coefficient μ (references.md).
 */

#include <suturesim/rod/rod_model.h>

#include <string>
#include <vector>

namespace suturesim::rod
{
  struct KnotTighteningParameters
  {
    double radius         = 1e-3; ///< h, m
    double youngs_modulus = 1e7;  ///< E, Pa (B = E π h⁴/4)
    double poisson        = 0.3;  ///< ν (GJ = B/(1 + ν))
    /// EA and GA as this multiple of E π h²: a nearly inextensible, unshearable rod, as
    /// the theory's Kirchhoff rod (the tight knot's strain would otherwise be ε⁴/8).
    double axial_factor = 100;
    double knot_scale   = 6;    ///< a/h of the trefoil
    double tail         = 20;   ///< each tail's length, in h
    double element      = 0.75; ///< element length, in h
    double contact_stiffness = 1e4;  ///< penalty k, N/m
    double smoothing         = 0.05; ///< penalty smoothing δ, in h
    double friction          = 0;    ///< μ
    double stick_stiffness   = 1e4;  ///< k_t, N/m
    double pretension        = 2.5e-3; ///< F₀, in B/h²
    double pull_step         = 1;      ///< end displacement per step, in h
    double drag              = 10;     ///< pseudo-time drag, N s/m² (over steps of 1 s)
  };

  /// One equilibrium of the pulled knot.
  struct KnotState
  {
    double pulled     = 0; ///< the last end's displacement since the knot was tied, m
    double shortening = 0; ///< e = L − |x_N − x_0|, m
    double force      = 0; ///< F, N
    double radius     = 0; ///< R, m (0: no contact, no knot)
    /// The least centreline distance of the pairs in contact, in 2h (1: touching;
    /// below, the strands interpenetrate by 2h (1 − closest)).
    double closest    = 1;
    std::size_t contacts = 0; ///< nodes in contact
    unsigned iterations = 0;  ///< Newton iterations of the state's solves
  };

  class KnotTightening
  {
  public:
    explicit KnotTightening(const KnotTighteningParameters &parameters);

    /// Steps 1 and 2 above; false (with failure()) if a stage could not be solved.
    bool
    tie();
    /// One pull step (cut back when its solve fails); false with failure() if even a
    /// thousandth of the step fails.
    bool
    pull();

    KnotState
    state() const;
    const RodModel &
    model() const
    {
      return rod;
    }
    /// B, N m².
    double
    bending_stiffness() const;
    const std::string &
    failure() const
    {
      return why;
    }

    /// Audoly et al.'s F h²/B at ε = √(h/R) for a trefoil with friction μ.
    static double
    audoly_tension(double eps, double mu);

  private:
    KnotTighteningParameters prm;
    std::vector<Vec3>        knot;   // the laid-out knot's nodes
    std::vector<Quat>        frames; // and their parallel-transported frames
    std::vector<double>      rest;   // element lengths
    RodModel                 rod;
    double                   pulled    = 0;
    double                   end_force = 0;
    unsigned                 last_iterations = 0;
    std::string              why;

    RodModel
    make(double s, double tension, const std::vector<Vec3> &x, const std::vector<Quat> &q) const;
    bool
    settle(RodModel &m, unsigned &iterations) const;
    /// Commits the friction's anchors and reads the end force.
    void
    accept();
  };
} // namespace suturesim::rod
