#pragma once
/**
 * @file
 * The C¹ centreline of the Cosserat suture that pierce points are measured against
 * (coupling/accurate/tissue_needle.h): a cubic Hermite curve per element through the
 * rod's nodes with the rod's own tangent directors there.
 *
 * On element e (nodes a, b, reference length l₀ = s_b − s_a of the suture's reference
 * arc length s), u ∈ [0, 1]:
 *   c(u) = h₀₀(u) x_a + h₁₀(u) m_a + h₀₁(u) x_b + h₁₁(u) m_b,
 *   h₀₀ = 2u³ − 3u² + 1, h₁₀ = u³ − 2u² + u, h₀₁ = 3u² − 2u³, h₁₁ = u³ − u²,
 * with end tangents m = ℓ d₁, ℓ = |x_b − x_a|, and d₁ = R e₁ the rod's tangent director
 * at the node. c(0) = x_a, c(1) = x_b, c′(0) = m_a, c′(1) = m_b: the elements that meet
 * at a node share its director, so the curve's tangent direction is continuous along
 * the thread (its length ℓ jumps with the chord, which leaves the direction alone). This
 * is the beam-contact smoothing of Litewka & Wriggers 2002 (Comput. Mech. 28:26–39),
 * with the Cosserat rod's nodal tangents in place of fitted ones. A thread without
 * rotations (unit tests) gets the chord: m_a = m_b = x_b − x_a, so c(u) = (1 − u) x_a
 * + u x_b.
 *
 * The closest point of x on an element's curve solves g(u) = (x − c(u))·c′(u) = 0 by
 * Newton's method with g′ = −|c′|² + (x − c)·c″ (HermiteSegment::closest()).
 */

#include <suturesim/rod/rotation.h>

#include <Eigen/Core>

#include <cstddef>
#include <utility>
#include <vector>

namespace suturesim::coupling
{
  /// One element's cubic Hermite curve c(u), u ∈ [0, 1] from node a to node b, with end
  /// tangents m_a, m_b (see the file's description), and its first two derivatives.
  struct HermiteSegment
  {
    Eigen::Vector3d xa, ma, xb, mb;
    /// Whether the end tangents are the nodes' directors scaled by the chord (else the
    /// chord itself): what reaction() differentiates.
    bool directors = true;

    /// The curve from (@p xa, @p qa) to (@p xb, @p qb): end tangents the rod's tangent
    /// director d₁ = R e₁ at each node scaled by the chord with @p directors, else the
    /// chord itself.
    static HermiteSegment
    through(const rod::Vec3 &xa, const rod::Quat &qa, const rod::Vec3 &xb, const rod::Quat &qb,
            bool directors);

    /// The cubic Hermite basis (h₀₀, h₁₀, h₀₁, h₁₁)(u) = (2u³ − 3u² + 1, u³ − 2u² + u,
    /// 3u² − 2u³, u³ − u²), the weights of x_a, m_a, x_b, m_b in c(u): shared by at()
    /// and reaction(), which must weight the nodes as the curve does.
    static Eigen::Vector4d
    basis(const double u)
    {
      const double u2 = u * u, u3 = u2 * u;
      return {2 * u3 - 3 * u2 + 1, u3 - 2 * u2 + u, 3 * u2 - 2 * u3, u3 - u2};
    }
    /// c(u), m.
    Eigen::Vector3d
    at(const double u) const
    {
      const Eigen::Vector4d h = basis(u);
      return h[0] * xa + h[1] * ma + h[2] * xb + h[3] * mb;
    }
    /// c′(u), m.
    Eigen::Vector3d
    rate(const double u) const
    {
      const double u2 = u * u;
      return (6 * u2 - 6 * u) * (xa - xb) + (3 * u2 - 4 * u + 1) * ma + (3 * u2 - 2 * u) * mb;
    }
    /// c″(u), m.
    Eigen::Vector3d
    bend(const double u) const
    {
      return (12 * u - 6) * (xa - xb) + (6 * u - 4) * ma + (6 * u - 2) * mb;
    }

    /// The nodal loads a force @p f applied to the curve's material point c(u) puts on
    /// the element: the generalised forces (∂c(u)/∂q)ᵀ f conjugate to the nodes'
    /// positions and spatial rotation increments q = (x_a, θ_a, x_b, θ_b) at fixed u
    /// (virtual work f·δc), N and N m. With directors, m = ℓ d₁, ℓ = |x_b − x_a|,
    /// e = (x_b − x_a)/ℓ, δd₁ = δθ × d₁ and t = h₁₀ d₁ₐ + h₁₁ d₁ᵦ:
    ///   x_a: h₀₀ f − e (t·f),   θ_a: ℓ h₁₀ d₁ₐ × f,
    ///   x_b: h₀₁ f + e (t·f),   θ_b: ℓ h₁₁ d₁ᵦ × f;
    /// for the chord, (1 − u) f and u f and no moments. Their resultant is f and their
    /// moment c(u) × f: the force acts where the curve is, and for a potential whose
    /// force this is (a penalty tie to the curve, at its closest point) they are its
    /// gradient with respect to q (the closest point's own variation drops out there).
    Eigen::Matrix<double, 12, 1>
    reaction(double u, const Eigen::Vector3d &f) const;

    /// The parameter u of the point of the curve (extended past its ends by the cubic)
    /// closest to @p x: Newton on g(u) = (x − c)·c′ = 0 from @p u0, u kept within
    /// [−1, 2], until a step below 1e-14 (at most 50 iterations). Where x lies beyond the
    /// curve's centre of curvature g′ may not be negative, and the step falls back to
    /// the Gauss–Newton one (g′ = −|c′|²).
    double
    closest(const Eigen::Vector3d &x, double u0) const;
  };

  /// The suture beyond the needle's swage as a chain of Hermite segments over its nodes,
  /// addressed by the reference arc length s from node 0 (the swage).
  class ThreadCurve
  {
  public:
    /// The thread's current node positions and rotations (kept by the caller and read
    /// at every evaluation; @p rotations may be nullptr, each element is then its chord)
    /// and the reference length of each element (m). @p nodes nullptr detaches it.
    void
    attach(const std::vector<rod::Vec3> *nodes, const std::vector<double> &element_lengths,
           const std::vector<rod::Quat> *rotations);

    /// Whether a thread is attached.
    bool
    attached() const
    {
      return nodes != nullptr;
    }

    /// Number of nodes.
    std::size_t
    n_nodes() const
    {
      return s.size();
    }
    /// Number of elements.
    std::size_t
    n_elements() const
    {
      return s.size() - 1;
    }
    /// Reference length of the whole thread, m.
    double
    length() const
    {
      return s.back();
    }
    /// Reference arc length of node @p i, m.
    double
    arc_length(const std::size_t i) const
    {
      return s[i];
    }
    /// Reference length of element @p e, m.
    double
    element_length(const std::size_t e) const
    {
      return s[e + 1] - s[e];
    }

    /// Element holding arc length @p s (the first or last beyond the ends) and the weight
    /// ξ ∈ [0, 1] of its second node.
    std::pair<std::size_t, double>
    element(double s) const;

    /// Node @p i's position and rotation (identity without rotations).
    std::pair<rod::Vec3, rod::Quat>
    node(std::size_t i) const;

    /// Element @p e's curve with its nodes where they are now.
    HermiteSegment
    segment(std::size_t e) const;

    /// An element's curve with its nodes at (@p xa, @p qa) and (@p xb, @p qb) (a moved
    /// node, for finite differences).
    HermiteSegment
    segment(const rod::Vec3 &xa, const rod::Quat &qa, const rod::Vec3 &xb, const rod::Quat &qb) const
    {
      return HermiteSegment::through(xa, qa, xb, qb, rotations != nullptr);
    }

  private:
    const std::vector<rod::Vec3> *nodes     = nullptr;
    const std::vector<rod::Quat> *rotations = nullptr;
    std::vector<double>           s{0.0}; ///< reference arc length at each node, m
  };
} // namespace suturesim::coupling
