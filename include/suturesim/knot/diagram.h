#pragma once
/**
 * @file
 * The knot diagram of an open rope: its centreline (a polyline of nodes p_0 … p_n)
 * projected onto a plane with unit normal n, as seed 002 §5 reads a knot ("the suture
 * must be projected onto a plane. It is then easy to identify the crossings").
 *
 *  - A crossing is a pair of non-adjacent segments whose projections intersect. Each
 *    point of the rope is named by its arc index a = i + s (segment i, s ∈ [0, 1)), so a
 *    crossing has two occurrences a < b; the strand higher along n there is over.
 *  - The Gauss code lists the occurrences in the order of a along the rope, each as O
 *    (over) or U (under) with the crossing's label, crossings labelled 1, 2, … by first
 *    occurrence: the overhand knot (trefoil) tied in an open rope reads
 *    "O1 U2 O3 U1 O2 U3" (or its mirror image, O and U swapped), the figure-eight
 *    "O1 U2 O3 U4 O2 U1 O4 U3" when read from a point where the closed knot is cut open
 *    (tests/realtime/knot_diagram_test.cc draws both from their parametric curves).
 *  - Spans (seed 002 §5 A): "each span is a section of suture between crossings",
 *    numbered from the first node: 2k occurrences cut the rope into 2k + 1 spans.
 *  - reduced(): the code after Reidemeister moves I (a crossing whose two occurrences
 *    are next to each other: a twist loop) and II (two crossings next to each other at
 *    both places, one strand over both: a strand lying across another and back), applied
 *    until none is left. Wiggles of a simulated rope add such pairs without changing the
 *    knot; the reduced code is the knot's diagram as a reader would draw it. The open
 *    rope is read as closed by an arc from its last node to its first that crosses
 *    nothing (both ends outside the knot, as when it is pulled by them), so a crossing
 *    of the first span with the last is a twist loop too (move I through that arc): the
 *    trefoil cut open with both tails along one line may read "U1 O2 U3 O4 U2 O3 U4 O1",
 *    which reduces to "O1 U2 O3 U1 O2 U3".
 *
 * Plain C++ and Eigen (the realtime library); every pair of non-adjacent segments is
 * tested, O(n²): 4 753 pairs for a 100-node rope.
 */

#include <Eigen/Core>

#include <string>
#include <vector>

namespace suturesim::knot
{
  /// One occurrence of a crossing in a Gauss code.
  struct GaussEntry
  {
    unsigned label = 0; ///< 1, 2, … by first occurrence
    bool     over  = false;
    /// The crossing's sign, +1 or −1 (Crossing::sign), the same at both occurrences; 0
    /// when unknown (a code read from text). Not compared by operator==: the code is
    /// the sequence of over- and under-passes.
    int sign = 0;

    bool
    operator==(const GaussEntry &o) const
    {
      return label == o.label && over == o.over;
    }
  };

  /// A Gauss code: the occurrences along the rope from its first node.
  class GaussCode
  {
  public:
    GaussCode() = default;
    explicit GaussCode(std::vector<GaussEntry> entries);
    /// Reads "O1 U2 O3 U1 O2 U3" (empty: no crossing); std::invalid_argument if a label
    /// does not occur exactly twice, once over and once under.
    static GaussCode
    parse(const std::string &text);

    /// The code after Reidemeister I and II moves until none applies, relabelled.
    GaussCode
    reduced() const;
    /// The mirror image's code: every O and U swapped.
    GaussCode
    mirrored() const;
    /// Whether this code reads the closed diagram @p closed, or its mirror image, cut
    /// open somewhere: a rotation of its entries, relabelled. The trefoil cut anywhere
    /// reads O1 U2 O3 U1 O2 U3 or its mirror; the figure-eight's cuts read eight codes.
    bool
    is_cut_of(const GaussCode &closed) const;
    /// The knot determinant |Δ(−1)| of the rope closed as reduced() closes it: the
    /// colouring matrix has a row per crossing, 2 on its over-arc and −1 on each of its
    /// two under-arcs (an arc runs from one under-pass to the next), and its determinant
    /// with any one row and column struck out is the knot's (Lickorish, An Introduction
    /// to Knot Theory, 1997). 1 for the unknot, 3 for the trefoil, 5 for the
    /// figure-eight. Every diagram of a knot gives the same, so it names the knot where
    /// the moves of reduced() leave more crossings than its least number (a tight knot
    /// seen along a plane that is not its own).
    long
    determinant() const;
    /// The writhe: the sum of the crossings' signs (GaussEntry::sign), each counted once.
    /// Reidemeister II and III moves keep it (Lickorish 1997, ch. 1). Of a diagram that
    /// reduced() leaves with the knot's least number of crossings it tells a composite
    /// knot's summands' handedness apart where the determinant cannot: the square knot
    /// (the trefoil and its mirror image, 3₁ # 3₁*) has 0 in a six-crossing diagram, the
    /// granny knot (3₁ # 3₁) ±6.
    int
    writhe() const;

    std::size_t
    crossings() const
    {
      return entries_.size() / 2;
    }
    const std::vector<GaussEntry> &
    entries() const
    {
      return entries_;
    }
    std::string
    text() const;

    bool
    operator==(const GaussCode &o) const
    {
      return entries_ == o.entries_;
    }

  private:
    std::vector<GaussEntry> entries_;
  };

  /// The plane the rope is projected onto: unit normal n and in-plane axes u, v.
  struct Projection
  {
    /// @p normal need not be unit; std::invalid_argument if it is zero.
    explicit Projection(const Eigen::Vector3d &normal);
    Eigen::Vector3d n, u, v;

    Eigen::Vector2d
    in_plane(const Eigen::Vector3d &x) const
    {
      return {u.dot(x), v.dot(x)};
    }
    double
    height(const Eigen::Vector3d &x) const
    {
      return n.dot(x);
    }
  };

  struct Crossing
  {
    double a = 0, b = 0;   ///< arc indices of the two occurrences, a < b
    bool   a_over = false; ///< the strand at a is higher along n
    /// sign((t_over × t_under) · n), t the strands' directions along the rope (from its
    /// first node): the crossing's handedness; the mirror image turns every sign (which
    /// way round +1 is named does not matter to what the writhe tells)
    int sign = 0;
  };

  class KnotDiagram
  {
  public:
    /// The diagram of the rope through the columns of @p nodes (m) projected along
    /// @p projection.
    KnotDiagram(const Eigen::Matrix3Xd &nodes, const Projection &projection);

    const std::vector<Crossing> &
    crossings() const
    {
      return crossings_;
    }
    GaussCode
    gauss_code() const;

    /// The arc indices where spans begin and end: 0, the 2k occurrences in order, n.
    const std::vector<double> &
    span_bounds() const
    {
      return bounds;
    }
    std::size_t
    spans() const
    {
      return bounds.size() - 1;
    }
    /// The span holding arc index @p a.
    std::size_t
    span_of(double a) const;
    /// The point at arc index @p a (m).
    Eigen::Vector3d
    point(double a) const;

  private:
    Eigen::Matrix3Xd      x;
    std::vector<Crossing> crossings_; ///< ordered by a
    std::vector<double>   bounds;
  };
} // namespace suturesim::knot
