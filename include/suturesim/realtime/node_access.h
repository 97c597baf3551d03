#pragma once
/**
 * @file
 * Seed 004's node-access constraint: the suture passes through a fixed access point b
 * (where it enters or leaves the tissue) between two consecutive nodes p_i, p_{i+1}; the
 * segment bends over b and keeps its rest length l:
 *
 *   C(p_i, p_{i+1}) = |b − p_i| + |b − p_{i+1}| − l = 0
 *
 * (seed 004, "Interactions between strands and soft tissue", constraint 3). Its gradient
 * ∇_{p_i} C = (p_i − b)/|p_i − b| (and the same with i + 1) is a unit vector per node,
 * so XPBD's update is Δλ = (−C − α̃λ)/(w_i + w_{i+1} + α̃) (Macklin, Müller & Chentanez
 * 2016, eq. 18) and the penalty form's energy is E = ½ k C².
 *
 * The constraint is a frictionless peg: the two parts of the segment carry the same
 * tension k C, so the thread slides through b and turns there. It stands in for the
 * segment's own length constraint, which the suture must leave out while b is on that
 * segment: with both, a straight segment through b has two parallel constraint
 * gradients (an ill-posed pair), and a bent one cannot satisfy both.
 *
 * Which segment holds b: as the thread slides, detect() moves the access to the
 * neighbouring segment while b's parameter on the chord,
 * t = (b − p_i)·(p_{i+1} − p_i)/|p_{i+1} − p_i|², lies outside [0, 1] (b has passed a
 * node), up to the suture's ends.
 */

#include <suturesim/realtime/system.h>

#include <cmath>
#include <functional>
#include <limits>
#include <vector>

namespace suturesim::realtime
{
  class NodeAccess : public ContactSet
  {
  public:
    struct Access
    {
      Vector3d      b = Vector3d::Zero(); ///< the access point, m
      std::uint32_t segment = 0; ///< i: between suture nodes i and i + 1 (local indices)
      double        lambda  = 0; ///< XPBD multiplier
    };

    /// Access constraints on the suture @p suture (node range in the system) of segments
    /// of rest length @p rest_length (m, > 0), stiffness @p stiffness (N/m, > 0; ∞: rigid).
    NodeAccess(NodeRange suture, double rest_length, double stiffness);

    /// Adds an access point @p b (m) on segment @p segment (0 ≤ segment < nodes − 1);
    /// returns its index. std::invalid_argument when the segment is not on the suture.
    std::size_t
    add(const Vector3d &b, std::uint32_t segment);

    std::string
    name() const override
    {
      return "node-access";
    }
    /// Called by detect() when an access moves from segment @p from to segment @p to
    /// (local indices): the owner of the suture gives the first link its own elasticity
    /// back and leaves the second's out (realtime/world.h).
    using Moved = std::function<void(std::uint32_t from, std::uint32_t to)>;
    void
    on_move(Moved callback)
    {
      moved = std::move(callback);
    }

    /// Moves each access to the segment that holds b at @p x (see the file's comment).
    void
    detect(const Matrix3Xd &x) override;
    /// f += −k C ∇C.
    void
    add_forces(const Matrix3Xd &x, Matrix3Xd &f) const override;
    /// E = Σ ½ k C², J.
    std::optional<double>
    energy(const Matrix3Xd &x) const override;
    bool
    has_projection() const override
    {
      return true;
    }
    void
    add_constraint_forces(const Matrix3Xd &x, Matrix3Xd &f, double dt) const override;
    void
    reset_multipliers() override;
    void
    project(Matrix3Xd &x, const VectorXd &w, double dt) override;
    std::size_t
    active() const override
    {
      return points.size();
    }

    const std::vector<Access> &
    list() const
    {
      return points;
    }

    /// C of access @p a at @p x, m.
    double
    violation(std::size_t a, const Matrix3Xd &x) const;
    /// The tension through access @p a at @p x, k C (N; a bilateral constraint, negative
    /// when the segment is slack); NaN for a rigid access, whose force is its XPBD
    /// multiplier's.
    double
    tension(std::size_t a, const Matrix3Xd &x) const
    {
      return std::isfinite(stiffness) ? stiffness * violation(a, x) : std::numeric_limits<double>::quiet_NaN();
    }
    /// ∇C of access @p a at @p x, on node i (@p gi) and on node i + 1 (@p gj); returns
    /// C, from the same two distances.
    double
    gradient(std::size_t a, const Matrix3Xd &x, Vector3d &gi, Vector3d &gj) const;
    /// System index of node i of access @p a.
    std::uint32_t
    first_node(std::size_t a) const
    {
      return suture.begin + points[a].segment;
    }

  private:
    NodeRange           suture;
    double              rest, stiffness;
    std::vector<Access> points;
    Moved               moved;
  };
} // namespace suturesim::realtime
