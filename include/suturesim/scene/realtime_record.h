#pragma once
/**
 * @file
 * The record of a realtime run: forces.csv every haptic step (tool forces, the needle's
 * columns, boundary reactions, probes, closure gaps, kinetic energy, and the elastic
 * energy on the rows of the output ticks and the last step),
 * tissue.pvd (tetrahedra or triangles) and suture.pvd (tension per segment) at
 * Time/Output interval and the last state, summary.json with the models, the haptic
 * loop's step-time statistics and the run's metrics.
 */

#include <suturesim/core/background_writer.h>
#include <suturesim/io/recorder.h>
#include <suturesim/realtime/haptic_loop.h>
#include <suturesim/scene/realtime_world.h>
#include <suturesim/scene/run_summary.h>

#include <limits>
#include <memory>
#include <string>
#include <vector>

namespace suturesim::scene
{
  /// A state as the haptic thread hands it to the record's writer thread: the tissue's
  /// nodes (deformed, reference, velocity) and cells, copied because seed 002's
  /// subdivision changes them, and the suture's nodes and segment tensions.
  struct RecordState
  {
    double                         time  = 0;
    std::size_t                    index = 0; ///< the output's number: its files' suffix
    realtime::Matrix3Xd            x, X, v;
    std::vector<mesh::Tetrahedron> tetrahedra; ///< the volume model's; empty: triangles
    std::vector<mesh::Triangle>    triangles;
    realtime::Matrix3Xd            suture;
    std::vector<double>            tension;
  };

  class RealtimeRecord
  {
  public:
    /// Describes the run in summary.json and sets the forces.csv columns.
    RealtimeRecord(RealtimeWorld &world, const RealtimeSettings &settings, io::Recorder &recorder);
    /// The writer thread's sinks hold this record: it stays where it was made.
    RealtimeRecord(const RealtimeRecord &) = delete;
    RealtimeRecord &
    operator=(const RealtimeRecord &) = delete;

    /// A forces.csv row of the current state; the elastic energy, a sweep over every
    /// element, only on @p output rows (the output ticks and the last), NaN ("nan") on
    /// the others.
    /// Handed to the writer thread: the haptic thread formats and writes nothing.
    void
    row(bool output);
    /// tissue_*.vtu and suture_*.vtu of the current state: copied into a free slot of
    /// the writer thread, which writes them; when none is free the state is dropped and
    /// counted, unless @p wait (the run's last state, after the loop). The files are
    /// numbered by output, written or not, so that a name always means the same output
    /// (a dropped one leaves a gap; the .pvd lists the files written).
    void
    write_state(bool wait = false);
    /// Whether a write on the writer thread failed: the run stops, and finish() throws
    /// the WriteError naming the file.
    bool
    output_failed() const noexcept
    {
      return writer->failed();
    }
    /// Whether the last state handed to the writer is the current one.
    bool
    state_written() const
    {
      return last_written == world.world->time();
    }
    /// Writes what the writer thread holds (and rethrows its WriteError), then the
    /// metrics at the end of the run: the step's times (@p step), the whole tick's
    /// (@p tick: the step, the closure, the row and the states handed over) and its
    /// @p phases (metrics.tick_phases_us: median and p99 of each), and the
    /// rows and states the writer could not take (metrics.recording).
    void
    finish(const realtime::LoopStatistics &step, const realtime::LoopStatistics &tick,
           const realtime::PhaseStatistics &phases, double wall_time);

  private:
    RealtimeWorld      &world;
    io::Recorder       &recorder;
    RunSummary          summary;
    std::vector<double> values;
    std::vector<realtime::World::ReactionSet> reactions; ///< per boundary
    std::size_t         n_outputs    = 0; ///< states asked for (haptic thread), dropped or not
    double              longest_link_squared = 0; ///< the suture's longest link so far, m²
    /// the probe's least gap to the tissue so far (negative: within its radius), m
    double              probe_least_gap = std::numeric_limits<double>::infinity();
    double              last_written = -1;
    std::unique_ptr<BackgroundWriter<RecordState>> writer; ///< last: joined first

    /// Copies the current state into @p s.
    void
    capture(RecordState &s) const;
    /// Writes @p s as the next tissue_*.vtu and suture_*.vtu (writer thread).
    void
    write(const RecordState &s);
  };
} // namespace suturesim::scene
