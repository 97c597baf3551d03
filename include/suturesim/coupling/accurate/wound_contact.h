#pragma once
/**
 * @file
 * Contact between the two faces of an incision in the accurate (FE) tissue, so that a
 * wound drawn shut by a stitch closes on its faces instead of letting them pass through
 * each other (without it the coarse stitch's faces overlapped by 66 µm at the stitch's
 * depth while the top stayed open; docs/interrupted_stitch.md).
 *
 * Node to surface, one pass, small sliding (Wriggers 2006, "Computational Contact
 * Mechanics", §4.2 and §9.2): every mesh vertex P of face A (not on face B too: the
 * incision's front, where both faces meet, is shared) is paired once, in the reference
 * configuration, with the closest point Q of face B, a material point of B's surface
 * (barycentric on a boundary triangle), and B's outward normal n there. The gap and the
 * penalty
 *   g = (x_P − x_Q)·n,   f_P = −k min(g, 0) n = −f_Q
 * are then linear in the two points' positions: the pairing and n stay as in the
 * reference, which holds while the faces slide along each other by less than an element
 * and turn by small angles (closing a wound turns each face by a few degrees: g errs by
 * |x_P − x_Q| θ, zero at contact). The tangent of a pair in contact is k n nᵀ on each point
 * and −k n nᵀ between them: the first through the point loads' ∂f/∂x, the second through
 * the coupling of a condensed body (tissue/condensed_body.h; the points are not in the
 * same cells, so the FE matrix has no entries between them). Frictionless.
 *
 * Only pairs whose gap is below a margin are loaded (detect(), between solves, as the
 * suture's contacts): each loaded pair costs the coupled Newton iteration three more
 * linear solves.
 */

#include <suturesim/tissue/condensed_body.h>
#include <suturesim/tissue/point_loads.h>

#include <deal.II/base/types.h>

#include <Eigen/Core>

#include <nlohmann/json_fwd.hpp>

#include <array>
#include <vector>

namespace suturesim::coupling
{
  struct WoundContactParameters
  {
    double stiffness = 0; ///< k per pair, N/m
    double margin    = 0; ///< gap below which a pair is loaded, m
  };

  class WoundContact : public tissue::PointLoads, public tissue::CondensedBody
  {
  public:
    struct Pair
    {
      std::uint32_t                vertex = 0;  ///< P: a surface vertex of face A
      std::array<std::uint32_t, 3> triangle{}; ///< Q's triangle on face B (surface vertices)
      Eigen::Vector3d              weights = Eigen::Vector3d::Zero(); ///< Q's barycentric weights
      Eigen::Vector3d              normal  = Eigen::Vector3d::Zero(); ///< n, B's outward normal
    };

    /// Pairs face @p a's vertices with face @p b of the surface @p triangles (over the
    /// columns of @p reference, outward oriented; @p ids the boundary id of each
    /// triangle). std::invalid_argument when either face has no triangle.
    WoundContact(const WoundContactParameters &parameters, const Eigen::Matrix3Xd &reference,
                 const std::vector<std::array<std::uint32_t, 3>> &triangles,
                 const std::vector<dealii::types::boundary_id> &ids, dealii::types::boundary_id a,
                 dealii::types::boundary_id b);

    /// Loads the pairs whose gap at surface positions @p surface (current, one column per
    /// reference vertex) is below the margin; true when that set changed (the tissue
    /// must locate points() again).
    bool
    detect(const Eigen::Matrix3Xd &surface);

    /// The loaded pairs and their last equilibrium, for a checkpoint (io/checkpoint.h);
    /// restore() takes them back.
    nlohmann::json
    snapshot() const;
    void
    restore(const nlohmann::json &snapshot);

    /// Keeps the loaded pairs and where equilibrate() last saw their points at the start
    /// of a step; restore() with no argument takes them back when the step is undone, so
    /// that a halved step, and the checkpoint of a run that gave up, hold the last
    /// accepted state's.
    void
    save();
    void
    restore();

    /// Where the contact's points are among the tissue's point loads: index of its first.
    void
    set_offset(std::size_t first)
    {
      offset = first;
    }

    const std::vector<Pair> &
    pairs() const
    {
      return all;
    }
    /// Loaded pairs (indices into pairs()).
    const std::vector<std::size_t> &
    loaded() const
    {
      return active;
    }
    /// Pairs in contact (g < 0) at the last equilibrate(), and their total force, N.
    unsigned
    n_touching() const
    {
      return touching;
    }
    double
    total_force() const
    {
      return pressing;
    }
    /// Least gap of the loaded pairs at the last equilibrate(), m (∞ when none).
    double
    least_gap() const;

    // --- PointLoads: P of each loaded pair, then their Q -----------------------------
    const std::vector<dealii::Point<3>> &
    points() const override
    {
      return X;
    }
    void
    force(std::size_t k, const dealii::Point<3> &x, dealii::Tensor<1, 3> &f,
          dealii::Tensor<2, 3> &df_dx) const override;

    // --- CondensedBody: no unknowns of its own; G holds the pairs' cross terms --------
    std::vector<std::size_t>
    coupled_points() const override;
    bool
    equilibrate(const std::vector<dealii::Point<3>> &x, Eigen::MatrixXd &G, std::string &failure) override;

  private:
    /// The loaded pairs' points X: P of each, then their Q.
    void
    adopt();
    /// Gap of loaded pair j with P at @p p and Q at @p q, m.
    double
    gap(std::size_t j, const dealii::Point<3> &p, const dealii::Point<3> &q) const;

    WoundContactParameters        prm;
    Eigen::Matrix3Xd              reference;
    std::vector<Pair>             all;
    std::vector<std::size_t>      active;
    std::vector<dealii::Point<3>> X;
    std::vector<dealii::Point<3>> seen; ///< current positions of points(), set by equilibrate()
    std::size_t                   offset   = 0;
    unsigned                      touching = 0;
    double                        pressing = 0;
    struct Saved
    {
      std::vector<std::size_t>      active;
      std::vector<dealii::Point<3>> seen;
      unsigned                      touching = 0;
      double                        pressing = 0;
    } saved; ///< save()'s
  };
} // namespace suturesim::coupling
