#pragma once
/**
 * @file
 * The incision's faces kept from passing through each other in the realtime path, as
 * the accurate path's `Closure/Face contact` keeps them (coupling/accurate/
 * wound_contact.h): each node of face A is paired, in the reference configuration, with
 * the closest point of face B (its triangle and weights b), and pushed out of lip B
 * along that triangle's outward normal n (taken at each detection and held through the
 * step) while the gap g = (p − Σ bₖ xₖ)·n is negative: node_triangle_contacts.h's penalty
 * f = −k g n, or the XPBD inequality g ≥ 0 with compliance 1/k. A pair is listed while
 * its gap is below a margin, so that XPBD's sweeps within a step see a pair that closes
 * during them. Without it the realtime lips cross where the thread pulls them together
 * (docs/interrupted_stitch.md, "The load stopped at the wound in the realtime path").
 */

#include <suturesim/realtime/node_triangle_contacts.h>

#include <string>
#include <vector>

namespace suturesim::realtime
{
  class WoundFaceContact : public NodeTriangleContacts
  {
  public:
    /// Pairs the nodes @p face_a (system indices) with the triangles @p face_b (system
    /// indices, outward from lip B) at the rest positions of @p system; a node that is a
    /// corner of face B (where the faces meet) is left out. Penalty @p stiffness (N/m,
    /// > 0), listing @p margin (m, ≥ 0), XPBD projection when @p project.
    /// std::invalid_argument for an empty face or a stiffness that is not positive.
    WoundFaceContact(const System &system, const std::vector<std::uint32_t> &face_a,
                     const std::vector<mesh::Triangle> &face_b, double stiffness, double margin, bool project);

    std::string
    name() const override
    {
      return "wound face contact";
    }
    void
    detect(const Matrix3Xd &x) override;
    /// Adds to @p per_node (one entry per system node) each node's penalty stiffness
    /// along the normal were every pair in contact, Σ c² k with c = 1 at the paired node
    /// and bₖ at the corners: the stable step's estimate (World).
    void
    add_potential_stiffness(std::vector<double> &per_node) const;

  private:
    struct Pair
    {
      std::uint32_t  node;
      mesh::Triangle triangle;
      Vector3d       bary;
    };
    std::vector<Pair> pairs;
    double            margin;
  };
} // namespace suturesim::realtime
