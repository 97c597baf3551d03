#pragma once
/**
 * @file
 * Suture–tissue contact in the accurate path: the Cosserat suture's nodes against the
 * FE tissue's deformed boundary, outside the pierce points (the thread lying on the
 * skin between passes, the strands drawn across the wound when it is closed). The same
 * rule as the realtime path (realtime/surface_contact.h), so that the two paths differ
 * in their models, not in their contact:
 *  - detection (detect()): each suture node against its nearest boundary triangle
 *    (collision::NearestTriangle behind a triangle sphere tree refitted lazily); a node
 *    is in contact when its signed distance d = (p − q)·n lies in (−depth, 1.25 r), r
 *    the suture's radius. The triangle, the closest point's barycentric weights (a
 *    material point of the surface, embedded in its FE cell like a pierce point) and the
 *    outward normal n are frozen until the next detection;
 *  - response: the gap g = (p − x_q)·n − r, x_q the surface point's current position,
 *    and a penalty f = F n on the node (frictionless), −f on the tissue at x_q
 *    (tissue::PointLoads), with
 *        F = −k g                 for g ≤ −δ,
 *        F = k (δ − g)² / (4δ)    for |g| < δ,
 *        F = 0                    for g ≥ δ:
 *    the penalty −k g wherever it presses by more than δ, its kink at g = 0 rounded off
 *    by the quadratic that meets it with value and slope at g = ±δ (C¹; δ = 0 the sharp
 *    law). Why: with the kink sharp, a node grazing the surface pressed at the full
 *    Newton step and not at any of its halvings, the tangent never saw it, and the
 *    coupled solve stalled above its tolerance (docs/tearing.md, "The coupled solve's
 *    stalls"). The realtime path keeps the sharp law: its integrators take no Newton
 *    step across it. Node side: residual −f, Jacobian F' n nᵀ; tissue side:
 *    ∂f_q/∂x_q = −F' n nᵀ, F' = dF/d(−g). Each side is solved with the other held
 *    (the accurate pass's block Gauss–Seidel rounds), as the pierce points are.
 * Nodes the pierce points draw into the tissue (a stitch's tracts,
 * TissueNeedle::thread_nodes_in_tracts()) and nodes held by a support (the swage, a
 * grasper) are left out.
 *
 * Nodes only: a segment between two nodes outside may still cut a sharp edge of the
 * surface by up to a fraction of the node spacing; the no-node-inside check at the end
 * of a run (collision::surface_penetration) measures nodes too.
 */

#include <suturesim/collision/triangle_sphere_tree.h>
#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/rod/rod_model.h>
#include <suturesim/tissue/point_loads.h>

#include <Eigen/Core>

#include <nlohmann/json_fwd.hpp>

#include <vector>

namespace suturesim::coupling
{
  struct SutureContactParameters
  {
    double stiffness = 0; ///< k per node, N/m
    double radius    = 0; ///< r of the suture, m
    double depth     = 0; ///< how far inside a node is still pushed out, m
    double smoothing = 0; ///< δ: the law's kink at g = 0 rounded over |g| < δ (0: none), m
  };

  class SutureContact : public tissue::PointLoads
  {
  public:
    struct Contact
    {
      std::size_t     node = 0;
      std::uint32_t   triangle = 0;
      Eigen::Vector3d weights  = Eigen::Vector3d::Zero();
      Eigen::Vector3d normal   = Eigen::Vector3d::Zero();
    };

    /// @p triangles over the columns of @p reference (outward oriented, the tissue's
    /// boundary in its reference configuration).
    SutureContact(const SutureContactParameters &parameters, const std::vector<mesh::Triangle> &triangles,
                  const Eigen::Matrix3Xd &reference);

    /// New contacts for suture nodes @p nodes against the surface at @p surface (current
    /// vertex positions), skipping nodes with @p skip[i] != 0. Returns true when the set
    /// of contacts (node, triangle) changed: the tissue must locate points() again.
    /// With @p grow_only, the listed contacts stay, each on its triangle, and only nodes
    /// not yet listed are added: a set that can only grow settles within a step, where a
    /// node at an edge of the surface can otherwise be pushed along one triangle's normal
    /// onto the other's and back, round after round. A kept contact whose node has left
    /// the band carries no force (its gap is positive).
    bool
    detect(const Eigen::Matrix3Xd &surface, const std::vector<rod::Vec3> &nodes, const std::vector<char> &skip,
           bool grow_only = false);

    /// Where the suture sees the tissue points of the contacts (one per points(), m): the
    /// caller sets them from the tissue's solution before each suture solve.
    void
    set_tissue_positions(std::vector<dealii::Point<3>> x)
    {
      seen = std::move(x);
    }

    /// The suture's side: adds node @p node's residual and Jacobian block for its
    /// position @p x (a rod::NodalTerms with the tissue held).
    void
    add_node_terms(std::size_t node, const rod::Vec3 &x, rod::Vec6 &residual, rod::Mat6 &jacobian) const;

    /// Total contact force magnitude on the suture at nodes @p nodes with the tissue
    /// points at their last set positions, N.
    double
    total_force(const std::vector<rod::Vec3> &nodes) const;
    /// How many contacts carry a force (g < δ) with the nodes at @p nodes and the tissue
    /// points at their last set positions.
    std::size_t
    n_pressing(const std::vector<rod::Vec3> &nodes) const;

    /// The contacts of the last accepted state, for a checkpoint (io/checkpoint.h);
    /// restore() takes them back.
    nlohmann::json
    snapshot() const;
    void
    restore(const nlohmann::json &snapshot);

    /// Keeps the contacts as they are (each with the weights and normal it was frozen
    /// with, and where the suture saw its point) at the start of a step; restore() with
    /// no argument takes them back when the step is undone. Why: the rounds of a step
    /// detect again, so an attempt that failed after its first round left its own
    /// contacts to the halved attempt, and to the checkpoint written when the run gave
    /// up, whose replay then took another path (docs/checkpoints.md).
    void
    save();
    void
    restore();

    const std::vector<Contact> &
    contacts() const
    {
      return list;
    }
    /// Node @p node's contact index, or −1.
    int
    contact_of(std::size_t node) const
    {
      return node < slot.size() ? slot[node] : -1;
    }

    // --- PointLoads: the tissue's side, the suture held ---------------------------------
    const std::vector<dealii::Point<3>> &
    points() const override
    {
      return X;
    }
    void
    force(std::size_t k, const dealii::Point<3> &x, dealii::Tensor<1, 3> &f,
          dealii::Tensor<2, 3> &df_dx) const override;

    /// The suture's nodes the tissue side reads (kept by the caller).
    void
    set_suture(const std::vector<rod::Vec3> *nodes)
    {
      suture = nodes;
    }

  private:
    /// Penalty force magnitude F(g) of contact @p c for node position @p p and surface
    /// point @p q (N), and in @p slope (when given) F' = dF/d(−g), N/m.
    double
    pressure(const Contact &c, const Eigen::Vector3d &p, const Eigen::Vector3d &q, double *slope = nullptr) const;
    /// The contacts' material points X and the nodes' slots, from list.
    void
    adopt(std::size_t n_nodes);

    SutureContactParameters             prm;
    const std::vector<mesh::Triangle>  &triangles;
    Eigen::Matrix3Xd                    reference;
    collision::TriangleSphereTree       tree;
    std::vector<std::uint32_t>          candidates;
    std::vector<Contact>                list;
    std::vector<int>                    slot;
    std::vector<dealii::Point<3>>       X, seen;
    struct Saved
    {
      std::vector<Contact>          list;
      std::vector<dealii::Point<3>> seen;
      std::size_t                   nodes = 0;
    } saved; ///< save()'s
    const std::vector<rod::Vec3>       *suture = nullptr;
  };
} // namespace suturesim::coupling
