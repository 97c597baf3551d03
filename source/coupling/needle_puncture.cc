#include <suturesim/collision/proximity.h>
#include <suturesim/coupling/needle_puncture.h>
#include <suturesim/io/state_json.h>

#include <Eigen/Geometry>

#include <stdexcept>

namespace suturesim::coupling
{
  void
  PunctureParameters::declare(ParameterDeclarations &d)
  {
    const PunctureParameters defaults;
    d.add_real("Threshold", defaults.threshold, 0, 1e6,
               "Normal force of the tip on the surface at which it punctures (default: 0.61-0.90 N for "
               "suture needles, Maloney et al. 2025). Unit: N. Range: > 0.");
    d.add_real("Tip stiffness", defaults.stiffness, 0, 1e12,
               "Penalty k_c of the tip on the surface before puncture (the dimple). Unit: N/m. Range: > 0.");
    d.add_real("Reach", defaults.reach, 0, 1,
               "Distance from the surface within which the tip is looked for. Unit: m. Range: (0, 1].");
    d.add_real("Touch radius", defaults.touch_radius, 0, 0.01,
               "Radius of the tissue that carries the tip's push on the surface before it punctures, in "
               "the accurate path: as Pierce points/Load radius for a pierce point, the touched point "
               "moves with, and loads, the tissue within this distance, weighted by (1 - r^2/radius^2)^2. "
               "0: a point load, whose dimple (and so where the tip punctures) deepens without bound as "
               "the mesh is refined. The realtime path's touch is a node and refuses a radius. "
               "Unit: m. Range: 0-0.01.");
  }

  PunctureParameters
  PunctureParameters::parse(const ParameterValues &v)
  {
    PunctureParameters p;
    p.threshold = v.real("Threshold");
    p.stiffness = v.real("Tip stiffness");
    p.reach     = v.real("Reach");
    p.touch_radius = v.real("Touch radius");
    v.require(p.threshold > 0, "Threshold", "must be > 0 N");
    v.require(p.stiffness > 0, "Tip stiffness", "must be > 0 N/m");
    v.require(p.reach > 0, "Reach", "must be > 0 m");
    return p;
  }

  NeedlePuncture::NeedlePuncture(const PunctureParameters &parameters,
                                 const std::vector<mesh::Triangle> &surface, const Matrix3Xd &X)
    : prm(parameters)
    , triangles(surface)
    , reference(X)
  {
    if (!(prm.threshold > 0) || !(prm.stiffness > 0) || !(prm.reach > 0))
      throw std::invalid_argument("needle puncture: threshold, stiffness and reach must be > 0");
    tree.build(X, triangles, prm.reach);
    candidates.reserve(64);
  }

  Vector3d
  NeedlePuncture::position(const SurfacePoint &p, const Matrix3Xd &x) const
  {
    const auto &t = triangles[p.triangle];
    return p.weights[0] * x.col(t[0]) + p.weights[1] * x.col(t[1]) + p.weights[2] * x.col(t[2]);
  }

  void
  NeedlePuncture::surface_changed(const Matrix3Xd &x)
  {
    tree.build(x, triangles, prm.reach);
  }

  bool
  NeedlePuncture::nearest(const Vector3d &tip, const Matrix3Xd &x, SurfacePoint &point,
                          double &signed_distance, Vector3d &normal)
  {
    // the surface moves slowly relative to the reach: lazy refit with a slack of a
    // tenth of it
    tree.update(x, 0.1 * prm.reach);
    tree.leaves_near(tip, 0, candidates);
    double   best = std::numeric_limits<double>::infinity();
    Vector3d bary;
    for (const auto leaf : candidates)
      {
        const auto     t = tree.triangle(leaf);
        const auto    &v = triangles[t];
        const Vector3d a = x.col(v[0]), b = x.col(v[1]), c = x.col(v[2]);
        const Vector3d q = collision::closest_point_on_triangle(tip, a, b, c, bary);
        const Vector3d n = (b - a).cross(c - a).normalized();
        const double   distance = (tip - q).norm();
        const double   d        = (tip - q).dot(n);
        // equally near triangles (closest point on a shared edge or vertex): the one whose
        // normal points most nearly at the tip decides the side
        const double tie = 1e-9 * (distance + prm.reach);
        if (distance > best + tie || (distance > best - tie && std::abs(d) <= std::abs(signed_distance)))
          continue;
        best            = distance;
        signed_distance = d;
        normal          = n;
        point           = {t, bary};
      }
    return best <= prm.reach;
  }

  bool
  NeedlePuncture::first_crossing(const Vector3d &from, const Vector3d &to, const Matrix3Xd &x,
                                 SurfacePoint &point, Vector3d &normal, double &along)
  {
    const Vector3d path = to - from;
    if (path.squaredNorm() == 0)
      return false;
    tree.update(x, 0.1 * prm.reach);
    tree.leaves_near(0.5 * (from + to), 0.5 * path.norm(), candidates);
    const bool inwards = state == Phase::outside;
    double     first   = std::numeric_limits<double>::infinity();
    Vector3d   bary;
    for (const auto leaf : candidates)
      {
        const auto     t = tree.triangle(leaf);
        const auto    &v = triangles[t];
        const Vector3d a = x.col(v[0]), b = x.col(v[1]), c = x.col(v[2]);
        double         s = 0;
        if (!collision::segment_crosses_triangle(from, to, a, b, c, s, bary) || s >= first)
          continue;
        const Vector3d n = (b - a).cross(c - a).normalized();
        if ((path.dot(n) < 0) != inwards)
          continue;
        first  = s;
        normal = n;
        point  = {t, bary};
      }
    along = first;
    return first <= 1;
  }

  void
  NeedlePuncture::update(const double time, const Vector3d &tip, const Vector3d &direction, const Matrix3Xd &x)
  {
    SurfacePoint   p;
    double         d = 0, along = 1;
    Vector3d       n;
    const bool     moved_from     = looked;
    const Vector3d from           = last_tip;
    const Vector3d from_direction = last_direction;
    last_tip                      = tip;
    last_direction                = direction;
    looked                        = true;
    switch (state)
      {
        case Phase::outside:
        case Phase::inside:
          // where the path crossed the surface, if it did; else the nearest point (the
          // first look, or a tip on the surface at the last look). In a gap narrower
          // than the tip's step the nearest surface may be the next body's, seen from
          // the front: only the path tells which surface the tip left.
          if ((moved_from && first_crossing(from, tip, x, p, n, along)) ||
              (nearest(tip, x, p, d, n) && ((state == Phase::outside) == (d < 0))))
            {
              // crossed the surface: from outside inwards (entry) or from inside out; the
              // direction where the path crossed (the needle turns by at most a step's
              // angle between two looks: linear within it to second order)
              contact.point     = p;
              contact.reference = position(p, reference);
              contact.normal    = n;
              contact.direction = moved_from && along <= 1 ? Vector3d((1 - along) * from_direction + along * direction)
                                                           : direction;
              if (contact.direction.squaredNorm() > 0)
                contact.direction.normalize();
              contact.exit      = state == Phase::inside;
              state             = contact.exit ? Phase::pressing_out : Phase::pressing_in;
              log.push_back({contact.exit ? "touch_exit" : "touch_entry", time, tip, 0});
            }
          break;
        case Phase::pressing_in:
        case Phase::pressing_out:
          if (normal_force(tip, position(contact.point, x)) <= 0 && last_force <= 0)
            {
              // backed off: the touch ends, the tip is where it was before it
              state = contact.exit ? Phase::inside : Phase::outside;
              log.push_back({"release", time, tip, 0});
            }
          break;
      }
  }

  double
  NeedlePuncture::normal_force(const Vector3d &tip, const Vector3d &x_point) const
  {
    if (!pressing())
      return 0;
    const double penetration =
      contact.exit ? (tip - x_point).dot(contact.normal) : (x_point - tip).dot(contact.normal);
    return prm.stiffness * std::max(0.0, penetration);
  }

  bool
  NeedlePuncture::accept(const double time, const double force, const Vector3d &tip)
  {
    last_force = force;
    if (!pressing() || force < prm.threshold)
      return false;
    log.push_back({contact.exit ? "puncture_exit" : "puncture_entry", time, tip, force, contact.reference,
                   contact.normal, contact.direction});
    state      = contact.exit ? Phase::outside : Phase::inside;
    last_force = 0;
    return true;
  }

  nlohmann::json
  event_state(const PunctureEvent &e)
  {
    return {{"kind", e.kind},           {"time", e.time},
            {"position", io::triple(e.position)}, {"force", e.force},
            {"reference", io::triple(e.reference)}, {"normal", io::triple(e.normal)},
            {"direction", io::triple(e.direction)}};
  }

  PunctureEvent
  event_from(const nlohmann::json &j)
  {
    return {j.at("kind").get<std::string>(),
            j.at("time").get<double>(),
            io::triple_as<Eigen::Vector3d>(j.at("position")),
            j.at("force").get<double>(),
            io::triple_as<Eigen::Vector3d>(j.at("reference")),
            io::triple_as<Eigen::Vector3d>(j.at("normal")),
            io::triple_as<Eigen::Vector3d>(j.at("direction"))};
  }

  nlohmann::json
  NeedlePuncture::snapshot() const
  {
    nlohmann::json events = nlohmann::json::array();
    for (const auto &e : log)
      events.push_back(event_state(e));
    return {{"phase", int(state)},
            {"touch",
             {{"triangle", contact.point.triangle},
              {"weights", io::triple(contact.point.weights)},
              {"reference", io::triple(contact.reference)},
              {"normal", io::triple(contact.normal)},
              {"direction", io::triple(contact.direction)},
              {"exit", contact.exit}}},
            {"events", events},
            {"last_force", last_force},
            {"last_tip", io::triple(last_tip)},
            {"last_direction", io::triple(last_direction)},
            {"looked", looked}};
  }

  void
  NeedlePuncture::restore(const nlohmann::json &j)
  {
    state                  = Phase(j.at("phase").get<int>());
    const auto &touch      = j.at("touch");
    contact.point.triangle = touch.at("triangle").get<std::uint32_t>();
    contact.point.weights  = io::triple_as<Eigen::Vector3d>(touch.at("weights"));
    contact.reference      = io::triple_as<Eigen::Vector3d>(touch.at("reference"));
    contact.normal         = io::triple_as<Eigen::Vector3d>(touch.at("normal"));
    contact.direction      = io::triple_as<Eigen::Vector3d>(touch.at("direction"));
    contact.exit           = touch.at("exit").get<bool>();
    log.clear();
    for (const auto &e : j.at("events"))
      log.push_back(event_from(e));
    last_force = j.at("last_force").get<double>();
    last_tip   = io::triple_as<Eigen::Vector3d>(j.at("last_tip"));
    last_direction = io::triple_as<Eigen::Vector3d>(j.at("last_direction"));
    looked     = j.at("looked").get<bool>();
  }
} // namespace suturesim::coupling
