#include <suturesim/collision/triangle_sphere_tree.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace suturesim::collision
{
  namespace
  {
    /// Spreads the low 21 bits of @p v so that two zero bits follow each one.
    std::uint64_t
    spread_bits(std::uint64_t v)
    {
      v &= 0x1fffff;
      v = (v | v << 32) & 0x1f00000000ffffULL;
      v = (v | v << 16) & 0x1f0000ff0000ffULL;
      v = (v | v << 8) & 0x100f00f00f00f00fULL;
      v = (v | v << 4) & 0x10c30c30c30c30c3ULL;
      v = (v | v << 2) & 0x1249249249249249ULL;
      return v;
    }
  } // namespace

  Sphere
  TriangleSphereTree::triangle_sphere(const Points &x, const std::uint32_t t, const double grow) const
  {
    const auto          &v = (*tris)[t];
    const Eigen::Vector3d c = (x.col(v[0]) + x.col(v[1]) + x.col(v[2])) / 3.0;
    const double r2 = std::max({(x.col(v[0]) - c).squaredNorm(), (x.col(v[1]) - c).squaredNorm(),
                                (x.col(v[2]) - c).squaredNorm()});
    return {c, std::sqrt(r2) + grow};
  }

  void
  TriangleSphereTree::build(const Points &x, const Triangles &triangles, const double thickness)
  {
    if (triangles.empty())
      throw std::invalid_argument("TriangleSphereTree: no triangles");
    tris   = &triangles;
    margin = thickness;

    // Morton order of the centroids in the bounding box
    Eigen::Vector3d lo = x.col(triangles[0][0]), hi = lo;
    std::vector<Eigen::Vector3d> centroid(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t)
      {
        const auto &v = triangles[t];
        centroid[t]   = (x.col(v[0]) + x.col(v[1]) + x.col(v[2])) / 3.0;
        lo            = lo.cwiseMin(centroid[t]);
        hi            = hi.cwiseMax(centroid[t]);
      }
    const Eigen::Vector3d scale = (hi - lo).cwiseMax(1e-300).cwiseInverse() * double((1 << 21) - 1);
    std::vector<std::uint64_t> code(triangles.size());
    for (std::size_t t = 0; t < triangles.size(); ++t)
      {
        const Eigen::Vector3d q = (centroid[t] - lo).cwiseProduct(scale);
        code[t] = spread_bits(std::uint64_t(q[0])) | spread_bits(std::uint64_t(q[1])) << 1 |
                  spread_bits(std::uint64_t(q[2])) << 2;
      }
    order.resize(triangles.size());
    std::iota(order.begin(), order.end(), 0u);
    std::stable_sort(order.begin(), order.end(),
                     [&](const std::uint32_t a, const std::uint32_t b) { return code[a] < code[b]; });

    std::vector<Sphere> leaves(triangles.size());
    for (std::size_t l = 0; l < leaves.size(); ++l)
      leaves[l] = triangle_sphere(x, order[l], margin);
    build_from_leaves(leaves);

    // vertex → leaves, for refits after a few vertices moved
    vertex_offsets.assign(x.cols() + 1, 0);
    for (const auto &v : triangles)
      for (const auto i : v)
        ++vertex_offsets[i + 1];
    std::partial_sum(vertex_offsets.begin(), vertex_offsets.end(), vertex_offsets.begin());
    vertex_leaves.resize(vertex_offsets.back());
    std::vector<std::uint32_t> fill(vertex_offsets.begin(), vertex_offsets.end() - 1);
    for (std::size_t l = 0; l < order.size(); ++l)
      for (const auto i : triangles[order[l]])
        vertex_leaves[fill[i]++] = static_cast<std::uint32_t>(l);
  }

  void
  TriangleSphereTree::refit(const Points &x)
  {
    for (std::size_t l = 0; l < order.size(); ++l)
      leaf_sphere(l) = triangle_sphere(x, order[l], margin);
    refit_all_inner();
  }

  std::size_t
  TriangleSphereTree::refit(const Points &x, const std::vector<std::uint32_t> &moved)
  {
    std::size_t leaves_updated = 0;
    for (const auto i : moved)
      for (auto k = vertex_offsets[i]; k < vertex_offsets[i + 1]; ++k)
        {
          const auto l = vertex_leaves[k];
          if (set_leaf(l, triangle_sphere(x, order[l], margin)))
            ++leaves_updated;
        }
    return leaves_updated + refit_marked();
  }

  std::size_t
  TriangleSphereTree::update(const Points &x, const double s)
  {
    if (slack < 0)
      {
        // first call: every leaf grown by the slack, every vertex fitted where it is
        // the points of the build: nodes added since (a tool's) are no vertex of it
        slack  = s;
        fitted = x.leftCols(static_cast<Eigen::Index>(vertex_offsets.size()) - 1);
        escaped.reserve(x.cols());
        for (std::size_t l = 0; l < order.size(); ++l)
          leaf_sphere(l) = triangle_sphere(x, order[l], margin + slack);
        refit_all_inner();
        return n_leaves() + (spheres().size() - n_leaves());
      }
    // Leaves are fitted to the recorded positions x₀ (not the current ones): a vertex
    // that escapes its slack gets x₀ = x, and every leaf touching it is refitted from
    // the x₀ of its three vertices, so each leaf keeps bounding the slack balls of all
    // of them.
    escaped.clear();
    const double s2 = slack * slack;
    for (Eigen::Index i = 0; i < fitted.cols(); ++i)
      if ((x.col(i) - fitted.col(i)).squaredNorm() > s2)
        {
          fitted.col(i) = x.col(i);
          escaped.push_back(static_cast<std::uint32_t>(i));
        }
    if (escaped.empty())
      return 0;
    std::size_t leaves_updated = 0;
    for (const auto i : escaped)
      for (auto k = vertex_offsets[i]; k < vertex_offsets[i + 1]; ++k)
        {
          const auto l = vertex_leaves[k];
          if (set_leaf(l, triangle_sphere(fitted, order[l], margin + slack)))
            ++leaves_updated;
        }
    return leaves_updated + refit_marked();
  }
} // namespace suturesim::collision
