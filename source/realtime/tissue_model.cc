#include <suturesim/realtime/angle_springs.h>
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/tissue_model.h>

#include <algorithm>
#include <sstream>
#include <stdexcept>

namespace suturesim::realtime
{
  void
  declare_bending_parameters(ParameterDeclarations &d)
  {
    d.add_text("Bending points", "",
               "Points near which the nearest surface vertex gets angular bending springs "
               "(seed 003), 'x, y, z; x, y, z; ...'. Unit: m.");
    d.add_real("Bending stiffness factor", 1, 0, 1e6,
               "Angular spring stiffness k = factor * k_e L_a L_b for edges a, b at the "
               "vertex (k_e the mean of their spring stiffnesses): the moment the two "
               "springs resist a lateral motion with. Unit: 1. Range: > 0.");
  }

  double
  TissueMaterial::youngs_modulus_of(const int tag) const
  {
    const auto r = regions.find(tag);
    return r == regions.end() ? youngs_modulus : r->second.first;
  }

  double
  TissueMaterial::bulk_modulus_of(const int tag) const
  {
    const auto r = regions.find(tag);
    return r == regions.end() ? bulk_modulus() : r->second.first / (3 * (1 - 2 * r->second.second));
  }

  double
  TissueMaterial::shear_modulus_of(const int tag) const
  {
    const double E = youngs_modulus_of(tag), K = bulk_modulus_of(tag);
    return 3 * K * E / (9 * K - E);
  }

  std::vector<std::uint32_t>
  TissueModel::add_tetrahedral_nodes(System &s, const mesh::SimplexMesh &mesh, const double density)
  {
    const Matrix3Xd    &X = mesh.vertices;
    std::vector<double> mass(X.cols(), 0.0);
    for (std::size_t t = 0; t < mesh.tetrahedra.size(); ++t)
      for (const auto v : mesh.tetrahedra[t])
        mass[v] += density * mesh.volume(t) / 4;
    for (Eigen::Index v = 0; v < X.cols(); ++v)
      if (mass[v] > 0)
        node_of_vertex[v] = s.nodes.add(X.col(v), mass[v], 0);
    std::vector<std::uint32_t> node(node_of_vertex.begin(), node_of_vertex.end());
    cells.clear();
    for (const auto &t : mesh.tetrahedra)
      cells.push_back({node[t[0]], node[t[1]], node[t[2]], node[t[3]]});
    return node;
  }

  void
  TissueModel::build(System &s, const mesh::SimplexMesh &mesh, const mesh::BoundarySurface &boundary,
                     const TissueMaterial &material, const bool position_based)
  {
    if (s.nodes.size() != 0)
      throw std::logic_error("the tissue is built first, into an empty system");
    node_of_vertex.assign(mesh.vertices.cols(), -1);
    add_body(s, mesh, boundary, material, position_based);
    s.tissue = {0, s.nodes.size()};

    surface_nodes.clear();
    for (const auto &t : boundary.triangles)
      surface_nodes.push_back({std::uint32_t(node_of_vertex[t[0]]), std::uint32_t(node_of_vertex[t[1]]),
                               std::uint32_t(node_of_vertex[t[2]])});
    tags = boundary.tags;

    // bending springs at the surface vertices nearest to the chosen points
    std::stringstream list(bending_points);
    for (std::string item; std::getline(list, item, ';');)
      {
        if (item.find_first_not_of(" \t") == std::string::npos)
          continue;
        std::stringstream coordinates(item);
        Vector3d          p;
        char              comma;
        if (!(coordinates >> p[0] >> comma >> p[1] >> comma >> p[2]))
          throw ParameterError("Bending points", "'" + item + "' is not 'x, y, z'");
        std::uint32_t best = boundary.vertices.front();
        for (const auto v : boundary.vertices)
          if ((mesh.vertices.col(v) - p).squaredNorm() < (mesh.vertices.col(best) - p).squaredNorm())
            best = v;
        add_bending(s, node_of_vertex[best]);
      }
  }

  std::size_t
  TissueModel::add_bending(System &s, const std::uint32_t node)
  {
    // mean stiffness of the springs at the node (any SpringSet of the tissue)
    double      k_sum = 0;
    std::size_t k_count = 0;
    for (const auto &i : s.interactions)
      if (const auto *springs = dynamic_cast<const SpringSet *>(i.get()))
        for (std::size_t e = 0; e < springs->size(); ++e)
          if (springs->first_ends()[e] == node || springs->second_ends()[e] == node)
            {
              k_sum += springs->stiffnesses()[e];
              ++k_count;
            }
    if (k_count == 0)
      return 0;
    const double k_e = k_sum / k_count;

    AngleSprings *angles = nullptr;
    for (const auto &i : s.interactions)
      if (auto *a = dynamic_cast<AngleSprings *>(i.get()))
        angles = a;
    if (angles == nullptr)
      {
        s.interactions.push_back(std::make_unique<AngleSprings>());
        angles = static_cast<AngleSprings *>(s.interactions.back().get());
      }
    std::size_t added = 0;
    for (const auto &t : surface_nodes)
      for (unsigned k = 0; k < 3; ++k)
        if (t[k] == node)
          {
            const std::uint32_t a = t[(k + 1) % 3], b = t[(k + 2) % 3];
            const double la = (s.nodes.x.col(a) - s.nodes.x.col(node)).norm();
            const double lb = (s.nodes.x.col(b) - s.nodes.x.col(node)).norm();
            angles->add(node, a, b, s.nodes.x, bending_factor * k_e * la * lb);
            ++added;
          }
    return added;
  }
} // namespace suturesim::realtime
