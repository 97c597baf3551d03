#include <suturesim/collision/proximity.h>
#include <suturesim/coupling/accurate/wound_contact.h>
#include <suturesim/io/state_json.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <limits>
#include <set>
#include <stdexcept>

namespace suturesim::coupling
{
  using namespace dealii;

  WoundContact::WoundContact(const WoundContactParameters &parameters, const Eigen::Matrix3Xd &X0,
                             const std::vector<std::array<std::uint32_t, 3>> &triangles,
                             const std::vector<types::boundary_id> &ids, const types::boundary_id a,
                             const types::boundary_id b)
    : prm(parameters)
    , reference(X0)
  {
    std::set<std::uint32_t>    on_a, on_b;
    std::vector<std::size_t>   b_triangles;
    for (std::size_t t = 0; t < triangles.size(); ++t)
      {
        if (ids[t] == a)
          on_a.insert(triangles[t].begin(), triangles[t].end());
        if (ids[t] == b)
          {
            on_b.insert(triangles[t].begin(), triangles[t].end());
            b_triangles.push_back(t);
          }
      }
    if (on_a.empty() || b_triangles.empty())
      throw std::invalid_argument("wound contact: boundary " + std::to_string(on_a.empty() ? a : b) +
                                  " has no faces");
    for (const std::uint32_t v : on_a)
      {
        if (on_b.count(v))
          continue; // the incision's front, shared by both faces
        const Eigen::Vector3d p = reference.col(v);
        Pair                  best;
        double                nearest = std::numeric_limits<double>::infinity();
        for (const std::size_t t : b_triangles)
          {
            const auto           &tri = triangles[t];
            Eigen::Vector3d       w;
            const Eigen::Vector3d q =
              collision::closest_point_on_triangle(p, reference.col(tri[0]), reference.col(tri[1]),
                                                   reference.col(tri[2]), w);
            if ((p - q).norm() < nearest)
              {
                nearest      = (p - q).norm();
                best.vertex   = v;
                best.triangle = tri;
                best.weights  = w;
                best.normal   = (reference.col(tri[1]) - reference.col(tri[0]))
                                 .cross(reference.col(tri[2]) - reference.col(tri[0]))
                                 .normalized();
              }
          }
        all.push_back(best);
      }
  }

  bool
  WoundContact::detect(const Eigen::Matrix3Xd &surface)
  {
    std::vector<std::size_t> next;
    for (std::size_t j = 0; j < all.size(); ++j)
      {
        const Pair           &c = all[j];
        const Eigen::Vector3d q = c.weights[0] * surface.col(c.triangle[0]) + c.weights[1] * surface.col(c.triangle[1]) +
                                  c.weights[2] * surface.col(c.triangle[2]);
        if ((surface.col(c.vertex) - q).dot(c.normal) < prm.margin)
          next.push_back(j);
      }
    if (next == active)
      return false;
    active = next;
    adopt();
    seen = X;
    return true;
  }

  void
  WoundContact::adopt()
  {
    // P of each loaded pair, then their Q
    X.clear();
    for (const bool on_b : {false, true})
      for (const std::size_t j : active)
        {
          const Pair           &c = all[j];
          const Eigen::Vector3d v = on_b ? Eigen::Vector3d(c.weights[0] * reference.col(c.triangle[0]) +
                                                           c.weights[1] * reference.col(c.triangle[1]) +
                                                           c.weights[2] * reference.col(c.triangle[2]))
                                         : Eigen::Vector3d(reference.col(c.vertex));
          X.emplace_back(v[0], v[1], v[2]);
        }
  }

  nlohmann::json
  WoundContact::snapshot() const
  {
    nlohmann::json positions = nlohmann::json::array();
    for (const auto &p : seen)
      positions.push_back(io::triple(p));
    return {{"active", active}, {"seen", positions}, {"touching", touching}, {"pressing", pressing}};
  }

  void
  WoundContact::save()
  {
    saved = {active, seen, touching, pressing};
  }

  void
  WoundContact::restore()
  {
    active = saved.active;
    adopt();
    seen     = saved.seen;
    touching = saved.touching;
    pressing = saved.pressing;
  }

  void
  WoundContact::restore(const nlohmann::json &j)
  {
    active = j.at("active").get<std::vector<std::size_t>>();
    adopt();
    seen.clear();
    for (const auto &p : j.at("seen"))
      seen.push_back(io::triple_as<dealii::Point<3>>(p));
    touching = j.at("touching").get<unsigned>();
    pressing = j.at("pressing").get<double>();
  }

  double
  WoundContact::gap(const std::size_t j, const Point<3> &p, const Point<3> &q) const
  {
    const Eigen::Vector3d &n = all[active[j]].normal;
    return (p[0] - q[0]) * n[0] + (p[1] - q[1]) * n[1] + (p[2] - q[2]) * n[2];
  }

  double
  WoundContact::least_gap() const
  {
    double least = std::numeric_limits<double>::infinity();
    for (std::size_t j = 0; j < active.size(); ++j)
      least = std::min(least, gap(j, seen[j], seen[active.size() + j]));
    return least;
  }

  void
  WoundContact::force(const std::size_t k, const Point<3> &x, Tensor<1, 3> &f, Tensor<2, 3> &df_dx) const
  {
    // P of pair j at k = j, its Q at k = m + j; the partner where equilibrate() saw it
    const std::size_t m = active.size();
    const std::size_t j = k < m ? k : k - m;
    const double      g = k < m ? gap(j, x, seen[m + j]) : gap(j, seen[j], x);
    f                   = 0;
    df_dx               = 0;
    if (g >= 0)
      return;
    Tensor<1, 3> n;
    for (unsigned d = 0; d < 3; ++d)
      n[d] = all[active[j]].normal[d];
    // f_P = −k g n pushes P back out along n; f_Q its opposite. Either way ∂f/∂x of the
    // point itself is −k n nᵀ
    f     = (k < m ? -1.0 : 1.0) * prm.stiffness * g * n;
    df_dx = -prm.stiffness * outer_product(n, n);
  }

  std::vector<std::size_t>
  WoundContact::coupled_points() const
  {
    std::vector<std::size_t> points(X.size());
    for (std::size_t k = 0; k < X.size(); ++k)
      points[k] = offset + k;
    return points;
  }

  bool
  WoundContact::equilibrate(const std::vector<Point<3>> &x, Eigen::MatrixXd &G, std::string &)
  {
    const std::size_t m = active.size();
    for (std::size_t k = 0; k < X.size(); ++k)
      seen[k] = x[offset + k];
    // the tissue's tangent takes −∂f/∂x; the point loads give each point's own block,
    // G the blocks between P and Q: −∂f_P/∂x_Q = −∂f_Q/∂x_P = −k n nᵀ in contact
    G.setZero(3 * X.size(), 3 * X.size());
    touching = 0;
    pressing = 0;
    for (std::size_t j = 0; j < m; ++j)
      {
        const double g = gap(j, seen[j], seen[m + j]);
        if (g >= 0)
          continue;
        ++touching;
        pressing += -prm.stiffness * g;
        const Eigen::Vector3d &n     = all[active[j]].normal;
        const Eigen::Matrix3d  cross = -prm.stiffness * n * n.transpose();
        G.block<3, 3>(3 * j, 3 * (m + j)) = cross;
        G.block<3, 3>(3 * (m + j), 3 * j) = cross;
      }
    return true;
  }
} // namespace suturesim::coupling
