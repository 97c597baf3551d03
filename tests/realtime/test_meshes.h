#pragma once
// Small tetrahedral meshes built in the tests, so that the realtime library's tests need
// neither gmsh nor deal.II.
#include <suturesim/mesh/simplex_mesh.h>

#include <array>

namespace suturesim::test_support
{
  /// A box [0, a] × [0, b] × [0, c] of nx × ny × nz cubes, each split into six
  /// tetrahedra around its main diagonal (Kuhn's subdivision: conforming across faces).
  /// Boundary triangles are tagged 1 (z = 0, "bottom"), 2 (z = c, "top"), 3 (sides).
  inline mesh::SimplexMesh
  box_mesh(const double a, const double b, const double c, const unsigned nx, const unsigned ny,
           const unsigned nz)
  {
    mesh::SimplexMesh m;
    const auto index = [&](unsigned i, unsigned j, unsigned k) {
      return std::uint32_t(i + (nx + 1) * (j + (ny + 1) * k));
    };
    m.vertices.resize(3, (nx + 1) * (ny + 1) * (nz + 1));
    for (unsigned k = 0; k <= nz; ++k)
      for (unsigned j = 0; j <= ny; ++j)
        for (unsigned i = 0; i <= nx; ++i)
          m.vertices.col(index(i, j, k)) << a * i / nx, b * j / ny, c * k / nz;
    const unsigned permutations[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2},
                                         {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
    for (unsigned k = 0; k < nz; ++k)
      for (unsigned j = 0; j < ny; ++j)
        for (unsigned i = 0; i < nx; ++i)
          for (const auto &p : permutations)
            {
              std::array<unsigned, 3> corner{{i, j, k}};
              mesh::Tetrahedron       t;
              t[0] = index(corner[0], corner[1], corner[2]);
              for (unsigned s = 0; s < 3; ++s)
                {
                  ++corner[p[s]];
                  t[s + 1] = index(corner[0], corner[1], corner[2]);
                }
              m.tetrahedra.push_back(t);
              if (m.volume(m.tetrahedra.size() - 1) < 0)
                std::swap(m.tetrahedra.back()[1], m.tetrahedra.back()[2]);
              m.tetrahedron_tags.push_back(1);
            }
    // tag the boundary by position
    const auto surface = mesh::extract_boundary(m);
    for (const auto &t : surface.triangles)
      {
        double z = 0, zmax = 0;
        for (const auto v : t)
          {
            z += m.vertices(2, v) / 3;
            zmax = std::max(zmax, std::abs(m.vertices(2, v) - m.vertices(2, t[0])));
          }
        m.triangles.push_back(t);
        m.triangle_tags.push_back(zmax > 1e-12 * c ? 3 : (z < 0.5 * c ? 1 : 2));
      }
    m.boundary_names = {{1, "bottom"}, {2, "top"}, {3, "sides"}};
    m.material_names = {{1, "tissue"}};
    return m;
  }
} // namespace suturesim::test_support
