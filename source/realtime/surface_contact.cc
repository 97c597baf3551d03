#include <suturesim/collision/proximity.h>
#include <suturesim/realtime/surface_contact.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>

namespace suturesim::realtime
{
  namespace
  {
    /// The skin above the surface within which a node is in contact, in suture radii:
    /// detection lists a node while its distance is below (1 + skin) r, i.e. g < skin r,
    /// which keeps resting contacts listed from step to step.
    constexpr double skin = 0.25;

    /// The closest feature of a triangle (a face, an edge or a corner) as the corners of
    /// non-zero weight @p weights, sorted, the unused entries last: the same for every
    /// triangle that shares it.
    std::array<std::uint32_t, 3>
    feature(const mesh::Triangle &corners, const Vector3d &weights)
    {
      std::array<std::uint32_t, 3> f;
      f.fill(std::numeric_limits<std::uint32_t>::max());
      for (unsigned c = 0; c < 3; ++c)
        if (weights[c] > 0)
          f[c] = corners[c];
      std::sort(f.begin(), f.end());
      return f;
    }
  } // namespace

  SurfaceContact::SurfaceContact(const System &s, const std::vector<mesh::Triangle> &surface,
                                 const Parameters &parameters, const NodeRange nodes, std::string name)
    : NodeTriangleContacts(parameters.stiffness, parameters.radius, parameters.project)
    , prm(parameters)
    , triangles(surface)
    , suture(nodes)
    , label(std::move(name))
  {
    if (suture.size() < 2)
      throw std::invalid_argument(label + ": a chain of at least two nodes");
    surface_tree.build(s.nodes.x, triangles, prm.depth);
    // the tissue moves micrometres per step: its tree is refitted lazily, a leaf only
    // when a vertex left a slack of one suture radius (TriangleSphereTree::update)
    surface_tree.update(s.nodes.x, prm.radius);
    suture_tree.build(s.nodes.x.middleCols(suture.begin, suture.size()), prm.radius);
    nearest.resize(suture.size());
    slot.assign(suture.size(), -1);
    contacts.reserve(suture.size());
    // Broad-phase pairs: a segment's sphere meets a handful of triangle spheres grown by
    // the detection depth; 64 per node leaves room for dense meshes and folded sutures.
    // Past it the list grows once to a new maximum (never in a steady state).
    candidates.reserve(64 * suture.size());
  }

  void
  SurfaceContact::surface_changed(const Matrix3Xd &x)
  {
    surface_tree.build(x, triangles, prm.depth);
    surface_tree.update(x, prm.radius);
  }

  void
  SurfaceContact::detect(const Matrix3Xd &x)
  {
    surface_tree.update(x, prm.radius);
    suture_tree.refit_all(x.middleCols(suture.begin, suture.size()));
    suture_tree.overlaps(surface_tree, 0, candidates);
    contacts.clear();
    if (prm.every_triangle)
      {
        detect_every_triangle(x);
        return;
      }
    std::fill(slot.begin(), slot.end(), -1);
    std::fill(nearest.begin(), nearest.end(), collision::NearestTriangle{});
    // First the nearest triangle of every candidate node, then the contact test on it
    // alone: a node above a face near an edge is closer to the face than to the side
    // face beyond the edge, whose plane it may well be "behind".
    for (const auto &[segment, leaf] : candidates)
      {
        const std::uint32_t triangle = surface_tree.triangle(leaf);
        const auto         &t        = triangles[triangle];
        // node k is tested from segment k only (the last node from the last segment):
        // segment k's sphere holds node k, so it meets every triangle near the node
        const std::uint32_t last = segment + 2 == suture.size() ? segment + 1 : segment;
        for (std::uint32_t k = segment; k <= last; ++k)
          {
            nearest[k].offer(x.col(suture.begin + k), triangle, x.col(t[0]), x.col(t[1]), x.col(t[2]), prm.radius);
            slot[k] = 0;
          }
      }
    for (std::uint32_t k = 0; k < suture.size(); ++k)
      if (slot[k] >= 0)
        {
          if (exempted != nullptr && (*exempted)[k])
            {
              slot[k] = -1; // drawn into the tissue through pierce points
              continue;
            }
          // listed within the skin beyond touching; its gap constraint acts only while g < 0
          const auto &near = nearest[k];
          if (near.signed_distance < (1 + skin) * prm.radius && near.signed_distance > -prm.depth)
            {
              slot[k] = static_cast<std::int32_t>(contacts.size());
              contacts.push_back({suture.begin + k, triangles[near.triangle], near.weights, near.normal, 0});
            }
          else
            slot[k] = -1;
        }
  }


  void
  SurfaceContact::detect_every_triangle(const Matrix3Xd &x)
  {
    for (const auto &[segment, leaf] : candidates)
      {
        const std::uint32_t triangle = surface_tree.triangle(leaf);
        const auto         &t        = triangles[triangle];
        const std::uint32_t last     = segment + 2 == suture.size() ? segment + 1 : segment;
        for (std::uint32_t k = segment; k <= last; ++k)
          {
            const std::uint32_t  node = suture.begin + k;
            collision::NearestTriangle near;
            near.offer(x.col(node), triangle, x.col(t[0]), x.col(t[1]), x.col(t[2]), prm.radius);
            // outside: the direction from the closest point, which turns continuously
            // over edges and corners; behind the face's plane: its normal
            const bool     outside = near.signed_distance > 0 && near.distance > 0;
            const double   d       = outside ? near.distance : near.signed_distance;
            if (!(d < (1 + skin) * prm.radius && d > -prm.depth))
              continue;
            const Vector3d q = near.weights[0] * x.col(t[0]) + near.weights[1] * x.col(t[1]) +
                               near.weights[2] * x.col(t[2]);
            const Vector3d normal = outside ? Vector3d((x.col(node) - q) / near.distance) : near.normal;
            // one contact per closest feature: faces that share the edge or corner nearest
            // to the node would each push it out again
            const auto key  = feature(t, near.weights);
            const bool seen = std::any_of(contacts.begin(), contacts.end(), [&](const Contact &c) {
              return c.node == node && feature(c.triangle, c.bary) == key;
            });
            if (!seen)
              contacts.push_back({node, t, near.weights, normal, 0});
          }
      }
  }

  void
  SurfaceContact::after_step(Nodes &nodes)
  {
    // geometric suture nodes (FTL) are not moved by forces or projections: put the
    // ones that sank in back on the surface and hold them there for the next step
    bool any = false;
    for (std::uint32_t i = suture.begin; i < suture.end && !any; ++i)
      any = (nodes.held[i] & Nodes::geometric) && !(nodes.held[i] & Nodes::boundary);
    if (!any)
      return;
    detect(nodes.x);
    for (const auto &c : contacts)
      if ((nodes.held[c.node] & Nodes::geometric) && !(nodes.held[c.node] & Nodes::boundary))
        {
          const double g = gap(c, nodes.x);
          if (g >= 0)
            continue;
          nodes.x.col(c.node) -= g * c.normal;
          nodes.target.col(c.node) = nodes.x.col(c.node);
          nodes.set_held(c.node, Nodes::transient, true);
        }
  }

  void
  SurfaceContact::carry_thread(const System &system, const SutureModel &model)
  {
    thread_system = &system;
    thread        = &model;
    link_tension.reserve(suture.size());
  }

  void
  SurfaceContact::add_forces(const Matrix3Xd &x, Matrix3Xd &f) const
  {
    NodeTriangleContacts::add_forces(x, f);
    if (thread == nullptr || contacts.empty())
      return;
    // the links' tensions once a step, and only with a node of the interior to load
    bool tensions = false;
    for (const auto &c : contacts)
      {
        const std::uint32_t i = c.node - suture.begin;
        if (i == 0 || i + 1 >= suture.size() || gap(c, x) > skin * prm.radius)
          continue;
        if (!tensions)
          {
            thread->segment_tension(*thread_system, link_tension);
            tensions = true;
          }
        const Vector3d before = x.col(c.node - 1) - x.col(c.node), after = x.col(c.node + 1) - x.col(c.node);
        const double   lb = before.norm(), la = after.norm();
        if (!(lb > 0 && la > 0))
          continue;
        const double into = (link_tension[i - 1] / lb * before + link_tension[i] / la * after).dot(c.normal);
        if (into >= 0)
          continue; // the thread pulls away from the surface: nothing holds it
        for (unsigned k = 0; k < 3; ++k)
          f.col(c.triangle[k]) += c.bary[k] * into * c.normal;
      }
  }
} // namespace suturesim::realtime
