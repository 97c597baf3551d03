#pragma once
/**
 * @file
 * The frame of an accurate run: a wall-time table per section (deal.II TimerOutput),
 * printed when the run completes and when a solve fails (not for bad input, whose
 * one-line error must stay the only output), and recorded in summary.json "timings".
 */

#include <suturesim/io/recorder.h>

#include <deal.II/base/conditional_ostream.h>
#include <deal.II/base/timer.h>

#include <functional>

namespace suturesim::scene
{
  /// Runs @p body with the timer and rank 0's console; rethrows what it throws once the
  /// table is printed.
  void
  run_timed(io::Recorder &recorder,
            const std::function<void(dealii::TimerOutput &timer, dealii::ConditionalOStream &pcout)> &body);
} // namespace suturesim::scene
