#include <suturesim/collision/sphere_tree.h>

#include <stdexcept>

namespace suturesim::collision
{
  namespace
  {
    Eigen::Map<const Eigen::Matrix3Xd>
    as_columns(const std::vector<Eigen::Vector3d> &points)
    {
      // a vector of Vector3d is contiguous triples: the same memory as a 3 x n matrix
      return {points.empty() ? nullptr : points.front().data(), 3,
              static_cast<Eigen::Index>(points.size())};
    }
  } // namespace

  Sphere
  SphereTree::segment_sphere(const Points &points, const std::size_t s) const
  {
    return {0.5 * (points.col(s) + points.col(s + 1)),
            0.5 * (points.col(s + 1) - points.col(s)).norm() + tube};
  }

  void
  SphereTree::build(const std::vector<Eigen::Vector3d> &points, const double tube_radius)
  {
    build(as_columns(points), tube_radius);
  }

  void
  SphereTree::build(const Points &points, const double tube_radius)
  {
    if (points.cols() < 2)
      throw std::invalid_argument("SphereTree: a chain needs at least two points");
    tube = tube_radius;
    std::vector<Sphere> leaves(points.cols() - 1);
    for (std::size_t s = 0; s < leaves.size(); ++s)
      leaves[s] = segment_sphere(points, s);
    build_from_leaves(leaves);
    last_points = points;
  }

  std::size_t
  SphereTree::refit(const std::vector<Eigen::Vector3d> &points)
  {
    return refit(as_columns(points));
  }

  std::size_t
  SphereTree::refit(const Points &points)
  {
    if (static_cast<std::size_t>(points.cols()) != n_segments() + 1)
      throw std::invalid_argument("SphereTree::refit: the number of points changed; build again");
    moved_work.clear();
    for (Eigen::Index i = 0; i < points.cols(); ++i)
      if (points.col(i) != last_points.col(i))
        moved_work.push_back(i);
    return refit(points, moved_work);
  }

  void
  SphereTree::refit_all(const Points &points)
  {
    for (std::size_t s = 0; s < n_segments(); ++s)
      leaf_sphere(s) = segment_sphere(points, s);
    refit_all_inner();
    last_points = points;
  }

  std::size_t
  SphereTree::refit(const std::vector<Eigen::Vector3d> &points, const std::vector<std::size_t> &moved)
  {
    return refit(as_columns(points), moved);
  }

  std::size_t
  SphereTree::refit(const Points &points, const std::vector<std::size_t> &moved)
  {
    // a moved point dirties the segments on both sides; each leaf is recomputed once
    std::size_t leaves_updated = 0;
    for (const std::size_t i : moved)
      {
        if (i > 0 && set_leaf(i - 1, segment_sphere(points, i - 1)))
          ++leaves_updated;
        if (i < n_segments() && set_leaf(i, segment_sphere(points, i)))
          ++leaves_updated;
        last_points.col(i) = points.col(i);
      }
    return leaves_updated + refit_marked();
  }
} // namespace suturesim::collision
