#pragma once
/**
 * @file
 * Seed 003's evaluation of a stitch: "if needle insertion points are too close from each
 * other or from the edge of the wound, the suture will tear the soft tissue instead of
 * suturing the incision together". Both model paths hand over their needle's puncture
 * events (coupling/needle_puncture.h: the material point pierced, the surface normal
 * there, the needle's direction) and the wound's faces in the reference configuration;
 * the stitches and their measures come out the same way for both.
 *
 * A stitch runs from an entry puncture on the skin (not on a wound face) to the next exit
 * on the skin; the punctures in between go through the wound's faces (out of the near
 * lip, into the far one). Without wound faces every entry and the exit after it are one
 * stitch. Per stitch, all in the reference configuration:
 *  - bite width c = |X_exit − X_entry|, the chord of the pass;
 *  - bite depth δ = R − √(R² − c²/4): how deep a needle of arc radius R that turns about
 *    its centre (tools/surgical_pass.h) reaches below the chord between the two points;
 *    NaN when c > 2R (no such arc);
 *  - the entry's and the exit's distance to the wound: to the nearest point of its faces
 *    (for a point on the skin beside a wound whose faces do not overhang it, the edge);
 *  - the entry and exit angles, between the needle's direction t where its tip met the
 *    surface (the touch that ended in the puncture) and the surface there with its
 *    normal n, θ = asin |t·n| (π/2: perpendicular, as taught). A planned pass enters at
 *    its α (tools/surgical_pass.h); by the puncture the needle has turned on through the
 *    dimple, so the angle then would be smaller on entry and larger on exit;
 *  - the spacing: the distance from the midpoint of its chord to the nearest other
 *    stitch's (NaN alone);
 *  - the flags: too close to the edge when the entry or exit is nearer the wound than the
 *    edge limit, too close to a neighbour when the spacing is below the spacing limit.
 *
 * The limits are the scene's ("Stitch evaluation"). Seed 003 gives no numbers ("a pre-set
 * threshold"); by default they follow the rule of thumb of surgical teaching for
 * interrupted sutures: the entry about as far from the edge as the tissue sutured is deep,
 * successive stitches about twice that apart. So a zero edge limit reads as the stitch's
 * own bite depth, and a zero spacing limit as twice the edge limit.
 *
 * Plain C++ and Eigen: the realtime library holds it.
 */

#include <suturesim/core/model_parameters.h>
#include <suturesim/coupling/needle_puncture.h>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <nlohmann/json.hpp>

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace suturesim::tearing
{
  /// "Wound faces", "Minimum edge distance", "Minimum spacing" (subsection "Stitch
  /// evaluation").
  struct StitchLimits
  {
    std::string wound_faces;       ///< boundary names or ids, "a, b"; empty: Closure/Face contact's
    double      edge_distance = 0; ///< m; 0: the stitch's bite depth
    double      spacing       = 0; ///< m; 0: twice the edge limit

    static void
    declare(ParameterDeclarations &declarations);
    static StitchLimits
    parse(const ParameterValues &values);
  };

  /// The wound's faces in the reference configuration (m).
  class Wound
  {
  public:
    /// No wound: distances are NaN, no point is on a face.
    Wound() = default;
    /// The triangles of @p triangles (indices into @p vertices) whose @p on_face entry
    /// is set, counter-clockwise seen from outside the tissue (both paths' boundary
    /// surfaces are), so that each face's winding gives its lip's outward normal.
    Wound(const Eigen::Matrix3Xd &vertices, const std::vector<std::array<std::uint32_t, 3>> &triangles,
          const std::vector<char> &on_face);

    bool
    present() const
    {
      return !faces.empty();
    }
    /// Distance from @p X to the nearest point of the faces, m; NaN without a wound.
    double
    distance(const Eigen::Vector3d &X) const;
    /// @p X lies on a face (within 1e-9 of the faces' extent).
    bool
    on_face(const Eigen::Vector3d &X) const;
    /// Distance from @p X along the unit direction @p d to the first face it meets, m;
    /// +∞ when it meets none.
    double
    ray(const Eigen::Vector3d &X, const Eigen::Vector3d &d) const;
    /// The segment from @p a to @p b passes through a face strictly between its ends (the
    /// wound lies between them; an end on a face is on its own side).
    bool
    separates(const Eigen::Vector3d &a, const Eigen::Vector3d &b) const;
    /// The tissue at @p b is out of sight from @p a through the tissue: the segment
    /// separates() them, or an end on a face looks out of its lip through that face,
    /// (b − a)·n > 0 at a (and (a − b)·n > 0 at b) for the outward normal n of every face
    /// the end lies on. The visibility criterion of meshless methods on cracked bodies
    /// (Belytschko, Lu & Gu 1994, Int J Numer Meth Eng 37:229–256) for a spread pierce
    /// point on a face (Pierce points/Load across the wound = false): the realtime path
    /// samples its kernel at the nodes, and those of the other lip's face lie on that face,
    /// reached across the gap without crossing a face strictly. A point in the plane of
    /// its face sees along it (faces flat within the spread's radius, as the slit's are).
    bool
    hides(const Eigen::Vector3d &a, const Eigen::Vector3d &b) const;

  private:
    /// @p p lies on a face, and @p d points out of the lip of every face it lies on
    bool
    looks_out(const Eigen::Vector3d &p, const Eigen::Vector3d &d) const;

    std::vector<std::array<Eigen::Vector3d, 3>> faces;
    std::vector<Eigen::Vector3d>                normals; ///< each face's, unit and outward
    std::vector<Eigen::AlignedBox3d>            boxes;   ///< each face's, for separates()
    double                                      tolerance = 0;
  };

  struct StitchEvaluation
  {
    coupling::PunctureEvent                entry;
    std::optional<coupling::PunctureEvent> exit;                           ///< none: the pass has not come out yet
    std::vector<coupling::PunctureEvent>   between;                        ///< through the wound's faces
    double                                 bite_width = 0, bite_depth = 0; ///< m (NaN without an exit)
    double entry_edge_distance = 0, exit_edge_distance = 0;                ///< m (NaN without wound or exit)
    double spacing     = 0;                                                ///< m (NaN: no other stitch)
    double entry_angle = 0, exit_angle = 0;                                ///< rad
    double edge_limit = 0, spacing_limit = 0;                              ///< m, as applied
    bool   too_close_to_edge = false, too_close_to_neighbour = false;

    /// The wound lies between entry and exit: a puncture went through one of its faces.
    bool
    crosses_wound() const
    {
      return !between.empty();
    }
  };

  /// The stitches of @p events (a needle's events in time order; only punctures count)
  /// through @p wound, for a needle of arc radius @p needle_radius (m).
  std::vector<StitchEvaluation>
  evaluate_stitches(const std::vector<coupling::PunctureEvent> &events, const Wound &wound, double needle_radius,
                    const StitchLimits &limits);

  /// summary.json's "metrics.stitch_evaluation": per stitch its points, measures, limits
  /// and flags (null for NaN), and the counts of stitches and of flagged ones.
  nlohmann::json
  stitches_json(const std::vector<StitchEvaluation> &stitches);

  /// stitches.csv: one row per stitch, the same measures; every header names its unit,
  /// an empty cell is a NaN.
  std::string
  stitches_csv(const std::vector<StitchEvaluation> &stitches);
} // namespace suturesim::tearing
