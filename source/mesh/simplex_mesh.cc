#include <suturesim/mesh/simplex_mesh.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

namespace suturesim::mesh
{
  double
  SimplexMesh::volume(const std::size_t t) const
  {
    const auto           &v = tetrahedra[t];
    const Eigen::Vector3d a = vertices.col(v[1]) - vertices.col(v[0]);
    const Eigen::Vector3d b = vertices.col(v[2]) - vertices.col(v[0]);
    const Eigen::Vector3d c = vertices.col(v[3]) - vertices.col(v[0]);
    return a.cross(b).dot(c) / 6.0;
  }

  double
  SimplexMesh::total_volume() const
  {
    double v = 0;
    for (std::size_t t = 0; t < tetrahedra.size(); ++t)
      v += volume(t);
    return v;
  }

  int
  SimplexMesh::boundary_id(const std::string &name_or_id) const
  {
    for (const auto &[id, name] : boundary_names)
      if (name == name_or_id || std::to_string(id) == name_or_id)
        return id;
    return -1;
  }

  namespace
  {
    /// A face as its sorted vertex triple, packed into one key (vertex indices < 2^21).
    std::uint64_t
    face_key(Triangle f)
    {
      std::sort(f.begin(), f.end());
      return std::uint64_t(f[0]) << 42 | std::uint64_t(f[1]) << 21 | std::uint64_t(f[2]);
    }
  } // namespace

  BoundarySurface
  extract_boundary(const SimplexMesh &mesh)
  {
    if (mesh.vertices.cols() >= (1 << 21))
      throw std::invalid_argument("mesh: more than 2^21 vertices");
    double mean = 0;
    for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
      mean += std::abs(mesh.volume(t));
    mean /= std::max<std::size_t>(1, mesh.tetrahedra.size());
    for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
      if (!(mesh.volume(t) > 1e-12 * mean))
        {
          const auto        &v = mesh.tetrahedra[t];
          std::ostringstream s;
          s << "tetrahedron " << t << " (vertices " << v[0] << ", " << v[1] << ", " << v[2]
            << ", " << v[3] << ") is inverted or degenerate (volume " << mesh.volume(t)
            << " m^3)";
          throw std::invalid_argument(s.str());
        }

    // faces of positively oriented tetrahedra with outward normals (right hand rule)
    struct Face
    {
      Triangle      vertices;
      std::uint32_t count;
    };
    std::unordered_map<std::uint64_t, Face> faces;
    faces.reserve(2 * mesh.tetrahedra.size());
    for (const auto &v : mesh.tetrahedra)
      for (const Triangle f : {Triangle{v[0], v[2], v[1]}, Triangle{v[0], v[1], v[3]},
                               Triangle{v[1], v[2], v[3]}, Triangle{v[0], v[3], v[2]}})
        {
          auto [it, inserted] = faces.try_emplace(face_key(f), Face{f, 0});
          if (++it->second.count > 2)
            throw std::invalid_argument("mesh: a face is shared by more than two tetrahedra");
        }

    std::unordered_map<std::uint64_t, int> tag_of;
    for (std::size_t i = 0; i < mesh.triangles.size(); ++i)
      tag_of[face_key(mesh.triangles[i])] = mesh.triangle_tags[i];

    BoundarySurface surface;
    for (const auto &[key, face] : faces)
      if (face.count == 1)
        {
          surface.triangles.push_back(face.vertices);
          const auto it = tag_of.find(key);
          surface.tags.push_back(it == tag_of.end() ? 0 : it->second);
        }
    // a deterministic order (the hash map's is not): by smallest vertex, then the others
    std::vector<std::size_t> order(surface.triangles.size());
    for (std::size_t i = 0; i < order.size(); ++i)
      order[i] = i;
    std::sort(order.begin(), order.end(), [&](const std::size_t a, const std::size_t b) {
      return face_key(surface.triangles[a]) < face_key(surface.triangles[b]);
    });
    BoundarySurface sorted;
    for (const auto i : order)
      {
        sorted.triangles.push_back(surface.triangles[i]);
        sorted.tags.push_back(surface.tags[i]);
        for (const auto v : surface.triangles[i])
          sorted.vertices.push_back(v);
      }
    std::sort(sorted.vertices.begin(), sorted.vertices.end());
    sorted.vertices.erase(std::unique(sorted.vertices.begin(), sorted.vertices.end()),
                          sorted.vertices.end());
    return sorted;
  }

  std::vector<std::uint32_t>
  vertices_with_tag(const BoundarySurface &surface, const int tag)
  {
    std::vector<std::uint32_t> result;
    for (std::size_t i = 0; i < surface.triangles.size(); ++i)
      if (surface.tags[i] == tag)
        for (const auto v : surface.triangles[i])
          result.push_back(v);
    std::sort(result.begin(), result.end());
    result.erase(std::unique(result.begin(), result.end()), result.end());
    return result;
  }
  std::vector<TrianglePoint>
  subtriangle_centroids(const unsigned n)
  {
    if (n == 0)
      throw std::invalid_argument("subtriangle_centroids: n must be at least 1");
    // sub-triangle (i, j) pointing as the triangle has its centroid at λ₁ = (i + 1/3)/n,
    // λ₂ = (j + 1/3)/n; the one pointing the other way, beside it, at (i + 2/3)/n, (j + 2/3)/n
    std::vector<TrianglePoint> points;
    const double               h = n, w = 1.0 / (h * h);
    const auto add = [&](const double l1, const double l2) { points.push_back({{{1 - l1 - l2, l1, l2}}, w}); };
    if (n == 1) // the centroid exactly
      return {{{{1. / 3, 1. / 3, 1. / 3}}, 1.0}};
    for (unsigned i = 0; i < n; ++i)
      for (unsigned j = 0; i + j < n; ++j)
        {
          add((i + 1. / 3) / h, (j + 1. / 3) / h);
          if (i + j + 1 < n)
            add((i + 2. / 3) / h, (j + 2. / 3) / h);
        }
    return points;
  }
} // namespace suturesim::mesh
