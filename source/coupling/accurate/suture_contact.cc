#include <suturesim/collision/proximity.h>
#include <suturesim/coupling/accurate/suture_contact.h>
#include <suturesim/io/state_json.h>

#include <algorithm>
#include <stdexcept>

namespace suturesim::coupling
{
  using namespace dealii;

  SutureContact::SutureContact(const SutureContactParameters &parameters,
                               const std::vector<mesh::Triangle> &surface, const Eigen::Matrix3Xd &X0)
    : prm(parameters)
    , triangles(surface)
    , reference(X0)
  {
    if (!(prm.stiffness > 0) || !(prm.radius > 0) || !(prm.depth > 0) || !(prm.smoothing >= 0))
      throw std::invalid_argument("suture contact: stiffness, radius and depth must be > 0, smoothing >= 0");
    // leaves grown by the farther of the two reaches, outside (1.25 r) and inside (depth)
    tree.build(X0, triangles, std::max(1.25 * prm.radius, prm.depth));
  }

  bool
  SutureContact::detect(const Eigen::Matrix3Xd &surface, const std::vector<rod::Vec3> &nodes,
                        const std::vector<char> &skip, const bool grow_only)
  {
    // the tissue moves little between detections: a lazy refit with a slack of r
    tree.update(surface, prm.radius);
    std::vector<Contact> found;
    for (std::size_t i = 0; i < nodes.size(); ++i)
      {
        if (i < skip.size() && skip[i])
          continue;
        tree.leaves_near(nodes[i], 0, candidates);
        collision::NearestTriangle near;
        for (const auto leaf : candidates)
          {
            const std::uint32_t t = tree.triangle(leaf);
            const auto         &v = triangles[t];
            near.offer(nodes[i], t, surface.col(v[0]), surface.col(v[1]), surface.col(v[2]), prm.radius);
          }
        if (near.found() && near.signed_distance < 1.25 * prm.radius && near.signed_distance > -prm.depth)
          found.push_back({i, near.triangle, near.weights, near.normal});
      }
    if (grow_only)
      {
        std::vector<Contact> kept = list;
        for (const Contact &c : found)
          if (std::none_of(list.begin(), list.end(), [&](const Contact &l) { return l.node == c.node; }))
            kept.push_back(c);
        std::sort(kept.begin(), kept.end(), [](const Contact &a, const Contact &b) { return a.node < b.node; });
        found = std::move(kept);
      }
    const bool changed =
      found.size() != list.size() ||
      !std::equal(found.begin(), found.end(), list.begin(), [](const Contact &a, const Contact &b) {
        return a.node == b.node && a.triangle == b.triangle;
      });
    if (!changed)
      {
        // same nodes on the same triangles: the points keep their material position
        // (only the gap along n counts, not where on the triangle the node is), so the
        // tissue need not locate them again; the frozen normal follows the surface
        for (std::size_t k = 0; k < list.size(); ++k)
          list[k].normal = found[k].normal;
        return false;
      }
    list = std::move(found);
    adopt(nodes.size());
    seen.clear();
    for (std::size_t k = 0; k < list.size(); ++k)
      {
        const auto           &v = triangles[list[k].triangle];
        const Eigen::Vector3d q = list[k].weights[0] * surface.col(v[0]) + list[k].weights[1] * surface.col(v[1]) +
                                  list[k].weights[2] * surface.col(v[2]);
        seen.emplace_back(q[0], q[1], q[2]);
      }
    return true;
  }

  double
  SutureContact::pressure(const Contact &c, const Eigen::Vector3d &p, const Eigen::Vector3d &q, double *slope) const
  {
    const double g = (p - q).dot(c.normal) - prm.radius, d = prm.smoothing, k = prm.stiffness;
    double       F = 0, dF = 0;
    if (g <= -d)
      F = -k * g, dF = k;
    else if (g < d)
      F = k * (d - g) * (d - g) / (4 * d), dF = k * (d - g) / (2 * d);
    if (slope)
      *slope = dF;
    return F;
  }

  void
  SutureContact::add_node_terms(const std::size_t node, const rod::Vec3 &x, rod::Vec6 &residual,
                                rod::Mat6 &jacobian) const
  {
    const int k = contact_of(node);
    if (k < 0)
      return;
    const auto           &c = list[k];
    const Eigen::Vector3d q(seen[k][0], seen[k][1], seen[k][2]);
    double                slope = 0;
    const double          F = pressure(c, x, q, &slope);
    if (F <= 0)
      return;
    // f = F n on the node; residual −f, and ∂(−f)/∂x = F' n nᵀ
    residual.head<3>() -= F * c.normal;
    jacobian.topLeftCorner<3, 3>() += slope * c.normal * c.normal.transpose();
  }

  double
  SutureContact::total_force(const std::vector<rod::Vec3> &nodes) const
  {
    double total = 0;
    for (std::size_t k = 0; k < list.size(); ++k)
      total += pressure(list[k], nodes[list[k].node], Eigen::Vector3d(seen[k][0], seen[k][1], seen[k][2]));
    return total;
  }

  std::size_t
  SutureContact::n_pressing(const std::vector<rod::Vec3> &nodes) const
  {
    std::size_t n = 0;
    for (std::size_t k = 0; k < list.size(); ++k)
      n += pressure(list[k], nodes[list[k].node], Eigen::Vector3d(seen[k][0], seen[k][1], seen[k][2])) > 0;
    return n;
  }

  void
  SutureContact::force(const std::size_t k, const Point<3> &x, Tensor<1, 3> &f, Tensor<2, 3> &df_dx) const
  {
    const auto &c = list[k];
    double       slope = 0;
    const double F = pressure(c, (*suture)[c.node], Eigen::Vector3d(x[0], x[1], x[2]), &slope);
    f              = Tensor<1, 3>();
    df_dx          = Tensor<2, 3>();
    if (F <= 0)
      return;
    // −F n on the tissue point; the gap shrinks as x_q moves along n: ∂f/∂x_q = −F' n nᵀ
    for (unsigned i = 0; i < 3; ++i)
      {
        f[i] = -F * c.normal[i];
        for (unsigned j = 0; j < 3; ++j)
          df_dx[i][j] = -slope * c.normal[i] * c.normal[j];
      }
  }

  void
  SutureContact::adopt(const std::size_t n_nodes)
  {
    slot.assign(n_nodes, -1);
    X.clear();
    for (std::size_t k = 0; k < list.size(); ++k)
      {
        const auto           &v = triangles[list[k].triangle];
        const Eigen::Vector3d Xq =
          list[k].weights[0] * reference.col(v[0]) + list[k].weights[1] * reference.col(v[1]) +
          list[k].weights[2] * reference.col(v[2]);
        X.emplace_back(Xq[0], Xq[1], Xq[2]);
        slot[list[k].node] = static_cast<int>(k);
      }
  }

  nlohmann::json
  SutureContact::snapshot() const
  {
    nlohmann::json contacts = nlohmann::json::array();
    for (std::size_t k = 0; k < list.size(); ++k)
      contacts.push_back({{"node", list[k].node},
                          {"triangle", list[k].triangle},
                          {"weights", io::triple(list[k].weights)},
                          {"normal", io::triple(list[k].normal)},
                          {"seen", io::triple(seen[k])}});
    return {{"nodes", slot.size()}, {"contacts", contacts}};
  }

  void
  SutureContact::save()
  {
    saved = {list, seen, slot.size()};
  }

  void
  SutureContact::restore()
  {
    list = saved.list;
    seen = saved.seen;
    adopt(saved.nodes);
  }

  void
  SutureContact::restore(const nlohmann::json &j)
  {
    list.clear();
    seen.clear();
    for (const auto &c : j.at("contacts"))
      {
        list.push_back({c.at("node").get<std::size_t>(), c.at("triangle").get<std::uint32_t>(),
                        io::triple_as<Eigen::Vector3d>(c.at("weights")), io::triple_as<Eigen::Vector3d>(c.at("normal"))});
        seen.push_back(io::triple_as<dealii::Point<3>>(c.at("seen")));
      }
    adopt(j.at("nodes").get<std::size_t>());
  }
} // namespace suturesim::coupling
