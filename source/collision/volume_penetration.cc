#include <suturesim/collision/proximity.h>
#include <suturesim/collision/volume_penetration.h>

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>

namespace suturesim::collision
{
  bool
  inside_tetrahedron(const Eigen::Vector3d &p, const Eigen::Vector3d &a, const Eigen::Vector3d &b,
                     const Eigen::Vector3d &c, const Eigen::Vector3d &d)
  {
    Eigen::Matrix3d J;
    J << b - a, c - a, d - a;
    const double det = J.determinant();
    if (det == 0)
      return false;
    const Eigen::Vector3d l = J.inverse() * (p - a);
    // a relative slack of round-off, so that a point on a shared face counts
    const double eps = 1e-12;
    return l.minCoeff() >= -eps && l.sum() <= 1 + eps;
  }

  namespace
  {
    /// Distance from @p p to the nearest triangle of @p surface, m.
    double
    depth_below(const Eigen::Vector3d &p, const Eigen::Matrix3Xd &x,
                const std::vector<std::array<std::uint32_t, 3>> &surface)
    {
      double depth = std::numeric_limits<double>::infinity();
      for (const auto &t : surface)
        {
          Eigen::Vector3d bary;
          depth = std::min(depth, (p - closest_point_on_triangle(p, x.col(t[0]), x.col(t[1]), x.col(t[2]), bary)).norm());
        }
      return depth;
    }

    /// The columns of @p points for which @p inside holds, deeper than @p tolerance.
    template <typename Inside>
    VolumePenetration
    deep_points(const Eigen::Matrix3Xd &x, const std::vector<std::array<std::uint32_t, 3>> &surface,
                const Eigen::Matrix3Xd &points, const double tolerance, const Inside &inside)
    {
      VolumePenetration result;
      for (Eigen::Index k = 0; k < points.cols(); ++k)
        {
          const Eigen::Vector3d p = points.col(k);
          if (!inside(p))
            continue;
          const double depth = depth_below(p, x, surface);
          if (depth > tolerance)
            {
              result.points.push_back(k);
              result.depths.push_back(depth);
            }
        }
      return result;
    }
  } // namespace

  VolumePenetration
  volume_penetration(const Eigen::Matrix3Xd &x, const std::vector<std::array<std::uint32_t, 4>> &cells,
                     const std::vector<std::array<std::uint32_t, 3>> &surface, const Eigen::Matrix3Xd &points,
                     const double tolerance)
  {
    return deep_points(x, surface, points, tolerance, [&](const Eigen::Vector3d &p) {
      return std::any_of(cells.begin(), cells.end(), [&](const auto &cell) {
        Eigen::Vector3d lo = x.col(cell[0]), hi = lo;
        for (unsigned v = 1; v < 4; ++v)
          {
            lo = lo.cwiseMin(x.col(cell[v]));
            hi = hi.cwiseMax(x.col(cell[v]));
          }
        if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any())
          return false;
        return inside_tetrahedron(p, x.col(cell[0]), x.col(cell[1]), x.col(cell[2]), x.col(cell[3]));
      });
    });
  }

  double
  winding_number(const Eigen::Vector3d &p, const Eigen::Matrix3Xd &x,
                 const std::vector<std::array<std::uint32_t, 3>> &surface)
  {
    double sum = 0;
    for (const auto &t : surface)
      {
        const Eigen::Vector3d a = x.col(t[0]) - p, b = x.col(t[1]) - p, c = x.col(t[2]) - p;
        const double          la = a.norm(), lb = b.norm(), lc = c.norm();
        // tan(Ω/2) = a·(b × c) / (|a||b||c| + (a·b)|c| + (a·c)|b| + (b·c)|a|)
        const double numerator   = a.dot(b.cross(c));
        const double denominator = la * lb * lc + a.dot(b) * lc + a.dot(c) * lb + b.dot(c) * la;
        sum += 2 * std::atan2(numerator, denominator);
      }
    return sum / (4 * M_PI);
  }

  VolumePenetration
  surface_penetration(const Eigen::Matrix3Xd &x, const std::vector<std::array<std::uint32_t, 3>> &surface,
                      const Eigen::Matrix3Xd &points, const double tolerance)
  {
    return deep_points(x, surface, points, tolerance,
                       [&](const Eigen::Vector3d &p) { return winding_number(p, x, surface) > 0.5; });
  }

  TractSplit
  split_by_tracts(const VolumePenetration &penetration, const std::vector<char> &in_tract)
  {
    TractSplit split;
    for (std::size_t k = 0; k < penetration.points.size(); ++k)
      if (penetration.points[k] < in_tract.size() && in_tract[penetration.points[k]])
        ++split.in_tracts;
      else
        {
          ++split.outside_tracts;
          split.depth = std::max(split.depth, penetration.depths[k]);
        }
    return split;
  }
} // namespace suturesim::collision
