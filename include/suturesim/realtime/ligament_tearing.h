#pragma once
/**
 * @file
 * Seed 003's tear-into and tear-through in a realtime world (tearing/ligament_tear.h for
 * the rule): after each haptic step, every tract the needle has left (an entry pierce
 * point and the exit after it along the thread) whose end on the skin, its top start C,
 * is pulled harder than T_c ℓ tears along its weakest ligament:
 *  - the tissue's springs crossing the tear's surface (the tract C–D swept along the
 *    path) are removed (World::cut_tissue());
 *  - a path to the wound frees the tract's two pierce points (the suture is torn out
 *    through the wound's edge); a path to another insertion moves C into that hole (the
 *    two holes are one slot now) and the tract's far end stays;
 *  - the tear is recorded: kind tear_into (D in a wound face or back on the skin) or
 *    tear_through (D on the far surface), crosses_wound, the tension, the ligament, the
 *    threshold and the points (reference configuration).
 * One tear per step at most: the next is looked for on the state the first left.
 * The skin's side is the side the needle entered first (the normal of its first entry).
 */

#include <suturesim/realtime/world.h>
#include <suturesim/tearing/ligament_tear.h>

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace suturesim::realtime
{
  /// One tear, as summary.json's events list it.
  struct LigamentTear
  {
    std::string       kind;              ///< tear_into, tear_through
    double            time          = 0; ///< s
    double            tension       = 0; ///< |force| on the top start's tissue point, N
    double            suture_tension = 0; ///< the suture's pulled end's (the caller's measure), N
    double            ligament      = 0; ///< ℓ, m
    double            threshold     = 0; ///< T_c ℓ, N
    bool              crosses_wound = false;
    tearing::TractEnd far_end       = tearing::TractEnd::groove;
    Vector3d          top_start = Vector3d::Zero(), far = Vector3d::Zero(), end = Vector3d::Zero(); ///< X, m
    Vector3d          pull        = Vector3d::Zero(); ///< unit, in the skin's plane
    std::size_t       springs_cut = 0;
  };

  class LigamentTearing
  {
  public:
    /// std::invalid_argument naming the tissue's family a cut cannot part
    /// (World::uncuttable_tissue()), or a world without a needle.
    LigamentTearing(const tearing::LigamentTearParameters &parameters, tearing::Wound wound, const World &world);

    /// Looks for a tract to tear at the world's current (accepted) state, and tears it,
    /// recording @p suture_tension (N) with it: the pulled end's tension, which the accurate
    /// path's criteria report at their onset too. Returns whether it did.
    bool
    check(World &world, double suture_tension);

    const tearing::LigamentTearParameters &
    parameters() const
    {
      return prm;
    }

    const std::vector<LigamentTear> &
    tears() const
    {
      return done;
    }

    /// The tears as summary.json events (kind, time, position of the top start at rest,
    /// force: the tension, suture_tension, and the fields above).
    nlohmann::json
    events() const;

  private:
    tearing::LigamentTearParameters prm;
    tearing::Wound                  wound;
    Vector3d                        skin_normal = Vector3d::Zero(); ///< zero until the first entry
    std::vector<LigamentTear>       done;
    std::vector<Vector3d>           insertions;      ///< scratch
    std::vector<std::size_t>        insertion_point; ///< their pierce points
    std::vector<tearing::TractEnd>  sides;           ///< scratch: each pierce point's
  };
} // namespace suturesim::realtime
