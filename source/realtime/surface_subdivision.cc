#include <suturesim/realtime/surface_subdivision.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <stdexcept>

namespace suturesim::realtime
{
  namespace
  {
    /// The neighbour across each edge (a, b) of @p pierced: the triangle of @p triangles
    /// holding the edge the other way round, and that triangle turned so that it reads
    /// (b, a, d).
    void
    find_neighbours(const std::vector<mesh::Triangle> &triangles, const mesh::Triangle &pierced,
                    std::array<std::uint32_t, 3> &neighbour, std::array<mesh::Triangle, 3> &across)
    {
      for (unsigned e = 0; e < 3; ++e)
        {
          const std::uint32_t a = pierced[e], b = pierced[(e + 1) % 3];
          bool                found = false;
          for (std::uint32_t t = 0; t < triangles.size() && !found; ++t)
            for (unsigned k = 0; k < 3 && !found; ++k)
              if (triangles[t][k] == b && triangles[t][(k + 1) % 3] == a)
                {
                  neighbour[e] = t;
                  across[e]    = {b, a, triangles[t][(k + 2) % 3]};
                  found        = true;
                }
          if (!found)
            throw std::logic_error("surface subdivision: an edge of the pierced triangle has no neighbour "
                                   "(the surface is not closed)");
        }
    }
  } // namespace

  SurfaceSubdivision::SurfaceSubdivision(const SubdivisionParameters &parameters, SpringSet &spring_set,
                                         HomeSprings &home_springs, const std::uint32_t first, const SurfaceLumping &l,
                                         const double l_max)
    : prm(parameters)
    , springs(spring_set)
    , home(home_springs)
    , first_spare(first)
    , lumping(l)
    , longest_edge(l_max)
  {
    if (!(prm.rest_length_factor > 0 && prm.rest_length_factor <= 1) || !(longest_edge > 0))
      throw std::invalid_argument("surface subdivision: rest length factor in (0, 1] and l_max > 0");
  }

  double
  SurfaceSubdivision::stiffness(const double l, const double k_mesh) const
  {
    return std::clamp(longest_edge / l * k_mesh, k_mesh, 4 * k_mesh);
  }

  void
  SurfaceSubdivision::relump(Nodes &n, const std::vector<mesh::Triangle> &old_patch,
                             const std::vector<mesh::Triangle> &new_patch, const std::uint32_t P)
  {
    // reference areas of the patch's triangles
    const auto area = [&](const mesh::Triangle &t) {
      const Matrix3Xd &X = n.reference;
      return 0.5 * (X.col(t[1]) - X.col(t[0])).cross(X.col(t[2]) - X.col(t[0])).norm();
    };
    // masses and home springs: the patch's shares of the surface, rescaled so that the
    // patch keeps its totals (the Loop mask moves the edge nodes off the old triangles'
    // planes, which changes the area a little)
    std::vector<std::uint32_t> patch_nodes;
    for (const auto &t : new_patch)
      patch_nodes.insert(patch_nodes.end(), t.begin(), t.end());
    std::sort(patch_nodes.begin(), patch_nodes.end());
    patch_nodes.erase(std::unique(patch_nodes.begin(), patch_nodes.end()), patch_nodes.end());
    std::vector<double> share(patch_nodes.size(), 0.0);
    const auto          slot = [&](const std::uint32_t i) {
      return std::lower_bound(patch_nodes.begin(), patch_nodes.end(), i) - patch_nodes.begin();
    };
    double old_area = 0, new_area = 0;
    for (const auto &t : old_patch)
      {
        const double A = area(t);
        old_area += A;
        for (const auto i : t)
          share[slot(i)] -= A / 3;
      }
    std::vector<double> gained(patch_nodes.size(), 0.0);
    for (const auto &t : new_patch)
      {
        const double A = area(t);
        new_area += A;
        for (const auto i : t)
          gained[slot(i)] += A / 3;
      }
    for (std::size_t k = 0; k < patch_nodes.size(); ++k)
      {
        const std::uint32_t i     = patch_nodes[k];
        const bool          fresh = i >= P && i < P + 4;
        const double        dA    = share[k] + gained[k] * old_area / new_area;
        // an old node's mass and home stiffness change with its share; a new one's are its share
        n.mass[i] = (fresh ? 0.0 : n.mass[i]) + lumping.mass_per_area * dA;
        const std::size_t h = home.find(i);
        if (h < home.size())
          {
            const double k_home = lumping.home_per_area > 0
                                    ? (fresh ? 0.0 : home.stiffness_of(h)) + lumping.home_per_area * dA
                                    : lumping.home_constant;
            home.set(h, n.reference.col(i), k_home);
          }
        // wakes the new nodes, and recomputes 1/m of every node for its new mass
        n.set_held(i, Nodes::dormant, false);
      }
  }

  std::int64_t
  SurfaceSubdivision::subdivide(System &s, std::vector<mesh::Triangle> &triangles, std::vector<int> &tags,
                                const std::uint32_t triangle, const Eigen::Vector3d &weights)
  {
    if (used == prm.capacity)
      return -1;
    Nodes               &n       = s.nodes;
    const mesh::Triangle pierced = triangles[triangle];
    std::array<std::uint32_t, 3>  neighbour{};
    std::array<mesh::Triangle, 3> across{};
    find_neighbours(triangles, pierced, neighbour, across);
    // the patch's old triangles (for the lumping)
    std::vector<mesh::Triangle> old_patch{pierced, across[0], across[1], across[2]};

    // mean stiffness of the pierced triangle's edges: this patch's k_mesh
    double k_mesh = 0;
    std::array<std::size_t, 3> edge_spring{};
    for (unsigned e = 0; e < 3; ++e)
      {
        edge_spring[e] = springs.find(pierced[e], pierced[(e + 1) % 3]);
        if (edge_spring[e] == springs.size())
          throw std::logic_error("surface subdivision: a triangle edge without a spring");
        k_mesh += springs.stiffnesses()[edge_spring[e]] / 3;
      }

    // the new nodes: P, then E_ab, E_bc, E_ca, each a mask of existing nodes applied
    // alike to rest and current positions and to velocities
    const std::uint32_t P     = first_spare + 4 * used;
    const auto          place = [&](const std::uint32_t node, const std::array<std::uint32_t, 4> &from,
                           const std::array<double, 4> &mask) {
      n.reference.col(node).setZero();
      n.x.col(node).setZero();
      n.v.col(node).setZero();
      for (unsigned k = 0; k < 4; ++k)
        {
          n.reference.col(node) += mask[k] * n.reference.col(from[k]);
          n.x.col(node) += mask[k] * n.x.col(from[k]);
          n.v.col(node) += mask[k] * n.v.col(from[k]);
        }
      n.previous.col(node) = n.target.col(node) = n.x.col(node);
      n.external.col(node).setZero();
      n.force.col(node).setZero();
    };
    place(P, {pierced[0], pierced[1], pierced[2], pierced[0]}, {weights[0], weights[1], weights[2], 0});
    std::array<std::uint32_t, 3> E{};
    for (unsigned e = 0; e < 3; ++e)
      {
        E[e] = P + 1 + e;
        place(E[e], {pierced[e], pierced[(e + 1) % 3], P, across[e][2]}, {3. / 8, 3. / 8, 1. / 8, 1. / 8});
      }
    ++used;

    // triangles: the fan about P in place of the pierced one (the first keeps its index,
    // with P first), each neighbour in two
    const int pierced_tag = tags[triangle];
    std::vector<mesh::Triangle> new_patch;
    for (unsigned e = 0; e < 3; ++e)
      {
        new_patch.push_back({P, pierced[e], E[e]});
        new_patch.push_back({P, E[e], pierced[(e + 1) % 3]});
      }
    triangles[triangle] = new_patch[0];
    for (std::size_t k = 1; k < new_patch.size(); ++k)
      {
        triangles.push_back(new_patch[k]);
        tags.push_back(pierced_tag);
      }
    for (unsigned e = 0; e < 3; ++e)
      {
        const auto &[b, a, d] = across[e];
        const mesh::Triangle first{b, E[e], d}, second{E[e], a, d};
        triangles[neighbour[e]] = first;
        triangles.push_back(second);
        tags.push_back(tags[neighbour[e]]);
        new_patch.push_back(first);
        new_patch.push_back(second);
      }

    relump(n, old_patch, new_patch, P);

    // springs by seed 002's eq. (1): the split edges' first halves in their old slots
    const auto add = [&](const std::uint32_t i, const std::uint32_t j, const std::size_t slot_index) {
      const double l = (n.x.col(i) - n.x.col(j)).norm();
      const double k = stiffness(l, k_mesh);
      if (slot_index < springs.size())
        springs.set(slot_index, i, j, prm.rest_length_factor * l, k);
      else
        springs.add(i, j, prm.rest_length_factor * l, k);
    };
    for (unsigned e = 0; e < 3; ++e)
      {
        const std::uint32_t a = pierced[e], b = pierced[(e + 1) % 3];
        add(a, E[e], edge_spring[e]);
        add(E[e], b, springs.size());
        add(E[e], across[e][2], springs.size());
        add(P, a, springs.size());
        add(P, E[e], springs.size());
      }
    return P;
  }
} // namespace suturesim::realtime
