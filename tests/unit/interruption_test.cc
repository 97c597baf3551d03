// SIGINT and SIGTERM stop a run at a step boundary (core/interruption.h): the outputs
// hold the state the run stopped at, summary.json says "interrupted", and the exit code
// is 128 + the signal.
#include <suturesim/core/process.h>

#include "run_scene.h"

#include <gtest/gtest.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <thread>

#include <sys/wait.h>

using namespace suturesim::test_support;
namespace fs = std::filesystem;

namespace
{
  struct Stopped
  {
    int            exit_code = -1;
    std::string    output;
    nlohmann::json summary;
    std::vector<std::vector<double>> rows;
  };

  /// Runs suturesim with @p args into a fresh folder @p name, sends @p signal once
  /// forces.csv has @p rows_before rows (the run is under way), and waits for the end.
  Stopped
  run_and_stop(const std::string &name, const std::vector<std::string> &args, const int signal,
               const std::size_t rows_before)
  {
    const fs::path dir = scratch_path() / name;
    fs::remove_all(dir);
    std::vector<std::string> argv{suturesim_binary()};
    argv.insert(argv.end(), args.begin(), args.end());
    argv.insert(argv.end(), {"--output", dir.string()});
    const std::string log = dir.string() + ".log";
    const pid_t       pid = suturesim::start_process(argv, log, {"OPENBLAS_NUM_THREADS=1"});

    RunResult r;
    r.directory = dir.string();
    bool signalled = false;
    int  status    = 0;
    for (int waited = 0; waited < 3000; ++waited) // 300 s at most
      {
        if (waitpid(pid, &status, WNOHANG) == pid)
          break;
        if (!signalled && fs::exists(dir / "forces.csv") && read_forces(r).size() >= rows_before)
          {
            kill(pid, signal);
            signalled = true;
          }
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
      }
    Stopped s;
    EXPECT_TRUE(signalled) << "the run ended before it was signalled";
    s.output    = read_text(log);
    s.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    s.rows      = read_forces(r);
    std::ifstream summary(dir / "summary.json");
    if (summary)
      summary >> s.summary;
    return s;
  }

  /// What every stopped run shows: exit 128 + @p signal, summary.json "interrupted" naming
  /// it (@p name), and forces.csv ending after the start and before @p end_time.
  void
  expect_stopped(const Stopped &s, const int signal, const std::string &name, const double end_time)
  {
    EXPECT_EQ(s.exit_code, 128 + signal) << s.output;
    ASSERT_FALSE(s.summary.is_null()) << s.output;
    EXPECT_EQ(s.summary["status"], "interrupted");
    EXPECT_NE(s.summary.value("error", "").find("interrupted by " + name), std::string::npos) << s.summary.dump();
    ASSERT_FALSE(s.rows.empty());
    EXPECT_LT(s.rows.back()[0], end_time);
    EXPECT_GT(s.rows.back()[0], 0);
  }
} // namespace

// The realtime loop asks between two ticks: a long stitch stopped early keeps its state
// and says why.
TEST(Interruption, SigintStopsARealtimeRunBetweenTicksWithStatusInterrupted)
{
  const double end_time = 100;
  const auto   s = run_and_stop("interrupt_realtime",
                                {suturesim::test_support::source_path("parameters/stitch_interrupted.prm"), "--set",
                                 "Time/End time=" + std::to_string(end_time)},
                                SIGINT, 50);
  expect_stopped(s, SIGINT, "SIGINT", end_time);
  EXPECT_TRUE(fs::exists(scratch_path() / "interrupt_realtime" / "tissue.pvd"));
  EXPECT_NE(s.output.find("suturesim: interrupted by SIGINT"), std::string::npos) << s.output;
}

// The implicit solvers ask after each accepted step (core/cutback_stepper.h): the
// accurate suture alone, SIGTERM.
TEST(Interruption, SigtermStopsAnAccurateRunAfterAnAcceptedStep)
{
  const double end_time = 100;
  const auto   s = run_and_stop("interrupt_accurate",
                                {suturesim::test_support::source_path("parameters/suture_swing.prm"), "--set",
                                 "Time/End time=" + std::to_string(end_time)},
                                SIGTERM, 5);
  expect_stopped(s, SIGTERM, "SIGTERM", end_time);
  const std::string error = s.summary.value("error", "");
  EXPECT_NE(error.find("suture.pvd"), std::string::npos) << error; // the state was written
  ASSERT_FALSE(s.rows.empty());
  // the last state is on disk: the series' last entry is the time the run stopped at
  const std::string pvd = read_text((scratch_path() / "interrupt_accurate" / "suture.pvd").string());
  std::ostringstream last;
  last << "timestep=\"" << s.rows.back()[0] << "\"";
  EXPECT_NE(pvd.find(last.str()), std::string::npos) << "no state at t = " << s.rows.back()[0] << " in\n" << pvd;
}
