#pragma once
/**
 * @file
 * Several sets of point loads on the tissue as one (the needle's touch and pierce
 * points, then the suture's contacts): their points in turn, each part's first point at
 * offset(part).
 */

#include <suturesim/tissue/point_loads.h>

#include <vector>

namespace suturesim::tissue
{
  class PointLoadList : public PointLoads
  {
  public:
    /// The parts, in order (kept by the caller); call again whenever a part's set of
    /// points changes.
    void
    set(std::vector<const PointLoads *> parts);

    /// Index of part @p part's first point among points().
    std::size_t
    offset(std::size_t part) const
    {
      return first[part];
    }

    const std::vector<dealii::Point<3>> &
    points() const override
    {
      return all;
    }
    void
    force(std::size_t k, const dealii::Point<3> &x, dealii::Tensor<1, 3> &f,
          dealii::Tensor<2, 3> &df_dx) const override;
    double
    spread_radius(std::size_t k) const override;
    bool
    cut_off(std::size_t k, const dealii::Point<3> &Y) const override;
    /// Symmetric when every part's is.
    bool
    symmetric_tangent() const override;
    bool
    symmetric_at(std::size_t k) const override;

  private:
    /// The part holding point @p k.
    std::size_t
    part_of(std::size_t k) const;

    std::vector<const PointLoads *> list;
    std::vector<std::size_t>        first;
    std::vector<dealii::Point<3>>   all;
  };
} // namespace suturesim::tissue
