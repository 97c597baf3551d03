#include <suturesim/realtime/slab_sweep.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace suturesim::realtime
{
  namespace
  {
    unsigned
    at_least_two(const unsigned threads)
    {
      if (threads < 2)
        throw std::invalid_argument("a slab sweep needs at least 2 threads");
      return threads;
    }
  } // namespace

  Eigen::Index
  longest_tissue_axis(const System &s)
  {
    Eigen::Index axis = 0;
    if (s.tissue.size() > 0)
      {
        const auto block = s.nodes.x.middleCols(s.tissue.begin, s.tissue.size());
        (block.rowwise().maxCoeff() - block.rowwise().minCoeff()).maxCoeff(&axis);
      }
    return axis;
  }

  SlabSweep::SlabSweep(const unsigned threads, const double caller_share)
    : team(at_least_two(threads))
    , share(caller_share)
    , slabs(threads)
  {
    if (!(share > 0 && share < 1))
      throw std::invalid_argument("the haptic thread's slab share must lie in (0, 1)");
  }

  void
  SlabSweep::partition(System &s)
  {
    const Matrix3Xd &x = s.nodes.x;
    std::vector<std::uint32_t> tissue(s.tissue.size());
    std::iota(tissue.begin(), tissue.end(), s.tissue.begin);
    const Eigen::Index axis = longest_tissue_axis(s);
    std::stable_sort(tissue.begin(), tissue.end(),
                     [&](const std::uint32_t a, const std::uint32_t b) { return x(axis, a) < x(axis, b); });
    // the caller's slab first (the lowest coordinates), then the helpers' of equal count
    const unsigned             n = threads();
    std::vector<std::uint32_t> part(x.cols(), n);
    for (std::size_t k = 0; k < tissue.size(); ++k)
      {
        const double q = double(k) / double(tissue.size()); // share 1/n: equal slabs
        part[tissue[k]] =
          q < share ? 0u : std::min(n - 1, 1 + static_cast<std::uint32_t>((q - share) / (1 - share) * (n - 1)));
      }
    std::vector<std::uint32_t> local(x.cols(), 0);
    for (auto &slab : slabs)
      slab.nodes.clear();
    for (std::uint32_t i = 0; i < x.cols(); ++i) // ascending
      if (part[i] < n)
        {
          local[i] = static_cast<std::uint32_t>(slabs[part[i]].nodes.size());
          slabs[part[i]].nodes.push_back(i);
        }
    for (auto &slab : slabs)
      {
        slab.x.resize(3, slab.nodes.size());
        slab.w.resize(slab.nodes.size());
        slab.f.resize(3, slab.nodes.size());
      }
    for (std::size_t k = 0; k < s.first_suture_interaction; ++k)
      s.interactions[k]->partition(part, local, n);
  }

  void
  SlabSweep::sweep_slab(System &s, const double dt, const unsigned t)
  {
    Nodes &n    = s.nodes;
    Slab  &slab = slabs[t];
    for (std::size_t k = 0; k < slab.nodes.size(); ++k)
      {
        slab.x.col(k) = n.x.col(slab.nodes[k]);
        slab.w[k]     = n.inverse_mass[slab.nodes[k]];
      }
    for (std::size_t k = 0; k < s.first_suture_interaction; ++k)
      if (s.interactions[k]->blocks() != nullptr)
        s.interactions[k]->project_block(t, slab.x, slab.w, dt);
    for (std::size_t k = 0; k < slab.nodes.size(); ++k)
      n.x.col(slab.nodes[k]) = slab.x.col(k);
  }

  void
  SlabSweep::sweep_interface(System &s, const double dt)
  {
    Nodes &n = s.nodes;
    for (std::size_t k = 0; k < s.first_suture_interaction; ++k)
      {
        Interaction &c = *s.interactions[k];
        if (const auto *b = c.blocks())
          c.project_range(n.x, n.inverse_mass, dt, (*b)[threads()], b->back());
        else
          c.project(n.x, n.inverse_mass, dt);
      }
  }

  void
  SlabSweep::sweep(System &s, const double dt)
  {
    team.run([&](const unsigned t) { sweep_slab(s, dt, t); });
    sweep_interface(s, dt);
  }

  void
  SlabSweep::constraint_forces(System &s, const double dt, Matrix3Xd &f)
  {
    Nodes &n = s.nodes;
    f.setZero(); // the nodes in no slab (the suture's) have nothing from the blocks
    team.run([&](const unsigned t) {
      Slab &slab = slabs[t];
      for (std::size_t k = 0; k < slab.nodes.size(); ++k)
        slab.x.col(k) = n.x.col(slab.nodes[k]);
      slab.f.setZero();
      for (std::size_t k = 0; k < s.first_suture_interaction; ++k)
        if (s.interactions[k]->blocks() != nullptr)
          s.interactions[k]->add_constraint_forces_block(t, slab.x, slab.f, dt);
      for (std::size_t k = 0; k < slab.nodes.size(); ++k)
        f.col(slab.nodes[k]) = slab.f.col(k);
    });
    for (std::size_t k = 0; k < s.first_suture_interaction; ++k)
      {
        const Interaction &c = *s.interactions[k];
        if (const auto *b = c.blocks())
          c.add_constraint_forces_range(n.x, f, dt, (*b)[threads()], b->back());
        else
          c.add_constraint_forces(n.x, f, dt);
      }
  }
} // namespace suturesim::realtime
