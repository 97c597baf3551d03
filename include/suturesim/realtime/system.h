#pragma once
/**
 * @file
 * The particle system every realtime model lives in: tissue nodes and suture nodes in
 * one set of arrays, the interactions between them (springs, home springs, bending,
 * volume, rod curvature), contact sets that change every step, gravity and external
 * loads. Integrators (integrator.h) advance it; the same discrete model can so be run by
 * a force-based integrator (quasi-static, symplectic Euler) or by XPBD, which treats
 * every interaction as a compliant constraint with compliance α = 1/k (Macklin, Müller
 * & Chentanez 2016, "XPBD: position-based simulation of compliant constrained dynamics").
 *
 * Layout (for the cache): per-node quantities are separate arrays (positions,
 * velocities, forces, masses, ...), positions as the columns of a 3 × n matrix so that a
 * node's coordinates share a cache line; interactions store their element data as
 * structures of arrays (springset.h). Nothing here allocates inside a step: work arrays
 * are sized when the system is built.
 */

#include <Eigen/Core>

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace suturesim::realtime
{
  using Eigen::Matrix3Xd;
  using Eigen::Vector3d;
  using Eigen::VectorXd;

  /// A contiguous range of node indices [begin, end).
  struct NodeRange
  {
    std::uint32_t begin = 0, end = 0;
    std::uint32_t
    size() const
    {
      return end - begin;
    }
    bool
    contains(const std::uint32_t i) const
    {
      return i >= begin && i < end;
    }
  };

  /// Per-node state, one array per quantity.
  struct Nodes
  {
    Matrix3Xd x;         ///< positions, m
    Matrix3Xd v;         ///< velocities, m/s
    Matrix3Xd reference; ///< rest positions X, m
    Matrix3Xd previous;  ///< positions at the start of the current step, m
    Matrix3Xd force;     ///< total force of the last evaluation, N
    Matrix3Xd external;  ///< prescribed external loads (tractions), N
    Matrix3Xd target;    ///< positions of held nodes at the end of the step, m
    VectorXd  mass;      ///< lumped mass, kg
    VectorXd  damping;   ///< B of quasi-static integration V = F/B, N s/m
    VectorXd  inverse_mass; ///< 1/m, 0 for held nodes
    /// Why a node's position is prescribed (bit mask of Hold); 0: free.
    std::vector<std::uint8_t> held;

    std::uint32_t
    size() const
    {
      return static_cast<std::uint32_t>(x.cols());
    }

    /// Appends a node at rest at @p X; returns its index.
    std::uint32_t
    add(const Vector3d &X, double mass, double damping);

    /// Reasons for holding a node; a node is held while any is set.
    enum Hold : std::uint8_t
    {
      boundary  = 1, ///< fixed or prescribed boundary, grasped by a tool
      geometric = 2, ///< moved by a geometric model (follow-the-leader suture)
      transient = 4, ///< a collision constraint of seed 002, for one step
      dormant   = 8  ///< a spare node of a model whose topology grows (seed 002's subdivision)
    };

    /// Sets or clears one reason @p why for holding node @p i at target(i); the node's
    /// inverse mass is 0 while any reason holds it.
    void
    set_held(std::uint32_t i, Hold why, bool hold);
  };

  /// A family of elements acting on nodes (all springs of a body, all its volume
  /// constraints, ...), in both forms an integrator may need: a potential energy with its
  /// forces, and the XPBD constraint projection with compliance α = 1/stiffness.
  class Interaction
  {
  public:
    virtual ~Interaction() = default;

    virtual std::string
    name() const = 0;
    virtual std::size_t
    size() const = 0;

    /// Potential energy at @p x, J.
    virtual double
    energy(const Matrix3Xd &x) const = 0;

    /// f += −∂E/∂x at @p x, N.
    virtual void
    add_forces(const Matrix3Xd &x, Matrix3Xd &f) const = 0;

    /// XPBD: zeroes the Lagrange multipliers at the start of a step.
    virtual void
    reset_multipliers() = 0;

    /// XPBD warm start (integrator xpbd, `Warm start = true`): keeps the last step's
    /// multipliers scaled by @p scale = (dt/dt_prev)², so that the forces λ/dt² carry
    /// over; a multiplier of a node now held (@p w = 0), which no sweep would change,
    /// restarts at zero. The integrator moves the nodes to the positions those
    /// multipliers imply, x = x̃ + M⁻¹∇Cᵀλ (XPBD's condition M(x − x̃) = ∇C(x)ᵀλ: Macklin
    /// et al. 2016, §3), as the displacement the tissue's projections made in the last
    /// step, which is M⁻¹ times the sum of their ∇Cᵀ Δλ. The sweeps then start from the
    /// last step's solution instead of the unconstrained prediction: at a static
    /// equilibrium x* the warm start lands on x* with C + α̃λ = 0, so every Δλ vanishes and
    /// one sweep holds the converged state, where a cold start settles where one sweep's λ
    /// balances the load (the warm starting of accumulated impulses in sequential-impulse
    /// solvers: Catto 2005, "Iterative dynamics with temporal coherence", GDC). A family
    /// whose multipliers cannot be kept says so (the default throws).
    virtual void
    warm_multipliers(const VectorXd &, double)
    {
      throw std::invalid_argument(name() + ": its multipliers cannot be kept from step to step "
                                           "(Realtime/xpbd/Warm start)");
    }

    /// XPBD: f += ∇Cᵀλ/dt², the forces the last solve applied (Macklin, Müller &
    /// Chentanez 2016, §4). They equal add_forces() once the solve has converged; with
    /// few iterations of a stiff constraint they are the forces consistent with the
    /// motion, whereas k·C of the unresolved violation may be far larger.
    virtual void
    add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, double dt) const = 0;

    /// The elements (springs, tetrahedra, ...) with a node flagged in @p touched,
    /// ascending, into @p elements: forces on those nodes come from them alone (a
    /// boundary's reaction). False: the family does not list its elements, and callers
    /// evaluate it whole.
    virtual bool
    elements_touching(const std::vector<char> &, std::vector<std::uint32_t> &) const
    {
      return false;
    }
    /// Counts changes of the family's elements or their nodes (seed 002's subdivision
    /// reuses spring slots), so that lists from elements_touching() can be renewed.
    virtual std::size_t
    revision() const
    {
      return 0;
    }
    /// add_forces() of the listed @p elements only, in the same order, so that each node
    /// receives bit for bit the sum add_forces() gives it from them. The default, for
    /// families that list no elements, adds all.
    virtual void
    add_forces_of(const Matrix3Xd &x, Matrix3Xd &f, const std::vector<std::uint32_t> &) const
    {
      add_forces(x, f);
    }
    /// add_constraint_forces() of the listed @p elements only (as add_forces_of()).
    virtual void
    add_constraint_forces_of(const Matrix3Xd &x, Matrix3Xd &f, double dt, const std::vector<std::uint32_t> &) const
    {
      add_constraint_forces(x, f, dt);
    }
    /// Σ over the nodes flagged in @p touched of the forces add_forces_of() gives them
    /// from the listed @p elements, added to @p sum: a boundary's reaction without a
    /// force per node (and without the elements whose contributions to the sum cancel,
    /// those with every node flagged). The same sum to round-off, in another order. False
    /// (the default): the family does not sum; callers use add_forces_of().
    virtual bool
    add_forces_on(const Matrix3Xd &, const std::vector<std::uint32_t> &, const std::vector<char> &, Vector3d &) const
    {
      return false;
    }
    /// add_forces_on() of the constraint forces (add_constraint_forces_of()).
    virtual bool
    add_constraint_forces_on(const Matrix3Xd &, double, const std::vector<std::uint32_t> &, const std::vector<char> &,
                             Vector3d &) const
    {
      return false;
    }

    /// Vertex block descent (integrator "vbd"): the nodes of every element,
    /// @p per_element apiece (2 for springs, 4 for tetrahedra), element by element into
    /// @p nodes. False: the family has no vertex blocks.
    virtual bool
    element_nodes(std::vector<std::uint32_t> &, unsigned &) const
    {
      return false;
    }
    /// Vertex block descent: at @p x, over the @p n elements @p elements (indices into
    /// the family, each with node @p i), f += −∂E/∂x_i and H += a positive
    /// semi-definite ∂²E/∂x_i² (the exact block where it is one).
    virtual void
    add_vertex_block(const Matrix3Xd &, std::uint32_t, const std::uint32_t *, std::size_t, Vector3d &,
                     Eigen::Matrix3d &) const
    {}

    /// Vertex block descent, for a family whose blocks read nodes beyond the vertex's
    /// own elements (averaged nodal volumes, nodal_volumes.h) and so keep what they derive
    /// from the positions: called with @p x before each sweep, and after each node's move
    /// with that node @p i and its @p n elements @p elements, so that add_vertex_block()
    /// sees the current positions. The default keeps nothing.
    virtual void
    begin_sweep(const Matrix3Xd &)
    {}
    virtual void
    vertex_moved(const Matrix3Xd &, std::uint32_t, const std::uint32_t *, std::size_t)
    {}
    /// Vertex block descent on several threads: true when add_vertex_block() for a node
    /// reads its own elements' nodes only and writes nothing of the family's, so nodes
    /// sharing no element (a colour) may move at once. False when a block and its
    /// vertex_moved() reach their elements' nodes' elements: colours then keep two apart.
    virtual bool
    vertex_blocks_local() const
    {
      return true;
    }

    /// False for a family with forces and vertex blocks only (the finite-element
    /// tissue): XPBD, which projects every tissue family, refuses it (World).
    virtual bool
    projectable() const
    {
      return true;
    }

    /// XPBD: constants of the sweeps that depend on the step only (α̃ = 1/(k dt²));
    /// implementations recompute them only when @p dt changes. The inverse masses enter
    /// each projection directly, since holds (tools, transient constraints) change them
    /// from step to step.
    virtual void
    prepare_projection(double)
    {}

    /// XPBD: one Gauss–Seidel sweep over the constraints with α̃ = α/dt² (Macklin et
    /// al. 2016, eqs. 17–18), moving nodes by their inverse masses @p w.
    virtual void
    project(Matrix3Xd &x, const VectorXd &w, double dt) = 0;

    /// XPBD on several threads (a domain decomposition): reorders the constraints into
    /// blocks for @p parts threads, given each node's part @p node_part and its index
    /// @p local within its part (independent_order.h, block_order()). Block p < parts
    /// holds the constraints within part p, swept by thread p on its own copy of the
    /// part's nodes (project_block()); the last block, the interface, sweeps after them
    /// (project_range()). Nodes outside the family may have any part. False: the family
    /// sweeps on one thread only.
    virtual bool
    partition(const std::vector<std::uint32_t> &, const std::vector<std::uint32_t> &, unsigned)
    {
      return false;
    }
    /// Offsets b of the blocks of the last partition(): [b[p], b[p + 1]) for p < parts,
    /// then the interface [b[parts], b[parts + 1]); nullptr when there is none or a
    /// topology change voided it.
    virtual const std::vector<std::size_t> *
    blocks() const
    {
      return nullptr;
    }
    /// project() of block @p p only, on @p x and @p w of part p's nodes in their local
    /// order.
    virtual void
    project_block(unsigned, Matrix3Xd &, const VectorXd &, double)
    {
      throw std::logic_error(name() + ": no blocks to sweep");
    }
    /// project() of the constraints [@p begin, @p end) only.
    virtual void
    project_range(Matrix3Xd &, const VectorXd &, double, std::size_t, std::size_t)
    {
      throw std::logic_error(name() + ": no blocks to sweep");
    }
    /// add_constraint_forces() of block @p p only, on @p x and into @p f of part p's
    /// nodes in their local order (the warm start's refresh on several threads).
    virtual void
    add_constraint_forces_block(unsigned, const Matrix3Xd &, Matrix3Xd &, double) const
    {
      throw std::logic_error(name() + ": no blocks");
    }
    /// add_constraint_forces() of the constraints [@p begin, @p end) only.
    virtual void
    add_constraint_forces_range(const Matrix3Xd &, Matrix3Xd &, double, std::size_t, std::size_t) const
    {
      throw std::logic_error(name() + ": no blocks");
    }
    /// The largest |C| (constraint violation) relative to its natural scale (for
    /// convergence studies): strain for distances, ΔV/V₀ for volumes, ...
    virtual double
    max_violation(const Matrix3Xd &x) const = 0;
  };

  /// Interactions that are found anew every step (contact, self-collision).
  class ContactSet
  {
  public:
    virtual ~ContactSet() = default;

    virtual std::string
    name() const = 0;

    /// Finds the active contacts at @p x.
    virtual void
    detect(const Matrix3Xd &x) = 0;

    /// Penalty or repelling forces of the contacts found by detect(), at @p x.
    virtual void
    add_forces(const Matrix3Xd &x, Matrix3Xd &f) const = 0;

    /// Potential energy of the contacts found by detect(), at @p x (J), with what
    /// detect() fixed (the pairs, normals, closest-point weights) held: add_forces() at
    /// the detected state is −∂E/∂x there. std::nullopt for sets whose forces have no
    /// potential (position corrections, friction in slip, one-sided loads).
    virtual std::optional<double>
    energy(const Matrix3Xd &) const
    {
      return std::nullopt;
    }

    /// True when XPBD should project the contacts as constraints rather than apply
    /// add_forces() as external forces.
    virtual bool
    has_projection() const
    {
      return false;
    }
    /// XPBD: ∇Cᵀλ/dt² of the projected contacts (Interaction::add_constraint_forces);
    /// sets without projection give their forces.
    virtual void
    add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, double) const
    {
      add_forces(x, f);
    }
    virtual void
    reset_multipliers()
    {}
    virtual void
    project(Matrix3Xd &, const VectorXd &, double)
    {}

    /// After the step: position corrections that are not forces (seed 002's transient
    /// collision constraints). May hold nodes for the next step.
    virtual void
    after_step(Nodes &)
    {}

    /// Number of active contacts of the last detect().
    virtual std::size_t
    active() const = 0;
  };

  class System
  {
  public:
    Nodes                                     nodes;
    std::vector<std::unique_ptr<Interaction>> interactions;
    std::vector<std::unique_ptr<ContactSet>>  contacts;
    Vector3d                                  gravity = Vector3d::Zero(); ///< m/s²
    NodeRange                                 tissue, suture;
    /// Index of the suture's first interaction: the tissue's come before it.
    std::size_t                               first_suture_interaction = 0;

    /// Time spent finding contacts (detect_contacts()) since it was last set to zero:
    /// the haptic tick's collision phase (World::step).
    std::chrono::steady_clock::duration detection_time{0};

    /// Sizes the work arrays; call after every node was added.
    void
    finalize();

    /// Which contact sets detect_contacts() updates.
    enum class Contacts
    {
      all,
      by_force, ///< those XPBD applies as external forces (no projection)
      projected ///< those XPBD projects as constraints
    };
    /// ContactSet::detect() of the sets @p which at @p x, timed into detection_time.
    void
    detect_contacts(const Matrix3Xd &x, Contacts which);

    /// Sum of the interactions' forces at @p x into @p f (overwritten), from interaction
    /// @p first on.
    void
    internal_forces(const Matrix3Xd &x, Matrix3Xd &f, std::size_t first = 0) const;

    /// Everything a force-based integrator moves by: internal forces, contacts (detected
    /// at @p x), gravity and external loads, into nodes.force.
    void
    total_forces(const Matrix3Xd &x);

    /// Elastic energy of the interactions at @p x, J.
    double
    elastic_energy(const Matrix3Xd &x) const;

    /// Kinetic energy ½ Σ m v², J (held nodes included).
    double
    kinetic_energy() const;

    /// K u, the stiffness (Hessian of the elastic energy) at @p x applied to @p u, by
    /// central differences of the internal forces (exact for quadratic energies, O(ε²)
    /// otherwise); for eigenvalue estimates.
    void
    stiffness_product(const Matrix3Xd &x, const Matrix3Xd &u, Matrix3Xd &Ku) const;

    /// Characteristic length: the diagonal of the bounding box of the rest positions, m.
    double
    length_scale() const
    {
      return scale;
    }

  private:
    double            scale = 1;
    mutable Matrix3Xd work_a, work_b, work_x;
  };
} // namespace suturesim::realtime
