#pragma once
/**
 * @file
 * The record of a realtime run: forces.csv every haptic step (tool forces, the needle's
 * columns, boundary reactions, probes, closure gaps, kinetic energy, and the elastic
 * energy on the rows of the states written),
 * tissue.pvd (tetrahedra or triangles) and suture.pvd (tension per segment) at
 * Time/Output interval and the last state, summary.json with the models, the haptic
 * loop's step-time statistics and the run's metrics.
 */

#include <suturesim/io/recorder.h>
#include <suturesim/realtime/haptic_loop.h>
#include <suturesim/scene/realtime_world.h>
#include <suturesim/scene/run_summary.h>

#include <string>
#include <vector>

namespace suturesim::scene
{
  class RealtimeRecord
  {
  public:
    /// Describes the run in summary.json and sets the forces.csv columns.
    RealtimeRecord(RealtimeWorld &world, const RealtimeSettings &settings, io::Recorder &recorder);

    /// A forces.csv row of the current state; the elastic energy, a sweep over every
    /// element, only on @p output rows (the states written), NaN ("nan") on the others.
    void
    row(bool output);
    /// tissue_*.vtu and suture_*.vtu of the current state.
    void
    write_state();
    /// Whether the last state written is the current one.
    bool
    state_written() const
    {
      return last_written == world.world->time();
    }
    /// The metrics at the end of the run: the step's times (@p step) and the whole
    /// tick's (@p tick: the step, the closure, the row and the states written).
    void
    finish(const realtime::LoopStatistics &step, const realtime::LoopStatistics &tick, double wall_time);

  private:
    RealtimeWorld      &world;
    io::Recorder       &recorder;
    RunSummary          summary;
    std::vector<double> values;
    std::vector<realtime::World::ReactionSet> reactions; ///< per boundary
    std::size_t         n_outputs    = 0;
    double              longest_link_squared = 0; ///< the suture's longest link so far, m²
    double              last_written = -1;
  };
} // namespace suturesim::scene
