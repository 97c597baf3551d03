#include <suturesim/io/checked_output.h>
#include <suturesim/io/simplex_writer.h>

#include <zlib.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace suturesim::io
{
  namespace
  {
    /// Appends the base64 text of @p n bytes (RFC 4648, with padding).
    void
    append_base64(std::string &out, const unsigned char *bytes, const std::size_t n)
    {
      static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
      out.reserve(out.size() + 4 * ((n + 2) / 3));
      for (std::size_t k = 0; k < n; k += 3)
        {
          const std::uint32_t a = bytes[k], b = k + 1 < n ? bytes[k + 1] : 0, c = k + 2 < n ? bytes[k + 2] : 0;
          const std::uint32_t w = (a << 16) | (b << 8) | c;
          out += digits[(w >> 18) & 63];
          out += digits[(w >> 12) & 63];
          out += k + 1 < n ? digits[(w >> 6) & 63] : '=';
          out += k + 2 < n ? digits[w & 63] : '=';
        }
    }

    /// One binary DataArray: @p bytes bytes at @p data, deflated in blocks; the header
    /// (number of blocks, block size, size of a partial last block or 0, each block's
    /// compressed size) as UInt32 words in base64 of its own, then the blocks in one run.
    void
    append_array(std::string &out, const std::string &attributes, const void *data, const std::size_t bytes)
    {
      constexpr std::size_t block = std::size_t(1) << 20;
      const std::size_t     n     = (bytes + block - 1) / block;
      if (bytes > std::numeric_limits<std::uint32_t>::max() / 2)
        throw std::invalid_argument("write_simplex_vtu: an array of " + std::to_string(bytes) +
                                    " bytes exceeds the UInt32 header");
      std::vector<std::uint32_t> header{std::uint32_t(n), std::uint32_t(block), std::uint32_t(bytes % block)};
      std::string                deflated;
      std::vector<unsigned char> buffer(compressBound(block));
      const auto                *in = static_cast<const unsigned char *>(data);
      for (std::size_t b = 0; b < n; ++b)
        {
          const std::size_t size   = std::min(block, bytes - b * block);
          uLongf            length = buffer.size();
          if (compress2(buffer.data(), &length, in + b * block, size, 1) != Z_OK)
            throw std::runtime_error("write_simplex_vtu: zlib could not deflate a block");
          header.push_back(std::uint32_t(length));
          deflated.append(reinterpret_cast<const char *>(buffer.data()), length);
        }
      out += "<DataArray " + attributes + " format=\"binary\">\n";
      append_base64(out, reinterpret_cast<const unsigned char *>(header.data()), header.size() * sizeof(std::uint32_t));
      append_base64(out, reinterpret_cast<const unsigned char *>(deflated.data()), deflated.size());
      out += "\n</DataArray>\n";
    }

    /// Float32 copy of the 3 x n or 1 x n values (the precision deal.II writes too).
    template <typename Matrix>
    std::vector<float>
    as_float(const Matrix &m)
    {
      std::vector<float> v(m.size());
      for (Eigen::Index k = 0; k < m.size(); ++k)
        v[k] = static_cast<float>(m.data()[k]);
      return v;
    }

    template <typename T>
    void
    append_values(std::string &out, const std::string &attributes, const std::vector<T> &v)
    {
      append_array(out, attributes, v.data(), v.size() * sizeof(T));
    }
  } // namespace

  template <std::size_t n_vertices>
  void
  write_simplex_vtu(const std::string &file_name, const SimplexData<n_vertices> &data, const double time)
  {
    const std::size_t n_points = data.points.cols(), n_cells = data.cells.size();
    if (n_points > std::size_t(std::numeric_limits<std::int32_t>::max()) ||
        n_vertices * n_cells > std::size_t(std::numeric_limits<std::int32_t>::max()))
      throw std::invalid_argument("write_simplex_vtu: more points or cells than Int32 indices address");
    std::vector<std::int32_t> connectivity, offsets(n_cells);
    connectivity.reserve(n_vertices * n_cells);
    for (std::size_t c = 0; c < n_cells; ++c)
      {
        for (const auto i : data.cells[c])
          {
            if (i >= n_points)
              throw std::invalid_argument("write_simplex_vtu: cell " + std::to_string(c) + " names point " +
                                          std::to_string(i) + " of " + std::to_string(n_points));
            connectivity.push_back(std::int32_t(i));
          }
        offsets[c] = std::int32_t(n_vertices * (c + 1));
      }
    // VTK_TETRA = 10, VTK_TRIANGLE = 5
    const std::vector<std::uint8_t> types(n_cells, n_vertices == 4 ? 10 : 5);

    std::ostringstream head;
    head.precision(std::numeric_limits<double>::max_digits10);
    head << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
            "header_type=\"UInt32\" compressor=\"vtkZLibDataCompressor\">\n<UnstructuredGrid>\n"
         << "<FieldData>\n<DataArray type=\"Float64\" Name=\"TIME\" NumberOfTuples=\"1\" format=\"ascii\">" << time
         << "</DataArray>\n</FieldData>\n<Piece NumberOfPoints=\"" << n_points << "\" NumberOfCells=\"" << n_cells
         << "\">\n<Points>\n";
    std::string text = head.str();
    append_values(text, "type=\"Float32\" NumberOfComponents=\"3\"", as_float(data.points));
    text += "</Points>\n<Cells>\n";
    append_values(text, "type=\"Int32\" Name=\"connectivity\"", connectivity);
    append_values(text, "type=\"Int32\" Name=\"offsets\"", offsets);
    append_values(text, "type=\"UInt8\" Name=\"types\"", types);
    text += "</Cells>\n<PointData";
    if (!data.vector_fields.empty())
      text += " Vectors=\"" + data.vector_fields.front().first + "\"";
    text += ">\n";
    for (const auto &[name, values] : data.vector_fields)
      {
        if (std::size_t(values.cols()) != n_points)
          throw std::invalid_argument("write_simplex_vtu: field '" + name + "' has another number of points");
        append_values(text, "type=\"Float32\" Name=\"" + name + "\" NumberOfComponents=\"3\"", as_float(values));
      }
    for (const auto &[name, values] : data.scalar_fields)
      {
        if (std::size_t(values.size()) != n_points)
          throw std::invalid_argument("write_simplex_vtu: field '" + name + "' has another number of points");
        append_values(text, "type=\"Float32\" Name=\"" + name + "\"", as_float(values));
      }
    text += "</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";

    errno = 0;
    std::ofstream out(file_name, std::ios::binary);
    if (!out)
      throw WriteError(file_name + ": cannot be written (cannot open)");
    out.write(text.data(), std::streamsize(text.size()));
    check_written(out, file_name);
  }

  template void
  write_simplex_vtu<3>(const std::string &, const SimplexData<3> &, double);
  template void
  write_simplex_vtu<4>(const std::string &, const SimplexData<4> &, double);
} // namespace suturesim::io
