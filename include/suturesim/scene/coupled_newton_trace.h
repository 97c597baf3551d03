#pragma once
/**
 * @file
 * Why a coupled Newton solve fails (Suture/Newton/Trace failures, with the suture's own
 * trace of scene/suture_newton_trace.h): every state the tissue's coupled solve
 * (tissue::TissueModel::solve_coupled()) brings the suture to equilibrium in, the full
 * Newton step and each halving of it, and when the solve fails its states are appended
 * to coupled_newton_trace.csv. Per state: the iterate it is a trial for, the step's
 * fraction and the largest DoF move it makes, the tissue's free residual there and its
 * largest entry (where, which component), whether the solve went on from it, the
 * suture Newton iterations its equilibrium took, and the suture's contacts and the
 * wound's touching face pairs. Beside it, coupled_newton_trace_points.csv has each
 * pierce point on the thread per state (carrier, slip, stick or slip, forces): a tissue
 * residual that will not fall while a point switches between stick and slip, or between
 * carriers, from one iterate to the next, is the friction's kink, not the tissue.
 *
 * A decorator of the condensed body: it forwards coupled_points() and equilibrate() and
 * records in observe(), so the solve and the body are the same with the trace on or off.
 */

#include <suturesim/coupling/accurate/tissue_needle.h>
#include <suturesim/tissue/condensed_body.h>

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace suturesim::scene
{
  class CoupledNewtonTrace : public tissue::CondensedBody
  {
  public:
    /// What the scene reports of the body after each trial state.
    struct BodyState
    {
      unsigned    suture_iterations = 0; ///< of the last equilibrate()
      std::size_t contacts          = 0; ///< the suture's contacts with the tissue's surface
      std::size_t pressing          = 0; ///< those of them that carry a force (SutureContact::n_pressing())
      std::size_t touching          = 0; ///< the wound's face pairs in contact
      /// the tissue's largest free residual entry, N, and where it is (reference), m; NaN
      /// for a state the solve did not reach, which has no residual of its own
      double           largest    = std::numeric_limits<double>::quiet_NaN();
      dealii::Point<3> largest_at = dealii::Point<3>(largest, largest, largest);
      unsigned         largest_component = 0;
      std::vector<coupling::TissueNeedle::ThreadPointState> points;
    };
    using Sample = std::function<BodyState(const Trial &)>;

    /// @p body: traced (kept by the caller); @p file: the trace's CSV.
    CoupledNewtonTrace(tissue::CondensedBody &body, std::string file, Sample sample);

    std::vector<std::size_t>
    coupled_points() const override
    {
      return body.coupled_points();
    }
    bool
    equilibrate(const std::vector<dealii::Point<3>> &x, Eigen::MatrixXd &G, std::string &failure) override
    {
      return body.equilibrate(x, G, failure);
    }
    /// Records @p trial with the body's state (a solve's start, iteration 0, starts afresh).
    void
    observe(const Trial &trial) override;

    /// Appends the current solve's states to the file and its points to the points
    /// file (the first call starts both afresh), labelled with the step's end time @p t
    /// and length @p dt; throws std::runtime_error naming the file when a write fails.
    void
    write(double t, double dt);

  private:
    struct Row
    {
      Trial     trial;
      BodyState state;
    };
    tissue::CondensedBody &body;
    std::string            file;
    Sample                 sample;
    std::vector<Row>       rows;
    unsigned               solves = 0;
  };
} // namespace suturesim::scene
