#pragma once
/**
 * @file
 * Process zones around pierce tracts, over which tear_criterion.h's measures are
 * averaged. A tract is the straight segment a needle pass leaves in the tissue, from its
 * entry pierce point to its exit, in the reference configuration; its zone is the capsule
 * of points within a distance ℓ of the segment, intersected with the tissue (the
 * quadrature points that fall in it). The zone is material, so the points a zone holds
 * are found once and it moves with the tissue.
 *
 * The mean of a measure m over zone Z is  m̄ = ∫_Z m dV / ∫_Z dV,  summed over quadrature
 * points with their weights (reference volume). Besides the mean a zone keeps its
 * largest pointwise value, where it is and the direction there: where and which way a
 * tear would start once the mean reaches the critical value.
 *
 * Plain C++ (no deal.II): the realtime path's tear evaluation can share it.
 */

#include <array>
#include <cstddef>
#include <functional>
#include <limits>
#include <vector>

namespace suturesim::tearing
{
  using Point3 = std::array<double, 3>;

  /// The segment a needle pass leaves in the tissue (reference configuration, m).
  struct Tract
  {
    Point3 entry;
    Point3 exit;
  };

  /// The point of the segment [a, b] nearest @p x (a if a = b).
  Point3
  closest_on_segment(const Point3 &x, const Point3 &a, const Point3 &b);

  /// Euclidean distance from @p x to the segment [a, b] (a point if a = b).
  double
  distance_to_segment(const Point3 &x, const Point3 &a, const Point3 &b);

  /// One measure accumulated over one zone: its volume integral, the zone's volume, and
  /// the pointwise peak with its location and direction.
  struct ZoneSample
  {
    double volume   = 0;
    double integral = 0;
    double peak     = -std::numeric_limits<double>::infinity();
    Point3 peak_location{};
    Point3 peak_direction{};

    /// Adds a quadrature point of reference volume @p weight (m³) where the measure is
    /// @p value, at @p where (m) with tear direction @p direction.
    void
    add(double weight, double value, const Point3 &where, const Point3 &direction);

    /// Adds another partial sum of the same zone (another thread's or rank's share).
    void
    merge(const ZoneSample &other);

    /// m̄ = integral / volume; NaN when the zone holds no point (ℓ smaller than the cells).
    double
    mean() const;
  };

  class ProcessZones
  {
  public:
    /// Whether the straight path between two reference points crosses a cut (the
    /// wound's faces: tearing/stitch_evaluation.h, Wound::separates()).
    using Separates = std::function<bool(const Point3 &, const Point3 &)>;

    /// @p radius ℓ > 0 (m). With @p cut, a point belongs to a zone only when the cut
    /// does not separate it from its nearest point of the tract: a tract ending in one
    /// wound face does not reach across the gap into the other lip, which is not loaded
    /// through the wound (below the incision's floor the tissue is one and the zone goes
    /// on).
    ProcessZones(std::vector<Tract> tracts, double radius, Separates cut = {});

    /// Replaces @p zones by the indices of the zones that contain the reference point
    /// @p X; tracts closer than 2ℓ share points.
    void
    zones_containing(const Point3 &X, std::vector<unsigned int> &zones) const;

    std::size_t
    size() const
    {
      return tracts.size();
    }

    const Tract &
    tract(const std::size_t i) const
    {
      return tracts[i];
    }

    double
    radius() const
    {
      return ell;
    }

  private:
    std::vector<Tract> tracts;
    double             ell;
    Separates          cut;
  };
} // namespace suturesim::tearing
