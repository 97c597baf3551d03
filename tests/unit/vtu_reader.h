#pragma once
// Reads back the .vtu files a run writes (VTK XML UnstructuredGrid, as deal.II's
// DataOutBase writes them): the piece's sizes and every DataArray decoded, so that tests
// check the fields' names, sizes and values rather than the files' existence.
// Formats: "ascii", and "binary" (base64) raw or zlib-compressed
// (compressor="vtkZLibDataCompressor": a header of UInt32 or UInt64 words — number of
// blocks, block size, size of the last block, compressed size of each block — encoded
// in base64 on its own, then the compressed blocks in one base64 run; VTK file formats,
// "XML File Formats", Kitware).
#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace suturesim::test_support
{
  struct VtuArray
  {
    std::string         name, type, section; ///< section: Points, Cells, PointData, CellData, FieldData
    unsigned            components = 1;
    std::vector<double> values;

    std::size_t
    tuples() const
    {
      return values.size() / components;
    }
  };

  struct Vtu
  {
    std::size_t           n_points = 0, n_cells = 0;
    std::vector<VtuArray> arrays; ///< in the file's order

    /// The array @p name of @p section; throws if there is none.
    const VtuArray &
    get(const std::string &section, const std::string &name) const
    {
      for (const auto &a : arrays)
        if (a.section == section && a.name == name)
          return a;
      throw std::runtime_error("no " + section + " array '" + name + "'");
    }
    /// The coordinates (Points has one unnamed array).
    const VtuArray &
    points() const
    {
      for (const auto &a : arrays)
        if (a.section == "Points")
          return a;
      throw std::runtime_error("no Points");
    }
    std::vector<std::string>
    names(const std::string &section) const
    {
      std::vector<std::string> n;
      for (const auto &a : arrays)
        if (a.section == section)
          n.push_back(a.name);
      return n;
    }
  };

  namespace vtu_detail
  {
    inline std::string
    attribute(const std::string &tag, const std::string &key)
    {
      const std::string pattern = " " + key + "=\"";
      const auto        start   = tag.find(pattern);
      if (start == std::string::npos)
        return "";
      const auto begin = start + pattern.size();
      return tag.substr(begin, tag.find('"', begin) - begin);
    }

    inline std::vector<unsigned char>
    base64(const std::string &text)
    {
      static const std::string alphabet =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
      std::vector<unsigned char> out;
      unsigned                   buffer = 0;
      int                        bits   = 0;
      for (const char c : text)
        {
          if (c == '=')
            break;
          const auto v = alphabet.find(c);
          if (v == std::string::npos)
            continue; // white space
          buffer = (buffer << 6) | static_cast<unsigned>(v);
          bits += 6;
          if (bits >= 8)
            {
              bits -= 8;
              out.push_back(static_cast<unsigned char>((buffer >> bits) & 0xff));
            }
        }
      return out;
    }

    /// Length of the base64 text of @p bytes bytes (with padding).
    inline std::size_t
    encoded_length(const std::size_t bytes)
    {
      return 4 * ((bytes + 2) / 3);
    }

    template <typename T>
    void
    append(const std::vector<unsigned char> &bytes, std::vector<double> &values)
    {
      for (std::size_t k = 0; k + sizeof(T) <= bytes.size(); k += sizeof(T))
        {
          T v;
          std::memcpy(&v, bytes.data() + k, sizeof(T));
          values.push_back(static_cast<double>(v));
        }
    }

    inline std::vector<double>
    convert(const std::string &type, const std::vector<unsigned char> &bytes)
    {
      std::vector<double> v;
      if (type == "Float32")
        append<float>(bytes, v);
      else if (type == "Float64")
        append<double>(bytes, v);
      else if (type == "Int32")
        append<std::int32_t>(bytes, v);
      else if (type == "UInt32")
        append<std::uint32_t>(bytes, v);
      else if (type == "Int64")
        append<std::int64_t>(bytes, v);
      else if (type == "UInt64")
        append<std::uint64_t>(bytes, v);
      else if (type == "UInt8")
        append<std::uint8_t>(bytes, v);
      else
        throw std::runtime_error("DataArray type " + type);
      return v;
    }

    /// The payload of a binary DataArray.
    inline std::vector<unsigned char>
    decode(const std::string &text, const bool compressed, const std::size_t word)
    {
      const auto read_word = [&](const std::vector<unsigned char> &b, const std::size_t k) {
        std::uint64_t v = 0;
        std::memcpy(&v, b.data() + k * word, word); // little endian, as the files say
        return static_cast<std::size_t>(v);
      };
      if (!compressed)
        {
          const auto all = base64(text);
          return std::vector<unsigned char>(all.begin() + word, all.begin() + word + read_word(all, 0));
        }
      const std::size_t blocks      = read_word(base64(text.substr(0, encoded_length(word))), 0);
      const std::size_t header_text = encoded_length((3 + blocks) * word);
      const auto        header      = base64(text.substr(0, header_text));
      const std::size_t block_size = read_word(header, 1), last = read_word(header, 2);
      const auto        data = base64(text.substr(header_text));
      std::vector<unsigned char> out;
      std::size_t                at = 0;
      for (std::size_t b = 0; b < blocks; ++b)
        {
          const std::size_t compressed_size = read_word(header, 3 + b);
          uLongf size = (b + 1 == blocks && last != 0) ? last : block_size;
          std::vector<unsigned char> block(size);
          if (uncompress(block.data(), &size, data.data() + at, compressed_size) != Z_OK)
            throw std::runtime_error("zlib cannot inflate a block");
          out.insert(out.end(), block.begin(), block.begin() + size);
          at += compressed_size;
        }
      return out;
    }
  } // namespace vtu_detail

  /// Reads @p file; throws std::runtime_error when it cannot.
  inline Vtu
  read_vtu(const std::string &file)
  {
    using namespace vtu_detail;
    std::ifstream in(file);
    if (!in)
      throw std::runtime_error("cannot open " + file);
    std::stringstream s;
    s << in.rdbuf();
    const std::string text = s.str();
    const auto        head = text.substr(text.find("<VTKFile"), text.find('>', text.find("<VTKFile")) -
                                                             text.find("<VTKFile"));
    const bool        compressed = attribute(head, "compressor") == "vtkZLibDataCompressor";
    const std::size_t word       = attribute(head, "header_type") == "UInt64" ? 8 : 4;
    Vtu               vtu;
    std::string       section;
    for (std::size_t at = text.find('<'); at != std::string::npos; at = text.find('<', at + 1))
      {
        const std::size_t close = text.find('>', at);
        const std::string tag   = text.substr(at, close - at);
        for (const char *name : {"Points", "Cells", "PointData", "CellData", "FieldData"})
          if (tag == std::string("<") + name || tag.rfind(std::string("<") + name + " ", 0) == 0)
            section = name;
        if (tag.rfind("<Piece", 0) == 0)
          {
            vtu.n_points = std::stoul(attribute(tag, "NumberOfPoints"));
            vtu.n_cells  = std::stoul(attribute(tag, "NumberOfCells"));
          }
        if (tag.rfind("<DataArray", 0) != 0)
          continue;
        VtuArray a;
        a.name    = attribute(tag, "Name");
        a.type    = attribute(tag, "type");
        a.section = section;
        if (const auto c = attribute(tag, "NumberOfComponents"); !c.empty())
          a.components = std::stoul(c);
        const std::size_t end     = text.find("</DataArray>", close);
        const std::string payload = text.substr(close + 1, end - close - 1);
        if (attribute(tag, "format") == "ascii")
          {
            std::stringstream numbers(payload);
            for (double v; numbers >> v;)
              a.values.push_back(v);
          }
        else
          {
            const auto first = payload.find_first_not_of(" \t\r\n");
            const auto last  = payload.find_last_not_of(" \t\r\n");
            a.values         = convert(a.type, decode(payload.substr(first, last - first + 1), compressed, word));
          }
        vtu.arrays.push_back(std::move(a));
        at = end;
      }
    return vtu;
  }
} // namespace suturesim::test_support
