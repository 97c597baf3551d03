#include <suturesim/collision/sphere_hierarchy.h>

#include <algorithm>
#include <stdexcept>

namespace suturesim::collision
{
  bool
  Sphere::contains(const Sphere &other) const
  {
    return (other.centre - centre).norm() + other.radius <= radius * (1 + 1e-12) + 1e-15;
  }

  Sphere
  enclosing_sphere(const Sphere &a, const Sphere &b)
  {
    const Eigen::Vector3d ab = b.centre - a.centre;
    const double          d  = ab.norm();
    if (d + b.radius <= a.radius)
      return a;
    if (d + a.radius <= b.radius)
      return b;
    // the diameter runs from the far side of a to the far side of b
    const double radius = 0.5 * (d + a.radius + b.radius);
    return {a.centre + ab * ((radius - a.radius) / d), radius};
  }

  void
  SphereHierarchy::build_from_leaves(const std::vector<Sphere> &leaf_spheres)
  {
    if (leaf_spheres.empty())
      throw std::invalid_argument("SphereHierarchy: no leaves");
    leaves = leaf_spheres.size();
    nodes  = leaf_spheres;
    children.assign(leaves, {-1, -1});
    parent.assign(leaves, -1);
    // pair successive nodes of one level into the next (seed 000, Fig. 1); an odd node
    // out gets a parent of its own so every level halves and the tree stays balanced
    std::size_t first = 0, count = leaves;
    while (count > 1)
      {
        const std::size_t next_first = nodes.size();
        for (std::size_t k = 0; k < count; k += 2)
          {
            const int a = static_cast<int>(first + k);
            const int b = k + 1 < count ? static_cast<int>(first + k + 1) : -1;
            const int p = static_cast<int>(nodes.size());
            nodes.push_back(b >= 0 ? enclosing_sphere(nodes[a], nodes[b]) : nodes[a]);
            children.emplace_back(a, b);
            parent.push_back(-1);
            parent[a] = p;
            if (b >= 0)
              parent[b] = p;
          }
        first = next_first;
        count = nodes.size() - next_first;
      }
    dirty.assign(nodes.size(), 0);
  }

  bool
  SphereHierarchy::set_leaf(const std::size_t leaf, const Sphere &sphere)
  {
    nodes[leaf] = sphere;
    if (dirty[leaf])
      return false;
    dirty[leaf] = 1;
    for (int p = parent[leaf]; p >= 0 && !dirty[p]; p = parent[p])
      dirty[p] = 1;
    return true;
  }

  void
  SphereHierarchy::update_node(const std::size_t node)
  {
    const auto [a, b] = children[node];
    nodes[node]       = b >= 0 ? enclosing_sphere(nodes[a], nodes[b]) : nodes[a];
  }

  std::size_t
  SphereHierarchy::refit_marked()
  {
    // Algorithm 1 of seed 000: every marked node once, children before parents. Parents
    // are stored after their children, so the index order is that order (the seed's
    // priority queue measured 2x slower when every point moves).
    std::size_t updated = 0;
    for (std::size_t node = leaves; node < nodes.size(); ++node)
      if (dirty[node])
        {
          update_node(node);
          ++updated;
        }
    std::fill(dirty.begin(), dirty.end(), 0);
    return updated;
  }

  void
  SphereHierarchy::refit_all_inner()
  {
    for (std::size_t node = leaves; node < nodes.size(); ++node)
      update_node(node);
    std::fill(dirty.begin(), dirty.end(), 0);
  }

  void
  SphereHierarchy::descend_self(const int a, const int b, const double margin,
                                LeafPairs &pairs) const
  {
    const bool a_leaf = static_cast<std::size_t>(a) < leaves;
    const bool b_leaf = static_cast<std::size_t>(b) < leaves;
    if (a == b)
      {
        if (a_leaf)
          return;
        const auto [l, r] = children[a];
        descend_self(l, l, margin, pairs);
        if (r >= 0)
          {
            descend_self(r, r, margin, pairs);
            descend_self(l, r, margin, pairs);
          }
        return;
      }
    const Sphere &sa = nodes[a], &sb = nodes[b];
    const double  reach = sa.radius + sb.radius + margin;
    if ((sa.centre - sb.centre).squaredNorm() > reach * reach)
      return;
    if (a_leaf && b_leaf)
      {
        pairs.emplace_back(std::min(a, b), std::max(a, b));
        return;
      }
    // split the larger inner sphere
    const bool split_a = !a_leaf && (b_leaf || sa.radius >= sb.radius);
    const int  node = split_a ? a : b, other = split_a ? b : a;
    const auto [l, r] = children[node];
    descend_self(l, other, margin, pairs);
    if (r >= 0)
      descend_self(r, other, margin, pairs);
  }

  void
  SphereHierarchy::descend_other(const SphereHierarchy &other, const int a, const int b,
                                 const double margin, LeafPairs &pairs) const
  {
    const Sphere &sa = nodes[a], &sb = other.nodes[b];
    const double  reach = sa.radius + sb.radius + margin;
    if ((sa.centre - sb.centre).squaredNorm() > reach * reach)
      return;
    const bool a_leaf = static_cast<std::size_t>(a) < leaves;
    const bool b_leaf = static_cast<std::size_t>(b) < other.leaves;
    if (a_leaf && b_leaf)
      {
        pairs.emplace_back(a, b);
        return;
      }
    if (!a_leaf && (b_leaf || sa.radius >= sb.radius))
      {
        const auto [l, r] = children[a];
        descend_other(other, l, b, margin, pairs);
        if (r >= 0)
          descend_other(other, r, b, margin, pairs);
      }
    else
      {
        const auto [l, r] = other.children[b];
        descend_other(other, a, l, margin, pairs);
        if (r >= 0)
          descend_other(other, a, r, margin, pairs);
      }
  }

  void
  SphereHierarchy::leaves_near(const Eigen::Vector3d &centre, const double radius,
                               std::vector<std::uint32_t> &found) const
  {
    found.clear();
    if (nodes.empty())
      return;
    // depth-first without recursion: a balanced tree of n leaves is log₂ n deep
    int stack[64];
    int top      = 0;
    stack[top++] = static_cast<int>(root());
    while (top > 0)
      {
        const int     node  = stack[--top];
        const double  reach = nodes[node].radius + radius;
        if ((nodes[node].centre - centre).squaredNorm() > reach * reach)
          continue;
        if (static_cast<std::size_t>(node) < leaves)
          found.push_back(static_cast<std::uint32_t>(node));
        else
          for (const int c : {children[node].first, children[node].second})
            if (c >= 0)
              stack[top++] = c;
      }
  }

  void
  SphereHierarchy::self_overlaps(const double margin, LeafPairs &pairs) const
  {
    pairs.clear();
    if (!nodes.empty())
      descend_self(static_cast<int>(root()), static_cast<int>(root()), margin, pairs);
  }

  void
  SphereHierarchy::overlaps(const SphereHierarchy &other, const double margin,
                            LeafPairs &pairs) const
  {
    pairs.clear();
    if (!nodes.empty() && !other.nodes.empty())
      descend_other(other, static_cast<int>(root()), static_cast<int>(other.root()), margin,
                    pairs);
  }
} // namespace suturesim::collision
