#include <suturesim/collision/proximity.h>
#include <suturesim/realtime/wound_face_contact.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace suturesim::realtime
{
  WoundFaceContact::WoundFaceContact(const System &s, const std::vector<std::uint32_t> &face_a,
                                     const std::vector<mesh::Triangle> &face_b, const double stiffness,
                                     const double listing_margin, const bool project)
    : NodeTriangleContacts(stiffness, 0, project)
    , margin(listing_margin)
  {
    if (face_a.empty() || face_b.empty())
      throw std::invalid_argument("wound face contact: both faces need triangles");
    if (!(stiffness > 0) || !(listing_margin >= 0))
      throw std::invalid_argument("wound face contact: the stiffness must be positive, the margin not negative");
    const Matrix3Xd &X = s.nodes.reference;
    for (const auto a : face_a)
      {
        const bool corner = std::any_of(face_b.begin(), face_b.end(), [a](const mesh::Triangle &t) {
          return t[0] == a || t[1] == a || t[2] == a;
        });
        if (corner)
          continue;
        // the closest point of face B at rest (a brute search: once, a few hundred nodes
        // against a few hundred triangles)
        double   nearest = std::numeric_limits<double>::infinity();
        Pair     pair{a, face_b.front(), Vector3d::Zero()};
        Vector3d bary;
        for (const auto &t : face_b)
          {
            const Vector3d q =
              collision::closest_point_on_triangle(X.col(a), X.col(t[0]), X.col(t[1]), X.col(t[2]), bary);
            if (const double d = (q - X.col(a)).norm(); d < nearest)
              {
                nearest       = d;
                pair.triangle = t;
                pair.bary     = bary;
              }
          }
        pairs.push_back(pair);
      }
    contacts.reserve(pairs.size());
  }

  void
  WoundFaceContact::add_potential_stiffness(std::vector<double> &per_node) const
  {
    for (const auto &p : pairs)
      {
        per_node[p.node] += penalty;
        for (unsigned k = 0; k < 3; ++k)
          per_node[p.triangle[k]] += p.bary[k] * p.bary[k] * penalty;
      }
  }

  void
  WoundFaceContact::detect(const Matrix3Xd &x)
  {
    contacts.clear();
    for (const auto &p : pairs)
      {
        const auto    &t      = p.triangle;
        const Vector3d normal = (x.col(t[1]) - x.col(t[0])).cross(x.col(t[2]) - x.col(t[0]));
        const double   area2  = normal.norm();
        if (!(area2 > 0))
          continue;
        Contact c{p.node, t, p.bary, normal / area2, 0};
        if (gap(c, x) < margin)
          contacts.push_back(c);
      }
  }
} // namespace suturesim::realtime
