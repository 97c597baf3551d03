#include <suturesim/io/checked_output.h>
#include <suturesim/io/polyline_writer.h>

#include <deal.II/base/data_out_base.h>

#include <cerrno>
#include <fstream>
#include <stdexcept>

namespace suturesim::io
{
  void
  write_polyline_vtu(const std::string &file_name, const PolylineData &data, const double time)
  {
    using namespace dealii;
    const std::size_t n_segments = data.points.size() - 1;
    const unsigned    n_fields   = data.point_fields.size() + data.segment_fields.size();
    std::vector<DataOutBase::Patch<1, 3>> patches(n_segments);
    std::vector<std::string>              names;
    for (const auto &[name, values] : data.point_fields)
      names.push_back(name);
    for (const auto &[name, values] : data.segment_fields)
      names.push_back(name);
    for (std::size_t s = 0; s < n_segments; ++s)
      {
        auto &p = patches[s];
        for (unsigned v = 0; v < 2; ++v)
          p.vertices[v] = Point<3>(data.points[s + v][0], data.points[s + v][1], data.points[s + v][2]);
        p.patch_index    = s;
        p.n_subdivisions = 1;
        p.reference_cell = ReferenceCells::Line;
        p.data.reinit(n_fields, 2);
        unsigned f = 0;
        for (const auto &[name, values] : data.point_fields)
          {
            p.data(f, 0) = values[s];
            p.data(f, 1) = values[s + 1];
            ++f;
          }
        for (const auto &[name, values] : data.segment_fields)
          {
            p.data(f, 0) = p.data(f, 1) = values[s];
            ++f;
          }
      }
    DataOutBase::VtkFlags flags(time);
    errno = 0;
    std::ofstream         out(file_name);
    if (!out)
      throw WriteError(file_name + ": cannot be written (cannot open)");
    DataOutBase::write_vtu(patches, names, {}, flags, out);
    check_written(out, file_name);
  }
} // namespace suturesim::io
