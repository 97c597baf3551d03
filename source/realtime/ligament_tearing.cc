#include <suturesim/realtime/ligament_tearing.h>

#include <cmath>
#include <stdexcept>

namespace suturesim::realtime
{
  namespace
  {
    /// Relative depth below the skin (of the tract's length) at which ligaments are
    /// measured: the skin's own plane holds the wound's top edges, where a ray along it
    /// would graze the faces' boundary.
    constexpr double below_skin = 1e-4;
    /// The tear's surface reaches this fraction of its extent past its ends, so that the
    /// springs ending on the wound's face and those in the skin's plane are crossed.
    constexpr double margin = 0.05;

    nlohmann::json
    point(const Vector3d &X)
    {
      return {X[0], X[1], X[2]};
    }
  } // namespace

  LigamentTearing::LigamentTearing(const tearing::LigamentTearParameters &parameters, tearing::Wound w,
                                   const World &world)
      : prm(parameters), wound(std::move(w))
  {
    if (world.needle() == nullptr)
      throw std::invalid_argument("tears start at pierce points: the scene needs a needle");
    if (const std::string family = world.uncuttable_tissue(); !family.empty())
      throw std::invalid_argument("a tear cuts the tissue's springs; its '" + family
                                  + "' cannot be cut (use Tissue model = volume without volume constraints, "
                                    "or surface)");
  }

  bool
  LigamentTearing::check(World &world, const double suture_tension)
  {
    NeedleCoupling *needle = world.needle();
    if (skin_normal.isZero())
      for (const auto &e : needle->puncture_state().events())
        if (e.kind == "puncture_entry")
          {
            skin_normal = e.normal.normalized();
            break;
          }
    const auto &states = needle->pierce_points();
    if (skin_normal.isZero() || states.size() < 2)
      return false;
    // each point's side once a step: on_face() measures the distance to every face
    sides.clear();
    for (const auto &p : states)
      sides.push_back(wound.on_face(p.reference)               ? tearing::TractEnd::groove
                      : p.surface_normal.dot(skin_normal) >= 0 ? tearing::TractEnd::top
                                                               : tearing::TractEnd::bottom);
    const auto side = [&](const std::size_t k) { return sides[k]; };
    // tracts in thread order: an entry, and the exit made after it (nearer the tip)
    for (std::size_t k = 1; k < states.size(); ++k)
      {
        if (states[k].exit || !states[k - 1].exit)
          continue;
        std::size_t top = k, far = k - 1;
        if (side(top) != tearing::TractEnd::top)
          std::swap(top, far);
        if (side(top) != tearing::TractEnd::top)
          continue;
        const Vector3d &C = states[top].reference, &D = states[far].reference;
        const Vector3d  f = needle->tissue_force(top);
        const double    F = f.norm();
        Vector3d        d = f - f.dot(skin_normal) * skin_normal;
        if (!(d.norm() > 1e-9 * F))
          continue;
        d.normalize();
        const double depth = below_skin * (D - C).norm();
        insertions.clear();
        insertion_point.clear();
        for (std::size_t j = 0; j < states.size(); ++j)
          // a hole this point was moved into by an earlier tear is its own
          if (j != top && j != far && side(j) == tearing::TractEnd::top
              && (states[j].reference - C).norm() > 1e-9 * (D - C).norm())
            {
              insertions.push_back(states[j].reference - depth * skin_normal);
              insertion_point.push_back(j);
            }
        const Vector3d          from     = C + below_skin * (D - C);
        const tearing::Ligament ligament = tearing::weakest_ligament(wound, from, d, insertions);
        if (!std::isfinite(ligament.length) || F <= prm.strength * ligament.length)
          continue;

        LigamentTear tear;
        tear.far_end        = side(far);
        tear.kind           = tearing::tear_kind(tear.far_end);
        tear.time           = world.time();
        tear.tension        = F;
        tear.suture_tension = suture_tension;
        tear.ligament       = ligament.length;
        tear.threshold      = prm.strength * ligament.length;
        tear.crosses_wound  = ligament.to_wound;
        tear.top_start      = C;
        tear.far            = D;
        tear.end            = ligament.end;
        tear.pull           = d;
        const tearing::TearSurface surface(C, D, ligament.end - from, margin);
        tear.springs_cut
            = world.cut_tissue([&](const Vector3d &a, const Vector3d &b) { return surface.crosses(a, b); });
        if (ligament.to_wound)
          {
            needle->tear_free(std::max(top, far));
            needle->tear_free(std::min(top, far));
          }
        else
          needle->move_into(top, insertion_point[ligament.insertion]);
        done.push_back(tear);
        return true;
      }
    return false;
  }

  nlohmann::json
  LigamentTearing::events() const
  {
    nlohmann::json list = nlohmann::json::array();
    for (const auto &t : done)
      list.push_back({{"kind", t.kind},
                      {"time", t.time},
                      {"position", point(t.top_start)},
                      {"force", t.tension},
                      {"suture_tension", t.suture_tension},
                      {"crosses_wound", t.crosses_wound},
                      {"far_end", tearing::to_string(t.far_end)},
                      {"ligament", t.ligament},
                      {"threshold", t.threshold},
                      {"top_start", point(t.top_start)},
                      {"far", point(t.far)},
                      {"path_end", point(t.end)},
                      {"pull", point(t.pull)},
                      {"springs_cut", t.springs_cut}});
    return list;
  }
} // namespace suturesim::realtime
