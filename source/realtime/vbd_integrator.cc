/**
 * Vertex block descent on the tissue (Chen, Macklin, Yuksel & Kim 2024, "Vertex Block
 * Descent", ACM Trans. Graph. 43(4):116), XPBD on the suture and contacts (xpbd_integrator.cc).
 *
 * The tissue's step minimises the implicit-Euler energy
 *   G(x) = 1/(2 dt²) Σᵢ mᵢ |xᵢ − yᵢ|² + E(x),  y = x_prev + dt v + dt² (g + f_ext/m),
 * by Gauss–Seidel over its nodes, one colour of independent nodes after another: each
 * node takes the Newton step of G in its own three coordinates,
 *   xᵢ ← xᵢ + Hᵢ⁻¹ fᵢ,  fᵢ = −(mᵢ/dt²)(xᵢ − yᵢ) − ∂E/∂xᵢ,  Hᵢ = (mᵢ/dt²) I + ∂²E/∂xᵢ²,
 * with the elements' blocks from Interaction::add_vertex_block (positive semi-definite,
 * so Hᵢ is positive definite). The iteration starts from x_prev + dt v, the inertial
 * guess without this step's accelerations: at a static equilibrium (v = 0, ∇E = M g)
 * that is the minimiser of G itself, so equilibrium is a fixed point for any number of
 * iterations. XPBD's iterations start from y and reset their multipliers each step, and
 * a few of them leave a static sag far off the converged one (docs/realtime.md).
 *
 * Each iteration: a sweep over the tissue's colours, then one XPBD sweep over the
 * suture's constraints and the projected contacts; then "Suture iterations" sweeps over
 * those alone (as xpbd). The tissue's interactions (those before
 * System::first_suture_interaction) must have vertex blocks: springs, volume
 * constraints, home springs; others are refused.
 *
 * Threads (`Threads` ≥ 2): the nodes of one colour share no element, so with families
 * whose blocks read their own elements' nodes only (Interaction::vertex_blocks_local)
 * they move at once, each thread taking a contiguous share of the colour (its nodes
 * sorted along the tissue's longest extent, so a slab of the mesh), and the colours
 * follow one another. Each node's block and move are the same arithmetic as on one
 * thread, in any interleaving, so the sweep is one thread's bit for bit. A family whose
 * blocks read and write the nodes of its elements' nodes (averaged nodal volumes) makes
 * the colouring keep a colour's nodes two elements apart, on one thread as on several
 * (more, smaller colours: 29 against 8 on the 16 × 16 × 4 test block), so that it too
 * sweeps the same bit for bit on any number. A colour too small to pay for the
 * hand-over (about 1 µs, worker_team.h) runs on the haptic thread alone.
 */
#include <suturesim/core/model_parameters.h>
#include <suturesim/core/worker_team.h>
#include <suturesim/realtime/integrator.h>
#include <suturesim/realtime/slab_sweep.h>

#include <Eigen/Cholesky>

#include <algorithm>
#include <memory>

namespace suturesim::realtime
{
  namespace
  {
    /// Counting sort: the items 0…n−1 grouped by key(item) < n_groups (a negative key
    /// leaves the item out), each group in item order, into @p items with the groups'
    /// @p offsets (n_groups + 1).
    template <typename Key>
    void
    group(const std::size_t n, const std::size_t n_groups, const Key &key, std::vector<std::uint32_t> &offsets,
          std::vector<std::uint32_t> &items)
    {
      offsets.assign(n_groups + 1, 0);
      for (std::size_t j = 0; j < n; ++j)
        if (key(j) >= 0)
          ++offsets[key(j) + 1];
      for (std::size_t g = 0; g < n_groups; ++g)
        offsets[g + 1] += offsets[g];
      items.resize(offsets.back());
      std::vector<std::uint32_t> fill(offsets.begin(), offsets.end() - 1);
      for (std::size_t j = 0; j < n; ++j)
        if (key(j) >= 0)
          items[fill[key(j)]++] = static_cast<std::uint32_t>(j);
    }

    /// Per interaction: for each node, the elements at it (compressed rows).
    struct Adjacency
    {
      std::vector<std::uint32_t> offsets, elements;
      std::size_t                revision = 0;
    };

    class Vbd : public Integrator
    {
    public:
      Vbd(const ParameterValues &p)
        : n_iterations(p.integer("Iterations"))
        , damping(p.real("Damping rate"))
        , suture_iterations(p.integer("Suture iterations"))
        , team(p.integer("Threads") > 1 ? std::make_unique<WorkerTeam>(p.integer("Threads")) : nullptr)
      {}

      void
      setup(System &s) override
      {
        tissue_end = s.first_suture_interaction;
        reach      = 1;
        for (std::size_t k = 0; k < tissue_end; ++k)
          if (!s.interactions[k]->vertex_blocks_local())
            reach = 2;
        adjacency.assign(tissue_end, Adjacency());
        build(s);
        y.resize(3, s.nodes.size());
      }

      void
      step(System &s, const double dt) override
      {
        Nodes &n = s.nodes;
        for (std::size_t k = 0; k < tissue_end; ++k)
          if (s.interactions[k]->revision() != adjacency[k].revision)
            build(s); // seed 002's subdivision changed the springs (allocates, rarely)
        n.previous = n.x;
        external_forces(s);
        for (Eigen::Index i = 0; i < n.x.cols(); ++i)
          if (n.held[i])
            n.x.col(i) = n.target.col(i);
          else
            {
              const Vector3d v0 = n.v.col(i);
              n.v.col(i) += dt * (s.gravity + n.force.col(i) / n.mass[i]);
              y.col(i)   = n.previous.col(i) + dt * n.v.col(i);
              // tissue nodes start from the inertial guess, the rest (XPBD) from y
              n.x.col(i) = coloured(i) ? Vector3d(n.previous.col(i) + dt * v0) : Vector3d(y.col(i));
            }

        s.detect_contacts(n.x, System::Contacts::projected);
        for (const auto &c : s.contacts)
          if (c->has_projection())
            c->reset_multipliers();
        for (std::size_t k = tissue_end; k < s.interactions.size(); ++k)
          {
            s.interactions[k]->reset_multipliers();
            s.interactions[k]->prepare_projection(dt);
          }
        for (unsigned it = 0; it < n_iterations; ++it)
          {
            descend(s, dt);
            project_constraints(s, dt, tissue_end);
          }
        for (unsigned it = 0; it < suture_iterations; ++it)
          project_constraints(s, dt, tissue_end);
        update_velocities(n, dt, damping);
      }

      bool
      position_based() const override
      {
        return true;
      }

      bool
      projects_tissue() const override
      {
        return false;
      }

      std::size_t
      first_constraint_interaction(const System &) const override
      {
        return tissue_end;
      }

      unsigned
      iterations() const override
      {
        return n_iterations;
      }

      std::string
      settings() const override
      {
        const std::size_t colours = colour_offsets.empty() ? 0 : colour_offsets.size() - 1;
        std::size_t       shared  = 0; // colours large enough to be cut between the threads
        for (std::size_t c = 0; c < colours; ++c)
          shared += colour_offsets[c + 1] - colour_offsets[c] >= min_shared_colour;
        return sweep_settings(n_iterations, suture_iterations) + ", " + std::to_string(colours) + " colours" +
               (team ? ", " + std::to_string(team->size()) + " threads on " + std::to_string(shared) + " of them" : "");
      }

    private:
      bool
      coloured(const Eigen::Index i) const
      {
        return std::size_t(i) < in_colour.size() && in_colour[i];
      }

      /// One Gauss–Seidel sweep of vertex block descent over the tissue's colours.
      void
      descend(System &s, const double dt)
      {
        const double idt = 1 / (dt * dt);
        for (std::size_t e = 0; e < tissue_end; ++e)
          s.interactions[e]->begin_sweep(s.nodes.x);
        for (std::size_t c = 0; c + 1 < colour_offsets.size(); ++c)
          {
            const std::size_t begin = colour_offsets[c], end = colour_offsets[c + 1];
            if (!team || end - begin < min_shared_colour)
              {
                for (std::size_t k = begin; k < end; ++k)
                  move(s, order[k], idt);
                continue;
              }
            const std::size_t parts = team->size();
            team->run([&](const unsigned t) {
              const std::size_t first = begin + (end - begin) * t / parts, last = begin + (end - begin) * (t + 1) / parts;
              for (std::size_t k = first; k < last; ++k)
                move(s, order[k], idt);
            });
          }
      }

      /// Node @p i's Newton step on G in its own coordinates (@p idt = 1/dt²).
      void
      move(System &s, const std::uint32_t i, const double idt) const
      {
        Nodes &n = s.nodes;
        if (n.inverse_mass[i] == 0) // held
          return;
        const double    m = n.mass[i] * idt;
        Vector3d        f = -m * (n.x.col(i) - y.col(i));
        Eigen::Matrix3d H = m * Eigen::Matrix3d::Identity();
        for (std::size_t e = 0; e < tissue_end; ++e)
          {
            const auto &a = adjacency[e];
            s.interactions[e]->add_vertex_block(n.x, i, a.elements.data() + a.offsets[i],
                                                a.offsets[i + 1] - a.offsets[i], f, H);
          }
        n.x.col(i) += H.llt().solve(f);
        for (std::size_t e = 0; e < tissue_end; ++e)
          {
            const auto &a = adjacency[e];
            s.interactions[e]->vertex_moved(n.x, i, a.elements.data() + a.offsets[i], a.offsets[i + 1] - a.offsets[i]);
          }
      }

      /// The node-to-element lists of the tissue's interactions and a greedy colouring
      /// of their nodes: no two nodes of one element share a colour (nor, where a
      /// family's blocks reach beyond their elements, two neighbours of one node:
      /// nodal_volumes.h), so the nodes of a colour can move in any order, or at once.
      void
      build(const System &s)
      {
        const std::size_t                       n_nodes = s.nodes.size();
        std::vector<std::vector<std::uint32_t>> nodes_of(tissue_end);
        std::vector<unsigned>                   per(tissue_end);
        in_colour.assign(n_nodes, 0);
        for (std::size_t k = 0; k < tissue_end; ++k)
          {
            const Interaction &i = *s.interactions[k];
            if (!i.element_nodes(nodes_of[k], per[k]))
              throw ParameterError("Integrator", "'vbd' needs vertex blocks for every tissue interaction, and '" +
                                                   i.name() + "' has none; use 'xpbd'");
            // the element-node incidences grouped by node, each as its element
            auto &a    = adjacency[k];
            a.revision = i.revision();
            group(
              nodes_of[k].size(), n_nodes, [&](const std::size_t j) { return std::int64_t(nodes_of[k][j]); },
              a.offsets, a.elements);
            for (auto &e : a.elements)
              {
                in_colour[nodes_of[k][e]] = 1;
                e /= per[k];
              }
          }
        // greedy colouring in node order: the smallest colour no neighbour has (with
        // reach 2, no neighbour's neighbour either)
        std::vector<std::int64_t> colour(n_nodes, -1);
        std::vector<char>         taken;
        std::int64_t              n_colours = 0;
        const auto                neighbours = [&](const std::uint32_t v, const auto &visit) {
          for (std::size_t k = 0; k < tissue_end; ++k)
            for (auto e = adjacency[k].offsets[v]; e < adjacency[k].offsets[v + 1]; ++e)
              for (unsigned j = 0; j < per[k]; ++j)
                visit(nodes_of[k][per[k] * adjacency[k].elements[e] + j]);
        };
        for (std::uint32_t v = 0; v < n_nodes; ++v)
          {
            if (!in_colour[v])
              continue;
            taken.assign(n_colours + 1, 0);
            const auto take = [&](const std::uint32_t u) {
              if (colour[u] >= 0)
                taken[colour[u]] = 1;
            };
            neighbours(v, [&](const std::uint32_t u) { reach == 1 ? take(u) : neighbours(u, take); });
            colour[v] = std::find(taken.begin(), taken.end(), 0) - taken.begin();
            n_colours = std::max(n_colours, colour[v] + 1);
          }
        group(
          n_nodes, std::size_t(n_colours), [&](const std::size_t v) { return colour[v]; }, colour_offsets, order);
        // with threads, each colour along the tissue's longest extent, so that the
        // threads' contiguous shares are slabs of the mesh, which meet at a plane only
        // (the mesh's numbering need not be spatial): the positions a thread reads are
        // mostly its own writes. (The order within a colour does not change the sweep,
        // whose blocks there are independent; one thread keeps node order.)
        if (!team)
          return;
        const Matrix3Xd   &x    = s.nodes.x;
        const Eigen::Index axis = longest_tissue_axis(s);
        for (std::size_t c = 0; c + 1 < colour_offsets.size(); ++c)
          std::stable_sort(order.begin() + colour_offsets[c], order.begin() + colour_offsets[c + 1],
                           [&](const std::uint32_t a, const std::uint32_t b) { return x(axis, a) < x(axis, b); });
      }

      unsigned                   n_iterations;
      double                     damping;
      unsigned                   suture_iterations;
      std::size_t                tissue_end = 0;
      std::vector<Adjacency>     adjacency;
      std::vector<char>          in_colour;      ///< per node: a tissue node, moved by the descent
      std::vector<std::uint32_t> order;          ///< tissue nodes by colour
      std::vector<std::uint32_t> colour_offsets; ///< of each colour in order
      Matrix3Xd                  y;              ///< inertial targets x_prev + dt v
      std::unique_ptr<WorkerTeam> team;          ///< Threads > 1
      /// How far apart the nodes of a colour are: 1, no shared element; 2, with a family
      /// whose blocks reach beyond their elements, no shared neighbour either
      unsigned reach = 1;
      /// Nodes a colour needs to be shared between the threads: a node's block and move
      /// take about 0.5 µs (the benchmark's fe sweep, about 1 ms over 1 905 nodes), a
      /// hand-over about 1 µs, so 8 nodes a thread save a few µs.
      static constexpr std::size_t min_shared_colour = 16;
    };

    const bool registered = Integrator::Registry::instance().add(
      {"vbd",
       "vertex block descent on the tissue (Chen et al. 2024: Gauss-Seidel over node colours, a 3x3 Newton step "
       "per node on the implicit-Euler energy; static equilibrium is a fixed point at any iteration count), XPBD "
       "on the suture and contacts; unconditionally stable.",
       [](ParameterDeclarations &d) {
         d.add_integer("Iterations", 1, 1, 1000,
                       "Sweeps per step over the tissue's node colours, each followed by one over the suture's "
                       "constraints and the contacts. Unit: 1. Range: 1-1000.");
         d.add_integer("Suture iterations", 8, 0, 1000,
                       "Extra XPBD sweeps per step over the suture's constraints and the contacts only. Unit: 1. "
                       "Range: 0-1000.");
         d.add_real("Damping rate", 0, 0, 1e9,
                    "Velocity damping v <- (1 - c dt) v after each step. Unit: 1/s. Range: >= 0.");
         d.add_integer("Threads", 1, 1, 64,
                       "Threads of the tissue's sweep: 2 or more move each colour's nodes (which share no "
                       "element) at once, the helpers spinning between colours; the result is one thread's bit "
                       "for bit (with fe/Volumetric energy = nodal, whose blocks reach beyond their elements, "
                       "the colours keep nodes two elements apart on any number of threads). Unit: 1. "
                       "Range: 1-64.");
       },
       [](const ParameterValues &p) { return std::unique_ptr<Integrator>(new Vbd(p)); }});
  } // namespace
} // namespace suturesim::realtime
