#include <suturesim/io/checked_output.h>
#include <suturesim/io/simplex_writer.h>

#include <deal.II/base/data_out_base.h>

#include <cerrno>
#include <fstream>
#include <stdexcept>
#include <tuple>

namespace suturesim::io
{
  template <std::size_t n_vertices>
  void
  write_simplex_vtu(const std::string &file_name, const SimplexData<n_vertices> &data,
                    const double time)
  {
    using namespace dealii;
    constexpr int dim = n_vertices - 1;
    std::vector<std::string> names;
    std::vector<std::tuple<unsigned int, unsigned int, std::string,
                           DataComponentInterpretation::DataComponentInterpretation>>
      vectors;
    for (const auto &[name, values] : data.vector_fields)
      {
        vectors.emplace_back(names.size(), names.size() + 2, name,
                             DataComponentInterpretation::component_is_part_of_vector);
        for (const char c : {'x', 'y', 'z'})
          names.push_back(name + "_" + std::string(1, c));
      }
    for (const auto &[name, values] : data.scalar_fields)
      names.push_back(name);

    std::vector<DataOutBase::Patch<dim, 3>> patches(data.cells.size());
    for (std::size_t c = 0; c < data.cells.size(); ++c)
      {
        auto &p          = patches[c];
        p.patch_index    = c;
        p.n_subdivisions = 1;
        p.reference_cell = dim == 3 ? ReferenceCells::Tetrahedron : ReferenceCells::Triangle;
        p.data.reinit(names.size(), n_vertices);
        for (std::size_t v = 0; v < n_vertices; ++v)
          {
            const auto i  = data.cells[c][v];
            p.vertices[v] = Point<3>(data.points(0, i), data.points(1, i), data.points(2, i));
            unsigned f    = 0;
            for (const auto &[name, values] : data.vector_fields)
              for (int d = 0; d < 3; ++d)
                p.data(f++, v) = values(d, i);
            for (const auto &[name, values] : data.scalar_fields)
              p.data(f++, v) = values[i];
          }
      }
    DataOutBase::VtkFlags flags(time);
    errno = 0;
    std::ofstream         out(file_name);
    if (!out)
      throw WriteError(file_name + ": cannot be written (cannot open)");
    DataOutBase::write_vtu(patches, names, vectors, flags, out);
    check_written(out, file_name);
  }

  template void
  write_simplex_vtu<3>(const std::string &, const SimplexData<3> &, double);
  template void
  write_simplex_vtu<4>(const std::string &, const SimplexData<4> &, double);
} // namespace suturesim::io
