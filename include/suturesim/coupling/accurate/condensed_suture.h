#pragma once
/**
 * @file
 * The Cosserat suture as a body condensed onto the tissue's point loads
 * (tissue/condensed_body.h), so that tissue and suture are solved together by one Newton
 * iteration instead of rounds of separate solves: the pierce points on the thread (the
 * tie and the friction of coupling/accurate/tissue_needle.h) and the suture's contacts
 * with the tissue's surface (coupling/accurate/suture_contact.h).
 *
 * equilibrate(): the suture's own Newton solve with the tissue's points held where the
 * tissue's iterate puts them, then G = F_q D⁻¹ H with D the suture's factorised Jacobian
 * there, H = ∂R_suture/∂y (the points' pull on the suture's residual) and F_q = ∂f/∂q
 * (the loads on the tissue against the suture's node positions and rotations: the
 * rotations' tangent directors shape the thread's curve the pierce points are measured
 * on). H and F_q are central differences of the residual and of the loads (steps 1e-8 m
 * and 1e-7 rad: the loads go through the projection on that curve, the return mapping
 * and the smoothed normal force, whose exact chain would be long); tests/unit compare
 * the coupled Newton's convergence.
 */

#include <suturesim/coupling/accurate/suture_contact.h>
#include <suturesim/coupling/accurate/tissue_needle.h>
#include <suturesim/rod/rod_model.h>
#include <suturesim/tissue/condensed_body.h>
#include <suturesim/tissue/point_load_list.h>

#include <utility>
#include <vector>

namespace suturesim::coupling
{
  class CondensedSuture : public tissue::CondensedBody
  {
  public:
    /// @p loads: the tissue's point loads, @p needle's points first, then @p contact's
    /// (may be nullptr); @p terms: the suture's nodal terms (stabilization, contact), may
    /// be nullptr. All kept by the caller.
    CondensedSuture(rod::RodModel &suture, const rod::NewtonParameters &newton, TissueNeedle &needle,
                    SutureContact *contact, const tissue::PointLoadList &loads, const rod::NodalTerms *terms);

    std::vector<std::size_t>
    coupled_points() const override;

    bool
    equilibrate(const std::vector<dealii::Point<3>> &x, Eigen::MatrixXd &G, std::string &failure) override;

    /// The suture's residual (6 per node; at supported nodes, their reactions) with the
    /// tissue's points where the last equilibrate() held them: the suture's pull on its
    /// supports in the converged state.
    Eigen::VectorXd
    residual();

    /// The pierce points on the thread as the suture's terms see them now (the tissue's
    /// points where equilibrate() holds them; diagnostics).
    std::vector<TissueNeedle::ThreadPointState>
    point_states() const
    {
      return needle.thread_point_states(seen);
    }

    /// Suture Newton iterations of the last equilibrate().
    unsigned
    last_iterations() const
    {
      return iterations;
    }

    /// The most suture Newton iterations one equilibrate() took since the last call
    /// (then 0 again): the suture's share of a coupled step's effort.
    unsigned
    take_peak_iterations()
    {
      return std::exchange(peak_iterations, 0u);
    }

  private:
    /// Sets the pierce points' element terms on the suture for its lifetime: they read
    /// this body's state, so they are attached only while it is at work.
    struct Attached
    {
      explicit Attached(CondensedSuture &body);
      ~Attached();
      CondensedSuture &body;
    };

    /// The suture's residual with the tissue's points at @p x.
    Eigen::VectorXd
    residual_at(const std::vector<dealii::Point<3>> &x);
    /// Makes the suture's terms see the tissue's points at @p x.
    void
    hold(const std::vector<dealii::Point<3>> &x);

    rod::RodModel               &suture;
    rod::NewtonParameters        newton;
    TissueNeedle                &needle;
    SutureContact               *contact;
    const tissue::PointLoadList &loads;
    const rod::NodalTerms       *terms;
    std::vector<dealii::Point<3>> seen; ///< the needle's part of the points, read by the element terms
    rod::ElementTerms             element_terms;
    rod::ElementList              elements;
    unsigned                      iterations = 0;
    unsigned                      peak_iterations = 0;
  };
} // namespace suturesim::coupling
