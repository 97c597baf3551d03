#include <suturesim/io/checked_output.h>
#include <suturesim/io/surface_field.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <map>
#include <stdexcept>

namespace suturesim::io
{
  SurfaceField
  SurfaceField::of(const double time, const Eigen::Ref<const Eigen::Matrix3Xd> &X,
                   const Eigen::Ref<const Eigen::Matrix3Xd> &u, const std::vector<std::array<std::uint32_t, 3>> &triangles)
  {
    SurfaceField                           s;
    std::map<std::uint32_t, std::uint32_t> index;
    std::vector<std::uint32_t>             used;
    s.time = time;
    for (const auto &t : triangles)
      {
        std::array<std::uint32_t, 3> local{};
        for (int k = 0; k < 3; ++k)
          {
            const auto [it, added] = index.try_emplace(t[k], static_cast<std::uint32_t>(used.size()));
            if (added)
              used.push_back(t[k]);
            local[k] = it->second;
          }
        s.triangles.push_back(local);
      }
    s.reference.resize(3, used.size());
    s.displacement.resize(3, used.size());
    for (std::size_t i = 0; i < used.size(); ++i)
      {
        s.reference.col(i)    = X.col(used[i]);
        s.displacement.col(i) = u.col(used[i]);
      }
    return s;
  }

  void
  SurfaceField::write(const std::string &file) const
  {
    nlohmann::json j{{"time", time}};
    auto          &X = j["reference"] = nlohmann::json::array();
    auto          &u = j["displacement"] = nlohmann::json::array();
    for (Eigen::Index i = 0; i < reference.cols(); ++i)
      {
        X.push_back({reference(0, i), reference(1, i), reference(2, i)});
        u.push_back({displacement(0, i), displacement(1, i), displacement(2, i)});
      }
    j["triangles"] = triangles;
    write_whole(file, j.dump() + '\n');
  }

  SurfaceField
  SurfaceField::read(const std::string &file)
  {
    std::ifstream in(file);
    if (!in)
      throw std::runtime_error(file + ": cannot be read");
    try
      {
        const auto   j = nlohmann::json::parse(in);
        SurfaceField s;
        s.time       = j.at("time").get<double>();
        const auto X = j.at("reference").get<std::vector<std::array<double, 3>>>();
        const auto u = j.at("displacement").get<std::vector<std::array<double, 3>>>();
        s.triangles  = j.at("triangles").get<std::vector<std::array<std::uint32_t, 3>>>();
        if (X.size() != u.size())
          throw std::runtime_error("reference and displacement differ in length");
        s.reference.resize(3, X.size());
        s.displacement.resize(3, X.size());
        for (std::size_t i = 0; i < X.size(); ++i)
          for (int c = 0; c < 3; ++c)
            s.reference(c, i) = X[i][c], s.displacement(c, i) = u[i][c];
        for (const auto &t : s.triangles)
          for (const auto k : t)
            if (k >= X.size())
              throw std::runtime_error("a triangle's vertex " + std::to_string(k) + " is out of range");
        return s;
      }
    catch (const nlohmann::json::exception &e)
      {
        throw std::runtime_error(file + ": " + e.what());
      }
    catch (const std::runtime_error &e)
      {
        throw std::runtime_error(file + ": " + e.what());
      }
  }
} // namespace suturesim::io
