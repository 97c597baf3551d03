#pragma once
/**
 * @file
 * Seed 003's realtime tearing: "if needle insertion points are too close from each other
 * or from the edge of the wound, the suture will tear the soft tissue instead of
 * suturing the incision together when the tension applied on the pierced nodes [goes]
 * beyond a pre-set threshold". The seed classifies a tear by the two constraints that
 * bound the tract the suture tears out of: C, the *top start* (where the stitch entered
 * or left the skin), and D, the tract's other end: a *groove* constraint (D in the wound's
 * face: tear-into, the tissue torn from the skin down into the groove) or a *bottom start*
 * (D on the tissue's far surface: tear-through, the tissue torn through its thickness);
 * and by whether the tear path crosses the wound.
 *
 * The seed gives neither the threshold nor the path; both are chosen here, and stated:
 *  - **Path: the weakest ligament.** A pierce point pulled in-plane along d fails like a
 *    pin in a plate: either the ligament between it and the free edge ahead of it shears
 *    out, or the ligament between it and a neighbouring hole parts in tension (the
 *    shear-out and net-tension modes of pin-loaded holes: Camanho & Matthews, Composites
 *    A 28:529, 1997). With the shear strength half the tensile (Tresca), the two
 *    shear planes of a shear-out ligament of length e carry as much as one net-tension
 *    ligament of length e, so the tear follows the shorter of: ℓ_w, from C along d to the
 *    wound's faces (the path crosses the wound: seed 003's tear-into "close to the edge"),
 *    and ℓ_n, from C to the nearest other insertion on the same side of the wound (the
 *    path joins the two holes and does not cross: "two insertions too close").
 *  - **Threshold: proportional to that ligament.** A point tears when its tension F
 *    exceeds T_c ℓ, ℓ = min(ℓ_w, ℓ_n), with T_c (N/m) the tissue's tear resistance per
 *    unit ligament length (the scene's `Ligament strength`). So a point tears the sooner
 *    the closer it is to the edge or its neighbour: suture pull-out force rises with bite
 *    (linea alba, Surgery 106:888, 1989), which a single force threshold would not
 *    show. T_c is a free constant of the reduced model, like the seed's threshold.
 *
 * Plain C++ and Eigen: the realtime library holds it.
 */

#include <suturesim/core/model_parameters.h>
#include <suturesim/tearing/stitch_evaluation.h>

#include <Eigen/Core>

#include <string>
#include <vector>

namespace suturesim::tearing
{
  /// "Ligament strength" (subsection Realtime/Tearing).
  struct LigamentTearParameters
  {
    double strength = 0; ///< T_c, N/m; 0: no tearing

    static void
    declare(ParameterDeclarations &declarations);
    static LigamentTearParameters
    parse(const ParameterValues &values);
  };

  /// Where the far end D of a torn tract lies (seed 003's constraints).
  enum class TractEnd
  {
    top,    ///< back on the skin: a bite that did not cross the wound
    groove, ///< in a wound face
    bottom  ///< on the tissue's far surface
  };

  /// "top", "groove", "bottom".
  std::string
  to_string(TractEnd end);

  /// "tear_through" when the tract ends on the far surface (a bottom start), else
  /// "tear_into".
  std::string
  tear_kind(TractEnd far_end);

  /// The weakest ligament ahead of a pierce point (reference configuration).
  struct Ligament
  {
    double          length    = 0;                       ///< ℓ, m; +∞: neither the wound nor an insertion ahead
    bool            to_wound  = false;                   ///< it ends on the wound's faces: the path crosses the wound
    std::ptrdiff_t  insertion = -1;                      ///< index into the insertions it ends at; −1: none
    Eigen::Vector3d end       = Eigen::Vector3d::Zero(); ///< where the tear path ends, m
  };

  /// The shorter of ℓ_w, from @p X along the unit in-plane pull @p pull to the first face
  /// of @p wound, and ℓ_n, from @p X to the nearest of @p insertions that the wound does
  /// not separate from it (entries at X itself, within 1e-12 of the scene, are skipped).
  Ligament
  weakest_ligament(const Wound &wound, const Eigen::Vector3d &X, const Eigen::Vector3d &pull,
                   const std::vector<Eigen::Vector3d> &insertions);

  /// The surface a tear opens: the tract from @p top to @p far, extended by @p margin of
  /// its length past both ends (so that the springs of the skin and of the far surface,
  /// which lie in the planes the tract ends in, are crossed too), swept along @p path
  /// extended likewise past its end. A segment crosses it when it meets the
  /// parallelogram at a point inside both of its parameters' ranges.
  class TearSurface
  {
  public:
    TearSurface(const Eigen::Vector3d &top, const Eigen::Vector3d &far, const Eigen::Vector3d &path, double margin);

    /// Whether the segment from @p a to @p b crosses the surface.
    bool
    crosses(const Eigen::Vector3d &a, const Eigen::Vector3d &b) const;

  private:
    Eigen::Vector3d origin, along_tract, along_path;
  };
} // namespace suturesim::tearing
