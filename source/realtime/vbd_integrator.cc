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
 */
#include <suturesim/core/model_parameters.h>
#include <suturesim/realtime/integrator.h>

#include <Eigen/Cholesky>

#include <algorithm>

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
      {}

      void
      setup(System &s) override
      {
        tissue_end = s.first_suture_interaction;
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
        return sweep_settings(n_iterations, suture_iterations) + ", " +
               std::to_string(colour_offsets.empty() ? 0 : colour_offsets.size() - 1) + " colours";
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
        Nodes       &n   = s.nodes;
        const double idt = 1 / (dt * dt);
        for (std::size_t e = 0; e < tissue_end; ++e)
          s.interactions[e]->begin_sweep(n.x);
        for (std::size_t c = 0; c + 1 < colour_offsets.size(); ++c)
          for (std::size_t k = colour_offsets[c]; k < colour_offsets[c + 1]; ++k)
            {
              const std::uint32_t i = order[k];
              if (n.inverse_mass[i] == 0) // held
                continue;
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
                  s.interactions[e]->vertex_moved(n.x, i, a.elements.data() + a.offsets[i],
                                                  a.offsets[i + 1] - a.offsets[i]);
                }
            }
      }

      /// The node-to-element lists of the tissue's interactions and a greedy colouring
      /// of their nodes: no two nodes of one element share a colour, so the nodes of a
      /// colour can move in any order within a sweep (or at once, unless a family's blocks
      /// read nodes beyond their elements: nodal_volumes.h).
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
        // greedy colouring in node order: the smallest colour no neighbour has
        std::vector<std::int64_t> colour(n_nodes, -1);
        std::vector<char>         taken;
        std::int64_t              n_colours = 0;
        for (std::uint32_t v = 0; v < n_nodes; ++v)
          {
            if (!in_colour[v])
              continue;
            taken.assign(n_colours + 1, 0);
            for (std::size_t k = 0; k < tissue_end; ++k)
              for (auto e = adjacency[k].offsets[v]; e < adjacency[k].offsets[v + 1]; ++e)
                for (unsigned j = 0; j < per[k]; ++j)
                  if (const auto c = colour[nodes_of[k][per[k] * adjacency[k].elements[e] + j]]; c >= 0)
                    taken[c] = 1;
            colour[v] = std::find(taken.begin(), taken.end(), 0) - taken.begin();
            n_colours = std::max(n_colours, colour[v] + 1);
          }
        group(
          n_nodes, std::size_t(n_colours), [&](const std::size_t v) { return colour[v]; }, colour_offsets, order);
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
       },
       [](const ParameterValues &p) { return std::unique_ptr<Integrator>(new Vbd(p)); }});
  } // namespace
} // namespace suturesim::realtime
