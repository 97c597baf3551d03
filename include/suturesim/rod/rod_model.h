#pragma once
/**
 * @file
 * A Cosserat rod discretised by two-node Simo–Reissner elements (rod_element.h): nodal
 * positions and unit-quaternion rotations, constraints per nodal degree of freedom,
 * conservative and fixed-direction loads, self-contact, and Newton's method (full steps
 * or an energy line search).
 *
 * Unknowns per node: (Δx, θ), the translation and the spatial rotation increment
 * applied as R ← exp(θ̂)R (multiplicative update; quaternions are never added). The
 * residual is the spatial force and moment imbalance r = ∂W/∂(Δx, θ) − f_ext (+ inertia
 * when a time integrator adds it). Its Jacobian with respect to (Δx, θ) is the element
 * Hessian minus ½ r̂_W on each node's rotation block, where r_W is the elastic moment
 * residual at the node: the Hessian is that of the pull-back W(exp(θ̂)R), whose gradient
 * is J_l(θ)ᵀ r_W, and J_l(θ)ᵀ = I − ½θ̂ + O(θ²). With that term the tangent is the exact
 * derivative of the residual also for non-conservative loads (a moment of fixed
 * direction), so Newton converges quadratically.
 *
 * Linear solves: without contact the Jacobian of an open rod is block tridiagonal
 * (6 × 6 blocks) and is factorised by block LU in O(N) (block_tridiagonal.h); contact
 * couples distant nodes and the system then goes to a sparse LU (Eigen::SparseLU).
 */

#include <suturesim/rod/block_tridiagonal.h>
#include <suturesim/rod/contact_friction.h>
#include <suturesim/rod/rod_element.h>
#include <suturesim/rod/self_contact.h>

#include <Eigen/Core>

#include <array>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace suturesim::rod
{
  /// Mass per node of a lumped rod (translational and material rotational inertia).
  struct NodeInertia
  {
    double mass = 0;                  ///< kg
    Vec3   rotational = Vec3::Zero(); ///< material principal moments (J₁, J₂, J₃), kg m²
  };

  /// Terms a time integrator adds at every node: residual r (6) and Jacobian block (6×6)
  /// given the node's current position and rotation.
  using NodalTerms = std::function<void(std::size_t node, const Vec3 &x, const Quat &q,
                                        Vec6 &residual, Mat6 &jacobian)>;

  /// Terms coupling the two nodes of element e (a load at a point inside it, such as a
  /// pierce point the suture slides through): residual (12, nodes e and e + 1) and its
  /// Jacobian (12 × 12), added to the element's blocks; the Jacobian is nullptr when
  /// only the residual is wanted (a term whose Jacobian is costly skips it then).
  using ElementTerms = std::function<void(std::size_t element, Eigen::Matrix<double, 12, 1> &residual,
                                          Eigen::Matrix<double, 12, 12> *jacobian)>;
  /// Elements that @ref ElementTerms acts on (the others are skipped).
  using ElementList = std::vector<std::size_t>;

  /// One Newton iteration as NewtonParameters::observer sees it, in the state x_k it
  /// starts from: the free residual's norm there and the correction it takes (nullptr
  /// and 0 on the last call, at the state the solve stops in).
  struct NewtonIterate
  {
    unsigned               iteration = 0;
    double                 residual  = 0;
    const Eigen::VectorXd *delta     = nullptr;
    double                 step      = 0; ///< the fraction of delta taken
  };

  struct NewtonParameters
  {
    unsigned max_iterations    = 50;
    double   tolerance         = 1e-10; ///< relative residual
    /// Energy line-search trials per iteration; 0 = full Newton steps (halved only when
    /// a step would turn an element by π). On the roll-up and cantilever benchmarks full
    /// steps converge in half the iterations of the line search.
    unsigned line_search_steps = 0;
    /// Residual below which round-off dominates (N); the solver uses at least
    /// 1e-13 EA. Time integrators raise it to the round-off of their inertia terms.
    double absolute_floor = 0;
    /// Full steps only: the largest node displacement (m) and turn (rad) of one
    /// iteration; a longer correction is scaled down (0 = no cap).
    double max_displacement = 0;
    double max_rotation     = 0;
    /// With both caps set: a Newton correction longer than they allow is replaced by
    /// the Levenberg–Marquardt step (J + σD) δ = −r, D = diag(1/Δx², 1/Δθ²) per node
    /// from the caps Δx and Δθ, with the least σ whose step fits within the caps and
    /// descends (δ·r < 0): the step of a trust region of fixed size, the caps (Nocedal
    /// & Wright, Numerical Optimization, 2nd ed., §4.3; no ratio test adapts it). A
    /// scaled-down Newton correction keeps its direction, which on a slack or
    /// compressed thread (an indefinite J) is dominated by its softest modes: on the
    /// wound series' coarsest stitch the corrections would have turned nodes by a median
    /// of 37–2 300 rad, and the solve crawled at the cap for 500 iterations
    /// (docs/interrupted_stitch.md). false: the scaled-down Newton correction.
    bool trust_region = true;
    /// Full steps only: after this many iterations in a row without the residual
    /// falling below 0.99 of its least value so far, the solve goes on with the energy
    /// line search (line_search(), 4 trials, from the capped step). Full steps cycle
    /// where a pierce point's slip reverses across its narrow stick band, the slip's
    /// tangent (zero along the thread) blind to the stick spring; the line search lands
    /// in the band (docs/interrupted_stitch.md). 0: never.
    unsigned stall_window = 20;
    /// Called at every iteration (diagnostics: why a solve stalls); may read the rod.
    std::function<void(const NewtonIterate &)> observer;
    /// Called after every step: terms whose active set moves with the state (the pierce
    /// points' carrier elements) update it there and return true; the solve then
    /// assembles again at the same state. The stall window runs on across such changes.
    std::function<bool()> follow;
  };

  /// The residual split by what contributes it (6 per node, constrained components
  /// included): their sum is residual() with the same terms.
  struct ResidualParts
  {
    Eigen::VectorXd              elastic;       ///< the elements' internal forces
    Eigen::VectorXd              self_contact;  ///< the rod against itself
    Eigen::VectorXd              applied;       ///< minus the nodal forces and moments
    Eigen::VectorXd              element_terms; ///< set_element_terms()'s (pierce points)
    std::vector<Eigen::VectorXd> nodal;         ///< each of the NodalTerms given
  };

  struct NewtonResult
  {
    bool     converged  = false;
    unsigned iterations = 0;
    double   residual   = 0;
    std::string reason;
    /// The iteration from which the energy line search took over (NewtonParameters::
    /// stall_window; 0: it did not).
    unsigned line_search_from = 0;
  };

  class RodModel
  {
  public:
    /// A rod through @p x with nodal rotations @p q, stress free in that configuration.
    RodModel(const std::vector<Vec3> &x, const std::vector<Quat> &q,
             const SectionStiffness &section, double mass_per_length,
             const Vec3 &rotational_inertia_per_length);
    ~RodModel();

    std::size_t
    n_nodes() const
    {
      return pos.size();
    }
    std::size_t
    n_elements() const
    {
      return reference.size();
    }

    const std::vector<Vec3> &
    positions() const
    {
      return pos;
    }
    const std::vector<Quat> &
    rotations() const
    {
      return rot;
    }
    /// Node @p i at @p x with rotation @p q normalised (a unit quaternion may change in
    /// its last bit).
    void
    set_node(std::size_t i, const Vec3 &x, const Quat &q);
    /// Node @p i at @p x with rotation @p q exactly as given: a state this model had (a
    /// checkpoint's), already unit, which set_node()'s normalisation would change in its
    /// last bit and a restarted run's stick-slip steps amplify. The caller checks that
    /// @p q is unit.
    void
    restore_node(std::size_t i, const Vec3 &x, const Quat &q);

    const std::vector<ElementReference> &
    references() const
    {
      return reference;
    }
    const SectionStiffness &
    section() const
    {
      return stiffness;
    }
    const NodeInertia &
    inertia(std::size_t node) const
    {
      return lumped[node];
    }

    /// Fixes components of a node: 0–2 translation, 3–5 rotation.
    void
    constrain(std::size_t node, const std::array<bool, 6> &fixed);
    bool
    is_constrained(std::size_t node, unsigned component) const
    {
      return fixed[node][component];
    }

    /// Cuts the rod at element @p element: it is left out from then on (no energy, force
    /// or stiffness; its nodes turn and move apart freely), so the rod is two pieces,
    /// each of which must be held for a solve (an interrupted series' thread cut beside a
    /// stitch's knot, scene/interrupted_series.h). Self-contact still sees the element.
    void
    cut(std::size_t element);
    bool
    is_cut(std::size_t element) const
    {
      return cut_element[element] != 0;
    }

    /// Fixed-direction nodal forces (N) and moments (N m), spatial.
    std::vector<Vec3> &
    forces()
    {
      return force;
    }
    std::vector<Vec3> &
    moments()
    {
      return moment;
    }

    /// Adds @p terms on the elements @p elements at every assembly (residual, Jacobian,
    /// solve) until cleared with nullptr; the caller keeps both alive meanwhile.
    void
    set_element_terms(const ElementTerms *terms, const ElementList *elements)
    {
      element_terms    = terms;
      element_list     = elements;
    }

    void
    set_contact(const ContactParameters &parameters);
    const SelfContact &
    contact() const
    {
      return self_contact;
    }
    /// The self-contact's friction and its history (contact_friction.h).
    const ContactFriction &
    friction() const
    {
      return contact_friction;
    }
    /// The current state is accepted: the self-contact's friction anchors return-map to
    /// it (the integrators call this after every accepted step; a cut-back does not).
    void
    commit_contact();
    /// Replaces the friction history (a checkpoint's, or a test's).
    void
    set_friction_anchors(std::vector<FrictionAnchor> anchors)
    {
      contact_friction.set_anchors(std::move(anchors));
    }

    /// Elastic + contact energy (with the friction's stick or Huber energy at its
    /// anchors) minus the work potential of the nodal forces (J); the
    /// moments have no potential in 3-D and are left out.
    double
    potential_energy();

    /// Kinetic energy from nodal velocities and material angular velocities, J.
    double
    kinetic_energy(const std::vector<Vec3> &velocity, const std::vector<Vec3> &omega) const;

    /// The residual (6 per node, constrained components included) in the current state,
    /// with @p extra terms when given.
    Eigen::VectorXd
    residual(const NodalTerms *extra = nullptr);

    /// residual() split by contribution, with each of @p nodal as a part of its own.
    ResidualParts
    residual_parts(const std::vector<const NodalTerms *> &nodal);

    /// The Jacobian of residual() as a dense matrix (for tests; O(N²) memory).
    Eigen::MatrixXd
    dense_jacobian(const NodalTerms *extra = nullptr);

    /// Newton's method from the current state; on failure the state is left where the
    /// iterations stopped (the caller restores it).
    NewtonResult
    solve(const NewtonParameters &parameters, const NodalTerms *extra = nullptr);

    /// One Newton iteration's work, assembly and linear solve, without updating the
    /// state: returns the correction (for benchmarks).
    Eigen::VectorXd
    newton_direction(const NodalTerms *extra = nullptr);

    /// Assembles the residual and Jacobian in the current state (with @p extra terms)
    /// and factorises the Jacobian; returns the residual (constrained components
    /// included). With solve_linearized() it condenses the rod onto what it is coupled
    /// to (a Schur complement needs several solves with one factorisation).
    const Eigen::VectorXd &
    linearize(const NodalTerms *extra = nullptr);
    /// J⁻¹ b with the Jacobian of the last linearize(); constrained components of the
    /// result are zero.
    Eigen::VectorXd
    solve_linearized(const Eigen::VectorXd &b) const;

    /// Applies the correction @p delta scaled by @p step.
    void
    update(const Eigen::VectorXd &delta, double step = 1);

    /// Element centre states (strains, resultants); a cut element's are zero.
    std::vector<ElementState>
    element_states() const;

    /// Contact force magnitude per node of the last assembly, N.
    const std::vector<double> &
    contact_forces() const
    {
      return contact_force;
    }

  private:
    struct System;
    /// Linear-system work space, kept between Newton iterations so that they do not
    /// allocate; a copied model starts with a fresh one.
    struct Workspace
    {
      Workspace();
      Workspace(const Workspace &);
      Workspace &operator=(const Workspace &);
      ~Workspace();
      std::unique_ptr<System> system;
    };
    /// What assemble() adds (a bit mask; residual_parts() takes them one by one).
    enum Part : unsigned
    {
      elastic_part       = 1,
      self_contact_part  = 2,
      applied_part       = 4,
      element_terms_part = 8,
      nodal_part         = 16,
      all_parts          = 31
    };
    void
    assemble(System &system, const NodalTerms *extra, bool with_jacobian, unsigned parts = all_parts);
    /// The self-contact's residual and Jacobian (the contacts found at the current state).
    void
    add_self_contact(System &system, bool with_jacobian);
    Eigen::VectorXd
    solve_linear(System &system) const;
    /// Factorises the assembled Jacobian of @p system (constrained rows and columns set
    /// to the identity): block LU, or sparse LU when contact couples distant nodes.
    void
    factorize(System &system) const;
    /// The norm of @p r over the free components.
    double
    free_norm(const Eigen::VectorXd &r) const;
    /// The fraction of @p delta NewtonParameters' caps on displacement and turn allow.
    double
    capped_step(const Eigen::VectorXd &delta, const NewtonParameters &parameters) const;
    /// The Newton correction of the assembled @p system, or, when it is longer than the
    /// caps allow, the trust-region step within them (NewtonParameters::trust_region).
    Eigen::VectorXd
    direction(System &system, const NewtonParameters &parameters) const;
    /// Takes @p step of @p delta (halved while an element would turn by π) and
    /// assembles at the new state; false when no halving helps (state unchanged).
    bool
    take_full_step(System &system, const Eigen::VectorXd &delta, double step, const NodalTerms *extra);
    /// The energy line search's step along @p delta, at most @p start, in at most
    /// @p trials secant moves (infinity when every trial fails).
    double
    line_search(const System &system, const Eigen::VectorXd &delta, unsigned trials, double start,
                const NodalTerms *extra);
    /// J⁻¹ @p b with the factorisation of @p system (constrained entries of b ignored).
    Eigen::VectorXd
    substitute(System &system, Eigen::VectorXd b) const;

    std::vector<Vec3>                  pos;
    std::vector<Quat>                  rot;
    std::vector<ElementReference>      reference;
    SectionStiffness                   stiffness;
    std::vector<NodeInertia>           lumped;
    std::vector<std::array<bool, 6>>   fixed;
    std::vector<char>                  cut_element; ///< per element, 1 where cut
    std::vector<Vec3>                  force, moment;
    SelfContact                        self_contact;
    ContactFriction                    contact_friction;
    std::vector<double>                contact_force;
    const ElementTerms                *element_terms = nullptr;
    const ElementList                 *element_list  = nullptr;
    Workspace                          work;
  };
} // namespace suturesim::rod
