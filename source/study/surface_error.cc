#include <suturesim/collision/proximity.h>
#include <suturesim/study/surface_error.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace suturesim::study
{
  namespace
  {
    /// The reference triangles' bounding boxes, to skip those farther than the best so far.
    struct Boxes
    {
      Eigen::Matrix3Xd lower, upper;

      explicit Boxes(const io::SurfaceField &s)
        : lower(3, s.triangles.size())
        , upper(3, s.triangles.size())
      {
        for (std::size_t t = 0; t < s.triangles.size(); ++t)
          {
            const auto &[a, b, c] = s.triangles[t];
            lower.col(t) = s.reference.col(a).cwiseMin(s.reference.col(b)).cwiseMin(s.reference.col(c));
            upper.col(t) = s.reference.col(a).cwiseMax(s.reference.col(b)).cwiseMax(s.reference.col(c));
          }
      }

      double
      squared_distance(const std::size_t t, const Eigen::Vector3d &p) const
      {
        const Eigen::Vector3d d = (lower.col(t) - p).cwiseMax(p - upper.col(t)).cwiseMax(0.0);
        return d.squaredNorm();
      }
    };
  } // namespace

  SurfaceErrors
  surface_errors(const io::SurfaceField &candidate, const io::SurfaceField &reference)
  {
    if (candidate.triangles.empty() || reference.triangles.empty())
      throw std::invalid_argument("a surface error needs two surfaces with triangles");
    const Boxes     boxes(reference);
    Eigen::VectorXd weight = Eigen::VectorXd::Zero(candidate.reference.cols());
    for (const auto &[a, b, c] : candidate.triangles)
      {
        const auto &X    = candidate.reference;
        const double area = 0.5 * (X.col(b) - X.col(a)).cross(X.col(c) - X.col(a)).norm();
        weight(a) += area / 3, weight(b) += area / 3, weight(c) += area / 3;
      }
    double diff2 = 0, ref2 = 0, diff_max = 0, ref_max = 0, distance = 0;
    for (Eigen::Index i = 0; i < candidate.reference.cols(); ++i)
      {
        if (weight(i) == 0)
          continue;
        const Eigen::Vector3d p    = candidate.reference.col(i);
        double                best = std::numeric_limits<double>::infinity();
        Eigen::Vector3d       u_ref = Eigen::Vector3d::Zero();
        for (std::size_t t = 0; t < reference.triangles.size(); ++t)
          {
            if (boxes.squared_distance(t, p) >= best)
              continue;
            const auto &[a, b, c] = reference.triangles[t];
            Eigen::Vector3d       bary;
            const Eigen::Vector3d closest = collision::closest_point_on_triangle(
              p, reference.reference.col(a), reference.reference.col(b), reference.reference.col(c), bary);
            const double d2 = (closest - p).squaredNorm();
            if (d2 < best)
              {
                best  = d2;
                u_ref = bary(0) * reference.displacement.col(a) + bary(1) * reference.displacement.col(b) +
                        bary(2) * reference.displacement.col(c);
              }
          }
        const double e = (candidate.displacement.col(i) - u_ref).norm();
        diff2 += weight(i) * e * e;
        ref2 += weight(i) * u_ref.squaredNorm();
        diff_max = std::max(diff_max, e);
        ref_max  = std::max(ref_max, u_ref.norm());
        distance = std::max(distance, std::sqrt(best));
      }
    if (ref2 == 0 || ref_max == 0)
      throw std::invalid_argument("the reference surface does not move: no relative error");
    return {std::sqrt(diff2 / ref2), diff_max / ref_max, distance};
  }
} // namespace suturesim::study
