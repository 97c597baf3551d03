#include <suturesim/tissue/point_load_list.h>

#include <algorithm>
#include <iterator>

namespace suturesim::tissue
{
  void
  PointLoadList::set(std::vector<const PointLoads *> parts)
  {
    list = std::move(parts);
    first.clear();
    all.clear();
    for (const auto *part : list)
      {
        first.push_back(all.size());
        all.insert(all.end(), part->points().begin(), part->points().end());
      }
    first.push_back(all.size());
  }

  std::size_t
  PointLoadList::part_of(const std::size_t k) const
  {
    // the last part whose first point is at or before k
    return std::distance(first.begin(), std::upper_bound(first.begin(), first.end() - 1, k)) - 1;
  }

  double
  PointLoadList::spread_radius(const std::size_t k) const
  {
    const std::size_t part = part_of(k);
    return list[part]->spread_radius(k - first[part]);
  }

  bool
  PointLoadList::cut_off(const std::size_t k, const dealii::Point<3> &Y) const
  {
    const std::size_t part = part_of(k);
    return list[part]->cut_off(k - first[part], Y);
  }

  void
  PointLoadList::force(const std::size_t k, const dealii::Point<3> &x, dealii::Tensor<1, 3> &f,
                       dealii::Tensor<2, 3> &df_dx) const
  {
    const std::size_t part = part_of(k);
    list[part]->force(k - first[part], x, f, df_dx);
  }

  bool
  PointLoadList::symmetric_at(const std::size_t k) const
  {
    const std::size_t part = part_of(k);
    return list[part]->symmetric_at(k - first[part]);
  }

  bool
  PointLoadList::symmetric_tangent() const
  {
    for (const PointLoads *part : list)
      if (!part->symmetric_tangent())
        return false;
    return true;
  }
} // namespace suturesim::tissue
