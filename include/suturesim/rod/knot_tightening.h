#pragma once
/**
 * @file
 * An open knot, the overhand (trefoil), the figure-eight or the cinquefoil, in a naturally straight
 * Cosserat rod, pulled tight by its ends: the accurate path's tightening curves (issue 30).
 *
 * The knot is laid along a closed knot of knot/curves.h scaled by a, cut open where it
 * is furthest from its axis (the trefoil at the tip of a lobe, t = π; the figure-eight
 * and the cinquefoil at t = 0) and given straight tails along the tangent there; the two passes through
 * the cut are lifted apart by the closed knot's clearance (one above the other, seen
 * along the diagram's normal), and the whole turned so that its ends lie along x.
 * The rod is stress free in that shape at first; the tying is a continuation:
 *   1. an end tension F₀ is ramped up on the stress-free knot (the first end pinned, the
 *      last one free along the tails' axis x), so that nothing in the knot is slack;
 *   2. the rest shape is straightened under F₀: the elements' rest rotations and chords
 *      are the knot's scaled by s, from s = 1 to s = 0 (a naturally straight rod);
 *   3. the last end is then held where F₀ left it and pulled along x, step by step.
 * Every stage, and every pull step, is solved to equilibrium through pseudo-time steps
 * with a small viscous drag (viscous_drag.h), which keeps each Newton solve well posed
 * however slack the knot, until neither any node's drag nor their sum (what the two
 * ends' reactions differ by) exceeds 10⁻⁵ B/h². A stage or step whose
 * solve fails is halved; a pseudo-time step that fails is retried at a tenth of its
 * length. The first end's twist is held (it removes the rigid rotation about the tails'
 * axis), the last end's is free, so that no twist is stored in the rod.
 *
 * At each state it reports what Audoly, Clauvelin & Neukirch (PRL 99, 164301, 2007)
 * relate: the end tension F (the first end's reaction along x) and the radius of
 * curvature R where the rope leaves the braid (1/max κ between the first and the last
 * node in contact). Their law for a trefoil, in ε = √(h/R), h the rod's radius and B
 * its bending stiffness:
 *   F h²/B = ε⁴/2 + μ σ ε³,  σ = 0.492,
 * leading order in ε and in the friction coefficient μ (as references.md and the
 * discrete-elastic-rod code dismech-newton's examples/overhand_knot.py state it; the
 * paper was not reachable here). Each state also reports R₀, where the loop's tension
 * vanishes: there Kirchhoff's first integral (first_integral()) makes ½Bκ² = F exactly
 * in a frictionless knot, whatever R the paper reads. Measured: docs/knots.md.
 */

#include <suturesim/rod/rod_model.h>

#include <functional>
#include <string>
#include <vector>

namespace suturesim::rod
{
  /// A circular section of radius @p r and Young's modulus @p E, B = E π r⁴/4 and
  /// GJ = B/(1 + ν), with EA and GA @p axial_factor times E π r²: a nearly inextensible,
  /// unshearable rod, as the theory's Kirchhoff rod (a tight knot's strain would
  /// otherwise be about ε⁴/8).
  inline SectionStiffness
  kirchhoff_section(const double r, const double E, const double nu, const double axial_factor)
  {
    const double     B = E * M_PI * r * r * r * r / 4, axial = axial_factor * E * M_PI * r * r;
    SectionStiffness s;
    s.force << axial, axial, axial;
    s.moment << B / (1 + nu), B, B;
    return s;
  }

  /// Lengths in m, forces in N (SI); the defaults are a rubber-like rod of radius 1 mm.
  struct KnotTighteningParameters
  {
    double           radius  = 1e-3;                                   ///< h, m
    SectionStiffness section = kirchhoff_section(1e-3, 1e7, 0.3, 100); ///< B = EI₂ = EI₃
    /// Penalty k (N/m) and smoothing δ (m), friction μ and stick stiffness k_t (N/m);
    /// enabled and radius are set from the above.
    ContactParameters contact{true, 1e4, 5e-5, 1e-3, 0, 1e4};
    std::string knot  = "overhand"; ///< overhand, figure-eight or cinquefoil (knot/curves.h)
    double knot_size  = 6e-3;    ///< a, the closed knot's scale, m
    double tail       = 20e-3;   ///< each tail's length, m
    double element    = 0.75e-3; ///< element length, m
    double pretension = 0.0196;  ///< F₀, N (2.5·10⁻³ B/h² here)
    double pull_step  = 2e-3;    ///< end displacement per pull(), m
    double drag       = 10;      ///< pseudo-time drag, N s/m² (over steps of 1 s)
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
    /// R₀, m: the radius of curvature where the loop's tension N·t vanishes, the mean
    /// over such points of the longest contact-free stretch between the first and the
    /// last contact (0: none, the loop in tension throughout). There ½Bκ² = H, so with
    /// H = F (frictionless) F R₀²/B = ½ H/F (first_integral()).
    double loop_radius = 0;
    /// max |H/F − 1| over the elements (first_integral()): 0 for an exact frictionless
    /// equilibrium of the continuum rod.
    double first_integral_spread = 0;
    /// The last end's reaction along x over the first end's, − 1: what the pseudo-time
    /// drag still carries when the state is accepted (0 at an exact equilibrium).
    double end_force_imbalance = 0;
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
    /// Kirchhoff's first integral at each element's centre, in material components,
    ///   H = N·(E₁ + Γ) + M·K − W = N·E₁ + ½ N·Γ + ½ M·K  (W quadratic),
    /// which a uniform elastic rod conserves along any stretch free of distributed loads
    /// (the rod's Hamiltonian in s: Kehrbaum & Maddocks, Phil. Trans. R. Soc. A 355,
    /// 1997; planar and inextensible, ½Bκ² + N·t = const). A frictionless contact between circular sections pushes
    /// normal to both centrelines, dH/ds = −p·t = 0, so through the whole tied knot H
    /// equals its tails' F + F²/(2EA): wherever the tangent is normal to the internal
    /// force, ½Bκ² = F, Audoly et al.'s F = B/(2R²) read at that point. N (m).
    std::vector<double>
    first_integral() const;
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

    /// The direction the knot's diagram is read along: the closed knot's own diagram
    /// normal (z of knot/curves.h) made normal to the tangent at the cut and turned with
    /// the knot, made normal to x (the ends' line): the tails run across the view and
    /// cross nothing but each other (a twist through the rope's closure, which
    /// knot::GaussCode::reduced() removes). Seen along it, the laid knot reads its closed
    /// code cut open.
    Vec3
    projection_normal() const;
    /// A bound on the least distance of the laid knot's strands over its scale a: 0.95
    /// of the closed knot's (knot/curves.h); std::invalid_argument for another name.
    static double
    strand_clearance(const std::string &knot);
    /// The knots a specimen can be laid as: overhand, figure-eight, cinquefoil.
    static const std::vector<std::string> &
    laid_knots();

    /// Audoly et al.'s F h²/B at ε = √(h/R) for a trefoil with friction μ.
    static double
    audoly_tension(double eps, double mu);

  private:
    /// The laid knot's nodes and frames, and projection_normal().
    struct LaidKnot
    {
      std::vector<Vec3> x;
      std::vector<Quat> q;
      Vec3              normal;
    };
    KnotTightening(const KnotTighteningParameters &parameters, LaidKnot laid);
    static LaidKnot
    lay(const KnotTighteningParameters &p);

    KnotTighteningParameters prm;
    Vec3                     normal; // projection_normal()
    std::vector<Vec3>        knot;   // the laid-out knot's nodes
    std::vector<Quat>        frames; // and their parallel-transported frames
    std::vector<double>      rest;   // element lengths
    RodModel                 rod;
    double                   pulled    = 0;
    double                   end_force = 0, last_end_force = 0;
    unsigned                 last_iterations = 0;
    std::string              why;

    RodModel
    make(double s, double tension, const std::vector<Vec3> &x, const std::vector<Quat> &q) const;
    /// Solves @p m to equilibrium (above); what failed, or empty.
    std::string
    settle(RodModel &m, unsigned &iterations) const;
    /// Commits the friction's anchors and reads the end force.
    void
    accept();
    /// Fills @p s's loop_radius, first_integral_spread and end_force_imbalance, with
    /// @p first and @p last the first and last nodes in contact.
    void
    loop_reading(KnotState &s, std::size_t first, std::size_t last) const;
    /// Takes a continuation parameter from 0 to @p total through @p attempt(from, to),
    /// which solves and keeps the state at `to` or reports failure: the increment starts
    /// at @p first, is halved after a failure and doubled (up to @p largest) after a
    /// success; false once it falls below @p smallest.
    static bool
    advance(double total, double first, double largest, double smallest,
            const std::function<bool(double, double)> &attempt);
  };
} // namespace suturesim::rod
