#pragma once
/**
 * @file
 * Suture–tissue-surface contact (seed 000 §VII.B, Fig. 8: "collision detection between
 * the model and the thread"), and the same for a tool's chain of nodes: seed 004's
 * external stage, node–triangle non-penetration C = (q − p₁)·n − ε ≥ 0 with ε the
 * chain's radius and p₁ the closest point of the triangle. Broad phase: the suture's chain sphere tree against the
 * tissue surface's triangle sphere tree (collision/), both refitted bottom-up every
 * detection. Narrow phase: each suture node against the candidate triangles; a node
 * touches a triangle when its signed distance d = (p − c)·n to the closest point c
 * (outward normal n) lies in (−depth, 1.25 r): it is then within a suture radius r (and
 * a skin of r/4, which keeps resting contacts listed from step to step) of the surface
 * or at most the detection depth inside it. The test is made on the node's
 * nearest triangle only (ties at shared edges go to the triangle whose normal points
 * most nearly at the node), so a node resting on a face next to an edge is not taken to
 * be behind the side face beyond the edge.
 *
 * Response, gap g = (p − Σ bₖ xₖ)·n − r < 0 with the closest point's barycentric
 * weights b and the normal frozen at detection: node_triangle_contacts.h's penalty or
 * XPBD inequality, and nodes a geometric model positions (FTL) pushed out to g = 0 after
 * the step and held there for the next step (a collision constraint of seed 002).
 *
 * A geometric thread is not moved by forces, so its penalty reaction is only that of
 * the depth a node happens to have when the forces are taken: the surface that holds the
 * thread up would not carry the thread's pull. With carry_thread() (Realtime/Contact
 * load) each listed node i of the thread's interior within the skin (g ≤ r/4) passes its
 * links' pull into the surface to it, the reaction of a frictionless support:
 *   p = T₋ (x_{i−1} − x_i)/|…| + T₊ (x_{i+1} − x_i)/|…|,  f = min(p·n, 0) n,
 * on the triangle's corners by the weights b (T± the links' tensions from the suture
 * model). Over a turn of angle θ under tension T the nodes that share it carry 2T sin(θ/2)
 * between them, however many they are (the sum telescopes), so the load on a given turn
 * does not depend on the link's length.
 */

#include <suturesim/collision/proximity.h>
#include <suturesim/collision/sphere_tree.h>
#include <suturesim/collision/triangle_sphere_tree.h>
#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/realtime/node_triangle_contacts.h>
#include <suturesim/realtime/suture_model.h>

#include <string>
#include <vector>

namespace suturesim::realtime
{
  class SurfaceContact : public NodeTriangleContacts
  {
  public:
    struct Parameters
    {
      double stiffness = 0; ///< k, N/m
      double radius    = 0; ///< r of the suture, m
      double depth     = 0; ///< how far inside a node is still pushed out, m
      bool   project   = false; ///< XPBD constraints instead of penalty forces
      /// Each node against every triangle within reach, not only its nearest (a tool's
      /// sphere pressing a dimple touches several faces at once; one contact on the
      /// nearest would flip from face to face), one contact per closest feature (face,
      /// edge or corner), its normal the direction from the closest point while the
      /// node is outside the face's plane (continuous over edges and corners).
      bool   every_triangle = false;
    };

    /// Contact of the chain of nodes @p nodes (the suture's, or a tool's: realtime/
    /// world.h's probe) with @p surface, named @p name.
    SurfaceContact(const System &system, const std::vector<mesh::Triangle> &surface,
                   const Parameters &parameters, NodeRange nodes, std::string name);

    std::string
    name() const override
    {
      return label;
    }
    void
    detect(const Matrix3Xd &x) override;
    void
    after_step(Nodes &nodes) override;
    /// The penalty (node_triangle_contacts.h), and with carry_thread() the thread's pull
    /// into the surface at its resting nodes (above).
    void
    add_forces(const Matrix3Xd &x, Matrix3Xd &f) const override;
    /// The chain is the geometric thread of @p model in @p system: its pull into the
    /// surface loads the tissue (above). Force-based integrators: XPBD's projection does
    /// not use add_forces() (World refuses the pair).
    void
    carry_thread(const System &system, const SutureModel &model);
    /// The surface's triangles changed (seed 002's subdivision): the tree on them is built
    /// again at @p x.
    void
    surface_changed(const Matrix3Xd &x);

    /// Suture nodes (local index, non-zero entries) to leave alone: those the needle's
    /// pierce points have drawn into the tissue. The mask is read at every detect().
    void
    exempt(const std::vector<char> *mask)
    {
      exempted = mask;
    }

  private:
    /// detect() of Parameters::every_triangle, from the broad phase's candidates.
    void
    detect_every_triangle(const Matrix3Xd &x);

    Parameters                      prm;
    const std::vector<mesh::Triangle> &triangles;
    NodeRange                       suture; ///< the chain's nodes (the suture's, or a tool's)
    std::string                     label;
    collision::TriangleSphereTree   surface_tree;
    collision::SphereTree           suture_tree;
    collision::LeafPairs            candidates;
    std::vector<collision::NearestTriangle> nearest; ///< per suture node
    std::vector<std::int32_t>       slot; ///< per suture node: index in contacts, −1
    const std::vector<char>        *exempted = nullptr;
    const System                   *thread_system = nullptr; ///< with carry_thread()
    const SutureModel              *thread        = nullptr;
    mutable std::vector<double>     link_tension; ///< per link, N (work array)
  };
} // namespace suturesim::realtime
