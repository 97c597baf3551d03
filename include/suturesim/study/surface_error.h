#pragma once
/**
 * @file
 * The displacement error over the tissue surface (issue 24): a candidate surface
 * (the realtime model's vertices) against a reference one (the FE model's), both as
 * io::SurfaceField. Each candidate vertex i, at material point Xᵢ, is projected onto the
 * reference surface in the reference configuration (closest point Pᵢ on its triangles,
 * Ericson 2005 §5.1.5), where the reference displacement u_ref(Pᵢ) is interpolated
 * linearly (barycentric weights of the FE face's vertices, exact nodal values there).
 * With wᵢ a third of the candidate's triangle areas around i (the lumped surface
 * integral):
 *
 *   relative L2:    e₂ = ( Σ wᵢ |uᵢ − u_ref(Pᵢ)|² / Σ wᵢ |u_ref(Pᵢ)|² )^½
 *   relative max:   e∞ = maxᵢ |uᵢ − u_ref(Pᵢ)| / maxᵢ |u_ref(Pᵢ)|
 *   distance:       dmax = maxᵢ |Xᵢ − Pᵢ|   (m: how far the two discretisations'
 *                   surfaces are apart; 0 on flat faces, the chordal error on curved ones)
 */

#include <suturesim/io/surface_field.h>

namespace suturesim::study
{
  struct SurfaceErrors
  {
    double relative_l2  = 0; ///< e₂, 1
    double relative_max = 0; ///< e∞, 1
    double distance     = 0; ///< dmax, m
  };

  /// e₂, e∞, dmax of @p candidate against @p reference; throws std::invalid_argument
  /// when either is empty or the reference does not move (no relative error).
  SurfaceErrors
  surface_errors(const io::SurfaceField &candidate, const io::SurfaceField &reference);
} // namespace suturesim::study
