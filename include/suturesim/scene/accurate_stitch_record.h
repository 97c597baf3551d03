#pragma once
/**
 * @file
 * The record of the accurate needle pass and stitch (scene/accurate_stitch.h), kept as
 * the realtime path keeps its own (scene/realtime_needle.h):
 *  - forces.csv per accepted step: reactions on the Dirichlet boundaries, the tissue's
 *    probes, the closure gaps, the needle's force, torque and arc centre, per recorded
 *    pierce point its state, ζ, slip velocity, normal and friction force; with the
 *    suture its tension at the swage and the free end, the drag's total, the contact
 *    force and count; with face contact its force and count;
 *  - tissue_*.vtu and suture_*.vtu at Time/Output interval (and the last state);
 *  - with Tearing/Criteria, the tear criteria per stitch at every accepted state
 *    (scene/tear_monitor.h): metrics.tearing, their cell ratios in the VTU, and in
 *    forces.csv the tension they are charged to (pull_tension), each criterion's
 *    largest zone mean / critical value (tear_<criterion>) and the force on that
 *    tract's holes (tear_force_<criterion>);
 *  - summary.json: the steps' solver account, the reactions and probes of the last
 *    state, events and puncture/pull metrics (NeedleParameters::write_summary), the
 *    suture nodes left inside the tissue, the closure metrics.
 */

#include <suturesim/io/recorder.h>
#include <suturesim/scene/accurate_stitch.h>
#include <suturesim/scene/run_summary.h>
#include <suturesim/scene/tear_monitor.h>

#include <string>

namespace suturesim::scene
{
  class AccurateStitchRecord
  {
  public:
    /// Sets the forces.csv columns and the head of summary.json.
    AccurateStitchRecord(AccurateStitch &stitch, io::Recorder &recorder);

    /// Records the accepted state at @p t with the solver's @p statistics.
    void
    record(double t, const nlohmann::json &statistics);

    /// Makes sure the last accepted state at @p t is on disk; returns its file ("" if
    /// none was written).
    std::string
    keep(double t);

    /// The metrics of the end of the run (simulated time @p t).
    void
    finish(double t);

    /// Where the record stands (its peak pull, its last output), for a checkpoint
    /// (io/checkpoint.h); restore() takes it back with summary.json's contents.
    nlohmann::json
    snapshot() const;
    void
    restore(const nlohmann::json &snapshot);

    /// The time of the last state written, s (−1: none).
    double
    last_written() const
    {
      return last_output;
    }

  private:
    /// The tension the closure and the tear onsets are charged to: the grasper's pull on
    /// the far end once grasped, else the needle's (as in the realtime path), N.
    double
    pull_tension() const
    {
      return stitch.grasped ? stitch.end_tension : stitch.load.first.norm();
    }
    /// Each pierce point's force on the tissue |f| (tie and friction), N, in the order
    /// of the needle's pierce points: what a tract's holes carry (TearMonitor).
    std::vector<double>
    hole_forces() const;
    void
    write_state(double t);
    /// The closure's gaps from the probes @p probes, into the row and the monitor.
    void
    record_gaps(double t, const std::vector<dealii::Tensor<1, 3>> &probes, std::vector<double> &row);

    AccurateStitch &stitch;
    io::Recorder   &recorder;
    RunSummary      summary;
    double          peak_pull    = 0;
    double          last_output  = -1;
    unsigned        output_index = 0;
    std::string     last_file;
    /// With Tearing/Criteria: the criteria per stitch (metrics.tearing).
    std::optional<TearMonitor> tears;
  };
} // namespace suturesim::scene
