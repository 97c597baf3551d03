// TissueModel: the boundary as a triangle surface (for the needle's puncture and
// contact, which both paths decide on triangles: coupling/needle_puncture.h).
#include <suturesim/tissue/tissue_model.h>

#include <deal.II/base/mpi.h>

#include <algorithm>
#include <map>
#include <stdexcept>

namespace suturesim::tissue
{
  using namespace dealii;

  BoundarySurface
  TissueModel::boundary_surface() const
  {
    // every rank lists the boundary faces of its cells: corner positions and DoFs, and
    // whether corners 0, 1, 3, 2 go round it inward (flat arrays: what MPI gathers)
    std::vector<double>                  corner;
    std::vector<types::global_dof_index> dof;
    std::vector<int>                     flip, id;
    for (const auto &cell : dof_handler.active_cell_iterators())
      if (cell->is_locally_owned())
        for (const auto f : cell->face_indices())
          if (cell->face(f)->at_boundary())
            {
              const auto face = cell->face(f);
              for (unsigned v = 0; v < 4; ++v)
                for (unsigned c = 0; c < 3; ++c)
                  {
                    corner.push_back(face->vertex(v)[c]);
                    dof.push_back(face->vertex_dof_index(v, c));
                  }
              const Tensor<1, 3> n = cross_product_3d(face->vertex(1) - face->vertex(0),
                                                      face->vertex(3) - face->vertex(0));
              flip.push_back(n * (face->center() - cell->center()) < 0);
              id.push_back(face->boundary_id());
            }
    struct Face
    {
      std::array<Point<3>, 4>                                X;
      std::array<std::array<types::global_dof_index, 3>, 4> dofs;
      bool                                                   flip;
      types::boundary_id                                     id;
    };
    std::vector<Face> all;
    const auto        corners  = Utilities::MPI::all_gather(comm, corner);
    const auto        dofs     = Utilities::MPI::all_gather(comm, dof);
    const auto        flips    = Utilities::MPI::all_gather(comm, flip);
    const auto        ids      = Utilities::MPI::all_gather(comm, id);
    for (std::size_t r = 0; r < flips.size(); ++r)
      for (std::size_t f = 0; f < flips[r].size(); ++f)
        {
          Face g;
          for (unsigned v = 0; v < 4; ++v)
            for (unsigned c = 0; c < 3; ++c)
              {
                g.X[v][c]    = corners[r][12 * f + 3 * v + c];
                g.dofs[v][c] = dofs[r][12 * f + 3 * v + c];
              }
          g.flip = flips[r][f];
          g.id   = static_cast<types::boundary_id>(ids[r][f]);
          all.push_back(g);
        }

    BoundarySurface           s;
    // vertices by their first DoF, which every rank numbers alike (vertex numbers of a
    // refined distributed mesh are each rank's own)
    std::map<types::global_dof_index, std::uint32_t> index;
    std::vector<Point<3>>     X;
    const auto                node = [&](const Face &g, const unsigned v) {
      const auto [it, added] = index.try_emplace(g.dofs[v][0], static_cast<std::uint32_t>(X.size()));
      if (added)
        {
          X.push_back(g.X[v]);
          s.dofs.push_back(g.dofs[v]);
        }
      return it->second;
    };
    for (const auto &g : all)
      {
        const std::uint32_t a = node(g, 0), b = node(g, 1), c = node(g, 3), d = node(g, 2);
        if (!g.flip)
          {
            s.triangles.push_back({{a, b, c}});
            s.triangles.push_back({{a, c, d}});
          }
        else
          {
            s.triangles.push_back({{a, c, b}});
            s.triangles.push_back({{a, d, c}});
          }
        s.ids.insert(s.ids.end(), 2, g.id);
      }
    s.reference.resize(3, X.size());
    for (std::size_t i = 0; i < X.size(); ++i)
      for (unsigned c = 0; c < 3; ++c)
        s.reference(c, i) = X[i][c];
    return s;
  }

  void
  TissueModel::surface_positions(const BoundarySurface &s, Eigen::Matrix3Xd &x) const
  {
    // each DoF's owner contributes its value, the sum over ranks gives everyone all
    std::vector<double> u(3 * s.dofs.size(), 0.0);
    for (std::size_t i = 0; i < s.dofs.size(); ++i)
      for (unsigned c = 0; c < 3; ++c)
        if (locally_owned_dofs.is_element(s.dofs[i][c]))
          u[3 * i + c] = solution[s.dofs[i][c]];
    Utilities::MPI::sum(u, comm, u);
    x = s.reference;
    for (std::size_t i = 0; i < s.dofs.size(); ++i)
      for (unsigned c = 0; c < 3; ++c)
        x(c, i) += u[3 * i + c];
  }
} // namespace suturesim::tissue
