// SIGINT and SIGTERM stop a run at a step boundary (core/interruption.h): the outputs
// hold the state the run stopped at, summary.json says "interrupted", and the exit code
// is 128 + the signal.
#include <suturesim/core/process.h>

#include "restart_checks.h"
#include "run_scene.h"

#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iterator>
#include <sstream>
#include <thread>
#include <vector>

#include <sys/wait.h>

using namespace suturesim::test_support;
namespace fs = std::filesystem;

namespace
{
  /// A CBOR file's content.
  nlohmann::json
  read_cbor(const fs::path &file)
  {
    std::ifstream in(file, std::ios::binary);
    return nlohmann::json::from_cbor(std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), {}));
  }

  /// A run folder's checkpoint/shared.cbor.
  nlohmann::json
  read_checkpoint(const fs::path &dir)
  {
    return read_cbor(dir / "checkpoint" / "shared.cbor");
  }

  /// Writes @p state to the CBOR file @p file (a checkpoint changed by a test).
  void
  write_cbor(const fs::path &file, const nlohmann::json &state)
  {
    const auto    bytes = nlohmann::json::to_cbor(state);
    std::ofstream out(file, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char *>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
    out.close();
    ASSERT_FALSE(out.fail()) << file;
  }

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
    s.directory = dir.string();
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

// Before the first step: a stop while gmsh meshes the scene's .geo (a mesh at h = 0.2 mm
// that takes gmsh minutes) stops gmsh and the run at once, as an interruption, not as a
// gmsh failure (exit 2, which it was). Only suturesim is signalled here; from a terminal
// gmsh gets Ctrl-C too.
TEST(Interruption, SigintWhileGmshMeshesStopsBothAtOnce)
{
  const fs::path dir = scratch_path() / "interrupt_gmsh";
  fs::remove_all(dir);
  const std::vector<std::string> argv{suturesim_binary(),
                                      suturesim::test_support::source_path("parameters/skin_pad_pull.prm"),
                                      "--set", "Model=accurate", "--set", "Mesh/Geo parameters=h: 0.0002, hexahedra: 1",
                                      "--output", dir.string()};
  const std::string log = dir.string() + ".log";
  const pid_t       pid = suturesim::start_process(argv, log);
  int               status = 0, waited = 0;
  bool              signalled = false;
  for (; waited < 1200 && waitpid(pid, &status, WNOHANG) != pid; ++waited) // 120 s at most
    {
      if (!signalled && fs::exists(dir / "gmsh.log") && fs::file_size(dir / "gmsh.log") > 0)
        {
          std::this_thread::sleep_for(std::chrono::milliseconds(300)); // gmsh under way
          kill(pid, SIGINT);
          signalled = true;
          waited    = 1150; // then 5 s at most
        }
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  ASSERT_TRUE(signalled) << read_text(log);
  if (waited >= 1200)
    kill(pid, SIGKILL); // the failure below says so
  const std::string output = read_text(log);
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 130) << output;
  EXPECT_NE(output.find("suturesim: interrupted by SIGINT"), std::string::npos) << output;
  std::ifstream summary(dir / "summary.json");
  nlohmann::json json;
  ASSERT_TRUE(summary >> json) << output;
  EXPECT_EQ(json["status"], "interrupted");
}

// The implicit solvers ask after each accepted step (core/cutback_stepper.h): the
// accurate suture alone, SIGTERM.
TEST(Interruption, SigtermStopsAnAccurateRunAfterAnAcceptedStep)
{
  const double end_time = 100;
  const auto   s = run_and_stop("interrupt_accurate",
                                {suturesim::test_support::source_path("parameters/suture_swing.prm"), "--set",
                                 "Time/End time=" + std::to_string(end_time), "--set", "Time/Maximum outputs=1e5"},
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

namespace
{
  /// The accurate needle pass with its suture (parameters/needle_pass.prm, Model =
  /// accurate: Q1 hexahedra of 2 mm) through both punctures and onto the suture, with
  /// two tear criteria over its tract (scene/tear_monitor.h): a restart takes their
  /// record back (metrics.tearing is compared with the rest of the metrics). The zone's
  /// energy peaks before the periodic checkpoint, at about 45 J/m³ (measured); the low
  /// toughness, 0.3 J/m² (Ψ_c = 28 J/m³), puts the onset there too. A record lost in the
  /// restart shows: without it the largest mean came out 0.0015 Ψ_c, not 0.48.
  const std::vector<std::string> accurate_pass{suturesim::test_support::source_path("parameters/needle_pass.prm"),
                                               "--set",
                                               "Model=accurate",
                                               "--set",
                                               "Time/End time=1.4",
                                               "--set",
                                               "Tearing/Criteria=max-principal-stretch, fracture-energy",
                                               "--set",
                                               "Tearing/Process zone radius=0.002",
                                               "--set",
                                               "Tearing/fracture-energy/Fracture toughness=0.3"};

  /// The solvers' tolerance of this scene: the tissue's Newton floor, 0.01 × Pierce
  /// points/Transverse stiffness (500 N/m) × Coupling tolerance (1e-7 m) = 5e-7 N
  /// (scene/accurate_stitch.cc); a solve stops anywhere within it.
  constexpr double solver_floor = 5e-7;
} // namespace

// Stopped mid-run by SIGTERM (which writes a checkpoint), then --restart: the run goes on
// from its last accepted step and ends as the run that was never stopped (issue 26).
TEST(Restart, AnAccurateNeedlePassStoppedMidRunEndsAsTheUninterruptedRun)
{
  const auto whole = run_suturesim("restart_reference", accurate_pass);
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const auto rows = read_forces(whole);
  ASSERT_GT(rows.size(), 30u);

  const auto stopped = run_and_stop("restart_stopped", accurate_pass, SIGTERM, rows.size() / 3);
  expect_stopped(stopped, SIGTERM, "SIGTERM", 1.4);
  EXPECT_NE(stopped.summary.value("error", "").find("--restart"), std::string::npos) << stopped.summary.dump();
  const fs::path dir = scratch_path() / "restart_stopped";
  ASSERT_TRUE(fs::exists(dir / "checkpoint" / "shared.cbor"));
  const auto restarted = restart(accurate_pass, dir);
  EXPECT_NE(restarted.output.find("restarting from the checkpoint after step"), std::string::npos)
    << restarted.output;
  expect_as_uninterrupted(restarted, whole, solver_floor);
}

// A periodic checkpoint (Time/Checkpoint steps) of a run that then ran to its end: a
// restart from it runs the rest again to the same end; a changed scene is refused.
TEST(Restart, FromAPeriodicCheckpointTheRestRunsAgainToTheSameEnd)
{
  const auto whole = run_suturesim("restart_periodic_reference", accurate_pass);
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const std::vector<std::string> every_25 = join(accurate_pass, {"--set", "Time/Checkpoint steps=25"});
  const auto periodic = run_suturesim("restart_periodic", every_25);
  ASSERT_EQ(periodic.exit_code, 0) << periodic.output;
  const fs::path dir = scratch_path() / "restart_periodic";
  ASSERT_TRUE(fs::exists(dir / "checkpoint" / "shared.cbor"));
  EXPECT_FALSE(fs::exists(dir / "checkpoint.new"));

  // another scene is refused, and leaves the folder as it was
  const auto other = restart(join(every_25, {"--set", "Puncture/Threshold=0.8"}), dir);
  EXPECT_EQ(other.exit_code, 2) << other.output;
  EXPECT_NE(other.output.find("error: --restart " + dir.string() +
                              ": the checkpoint was written with other parameters ('Puncture/Threshold = 0.7' then, "
                              "'Puncture/Threshold = 0.8' now)"),
            std::string::npos)
    << other.output;
  EXPECT_TRUE(fs::exists(dir / "summary.json"));
  // so are an end time not after the checkpoint, another process count, and a
  // checkpoint that cannot be read
  const auto early = restart(join(every_25, {"--set", "Time/End time=1.0"}), dir);
  EXPECT_EQ(early.exit_code, 2) << early.output;
  EXPECT_NE(early.output.find("Time/End time = 1.000000 s is not after the checkpoint's t = "), std::string::npos)
    << early.output;
  std::string mpi_output;
  const int   mpi = run_logged(join(join(mpi_launcher(2), join({suturesim_binary()}, every_25)), {"--restart", dir.string()}),
                               dir.string() + "_np2.log", mpi_output, mpi_environment());
  EXPECT_EQ(mpi, 2) << mpi_output;
  EXPECT_NE(mpi_output.find("MPI processes: 1 in the checkpoint, 2 in this run"), std::string::npos)
    << mpi_output;
  const fs::path broken = scratch_path() / "restart_broken";
  fs::remove_all(broken);
  fs::copy(dir, broken, fs::copy_options::recursive);
  std::ofstream(broken / "checkpoint" / "shared.cbor", std::ios::trunc) << "not CBOR";
  const auto garbled = restart(every_25, broken);
  EXPECT_EQ(garbled.exit_code, 2) << garbled.output;
  EXPECT_NE(garbled.output.find("shared.cbor is not a checkpoint"), std::string::npos) << garbled.output;
  EXPECT_TRUE(fs::exists(dir / "summary.json"));
  // the suture's rotations are set back as saved, not normalised (rod::RodModel::
  // restore_node()), so a checkpoint whose rotation is not unit is refused
  const fs::path scaled = scratch_path() / "restart_not_unit";
  fs::remove_all(scaled);
  fs::copy(dir, scaled, fs::copy_options::recursive);
  {
    const fs::path file  = scaled / "checkpoint" / "shared.cbor";
    auto           state = read_checkpoint(scaled);
    ASSERT_TRUE(state["scenario"]["stitch"].contains("suture"))
      << state["scenario"].dump().substr(0, 300);
    auto &q = state["scenario"]["stitch"]["suture"]["q"];
    ASSERT_GE(q.size(), 8u);
    for (int k = 4; k < 8; ++k) // node 1
      q[k] = 1.001 * q[k].get<double>();
    write_cbor(file, state);
  }
  const auto not_unit = restart(every_25, scaled);
  EXPECT_EQ(not_unit.exit_code, 2) << not_unit.output;
  EXPECT_NE(not_unit.output.find("the checkpoint's suture rotation at node 1 is not a unit quaternion"),
            std::string::npos)
    << not_unit.output;

  const auto restarted = restart(every_25, dir);
  const std::size_t steps = whole.summary["solver"]["steps"].get<std::size_t>();
  EXPECT_NE(restarted.output.find("restarting from the checkpoint after step " + std::to_string(steps / 25 * 25)),
            std::string::npos)
    << restarted.output;
  expect_as_uninterrupted(restarted, whole, solver_floor);
  EXPECT_TRUE(restarted.summary.contains("restarted_from")) << restarted.summary.dump();
  // the checkpoint (after step 25k, near the end) holds the tract made before it
  const auto &tracts = whole.summary["metrics"]["tearing"]["criteria"]["max-principal-stretch"]["tracts"];
  ASSERT_EQ(tracts.size(), 1u) << whole.summary["metrics"]["tearing"].dump();
  EXPECT_GT(tracts[0]["largest_mean_over_critical"].get<double>(), 1 / 1.54); // stretched: λ > 1
  const auto &onset = whole.summary["metrics"]["tearing"]["criteria"]["fracture-energy"]["tracts"][0]["onset"];
  ASSERT_FALSE(onset.is_null());
  EXPECT_LT(onset["time"].get<double>(), restarted.summary["restarted_from"]["t"].get<double>())
    << restarted.summary["restarted_from"].dump();
}

// A run whose step still fails after its halvings (exit 3) keeps its last converged state
// as a checkpoint too: a restart replays the failed step from there, with the same
// failure, and may turn on the failure traces, which change no result.
TEST(Restart, AFailedRunsCheckpointReplaysItsFailedStep)
{
  // one Newton iteration a solve: the steps fail once the needle presses the tissue
  const std::vector<std::string> failing = join(accurate_pass, {"--set", "Time/End time=0.5", "--set",
                                                                "Tissue/Newton/Max iterations=1", "--set",
                                                                "Time/Max cutbacks=1"});
  const auto     failed = run_suturesim("restart_failed", failing);
  const fs::path dir    = scratch_path() / "restart_failed";
  ASSERT_EQ(failed.exit_code, 3) << failed.output;
  const std::string error = failed.summary.value("error", "");
  EXPECT_NE(error.find("(suturesim --restart " + dir.string() + " replays the failed step from it)"),
            std::string::npos)
    << error;
  ASSERT_TRUE(fs::exists(dir / "checkpoint" / "shared.cbor"));
  const std::size_t at = error.find("Newton failed at t = ");
  ASSERT_NE(at, std::string::npos) << error;
  const std::string failure = error.substr(at, error.find(';', at) - at);

  const auto replayed = restart(join(failing, {"--set", "Suture/Newton/Trace failures=true"}), dir);
  EXPECT_EQ(replayed.exit_code, 3) << replayed.output;
  EXPECT_NE(replayed.output.find("restarting from the checkpoint after step"), std::string::npos) << replayed.output;
  EXPECT_NE(replayed.summary.value("error", "").find(failure), std::string::npos)
    << failure << "\n" << replayed.summary.value("error", "");
}

// A step undone leaves nothing of its own behind (scene/accurate_stitch.h, undo()): the
// checkpoint of a run that gave up is its last accepted state to the bit, and the replay
// fails at the same step. The stitch of the bite x spacing map with its thread at 0.25 mm
// touches the skin from about 1.3 s; one round a step makes the first step whose
// contacts change fail, after its round detected them and the wound's faces were
// equilibrated. The same run ended at that last accepted time writes the state to
// compare with. Before the undo took back the contacts, the faces' equilibrium and the
// suture's rotations as saved (2026-12-06), this checkpoint held the failed step's one
// contact where the accepted state had none, and the replay got past t = 1.29125 s.
TEST(Restart, AFailedRunsCheckpointIsItsLastAcceptedStateToTheBit)
{
  const std::vector<std::string> args{source_path("parameters/tearing/bite_spacing.prm"),
                                      "--set", "Model=accurate",
                                      "--set", "Suture/Elements=320",
                                      "--set", "Pierce points/Accurate/Coupling iterations=1",
                                      "--set", "Time/Max cutbacks=0"};
  const auto     failed = run_suturesim("restart_undone", args);
  const fs::path dir    = failed.directory;
  ASSERT_EQ(failed.exit_code, 3) << failed.output;
  const std::string error = failed.summary.value("error", "");
  const std::size_t at    = error.find("Newton failed at t = ");
  ASSERT_NE(at, std::string::npos) << error;
  const std::string failure = error.substr(at, error.find(';', at) - at);
  EXPECT_NE(failure.find("the contacts still changed"), std::string::npos) << failure;

  // the run ended at the failed run's last accepted step, its checkpoint written there
  const nlohmann::json stopped = read_checkpoint(dir);
  const auto          &stepper = stopped["scenario"]["stepper"];
  std::ostringstream   end;
  end << std::setprecision(17) << stepper["t"].get<double>();
  const auto accepted = run_suturesim("restart_undone_accepted",
                                      join(args, {"--set", "Time/End time=" + end.str(), "--set",
                                                  "Time/Checkpoint steps=" + std::to_string(stepper["steps"].get<int>())}));
  ASSERT_EQ(accepted.exit_code, 0) << accepted.output;
  const fs::path       accepted_dir = accepted.directory;
  const nlohmann::json kept         = read_checkpoint(accepted_dir);
  EXPECT_TRUE(kept["scenario"]["stepper"] == stepper);
  for (const auto &[part, value] : kept["scenario"]["stitch"].items())
    EXPECT_TRUE(stopped["scenario"]["stitch"][part] == value) << "the checkpoint's " << part << " is not the accepted state's";
  EXPECT_TRUE(read_text((dir / "checkpoint" / "rank-0.cbor").string()) ==
              read_text((accepted_dir / "checkpoint" / "rank-0.cbor").string()))
    << "the tissue's state differs";

  const auto replayed = restart(args, dir);
  EXPECT_EQ(replayed.exit_code, 3) << replayed.output;
  EXPECT_NE(replayed.summary.value("error", "").find(failure), std::string::npos)
    << failure << "\n" << replayed.summary.value("error", "");
}

// With the phase field (Tissue/Phase field) the checkpoint carries the damage
// (TissueModel::local_state()), accepted as the next step's lower bound. On the accurate
// needle pass at G_c = 4 J/m², l = 2 mm (psi_c = 375 J/m³) the needle's touch before the
// puncture damages the tissue under the tip to d = 0.029 (measured), which stays for the
// rest of the pass; so a restart from step 40 that lost the damage would record d = 0 in
// every step after it (its touch is over), and a degradation that was not restored would
// move the forces. A checkpoint without the damage is refused in one line.
TEST(Restart, APhaseFieldNeedlePassTakesItsDamageBack)
{
  const std::vector<std::string> args{source_path("parameters/needle_pass.prm"),
                                      "--set", "Model=accurate",
                                      "--set", "Time/End time=1.4",
                                      "--set", "Tissue/Phase field/Enabled=true",
                                      "--set", "Tissue/Phase field/Fracture toughness=4",
                                      "--set", "Tissue/Phase field/Length=0.002",
                                      "--set", "Time/Checkpoint steps=40"};
  const auto whole = run_suturesim("restart_phase_field", args);
  ASSERT_EQ(whole.exit_code, 0) << whole.output;
  const auto &steps = whole.summary["steps"];
  ASSERT_GT(steps.size(), 60u);
  const double d_max = steps.back()["damage"]["max"].get<double>();
  EXPECT_GT(d_max, 0.01);
  EXPECT_EQ(steps[40]["damage"]["max"].get<double>(), d_max); // torn by the touch, before the checkpoint

  const auto restarted = restart_copy(args, whole);
  EXPECT_NE(restarted.output.find("restarting from the checkpoint after step 40 "), std::string::npos)
    << restarted.output;
  expect_as_uninterrupted(restarted, whole, solver_floor);

  // the checkpoint's tissue without its damage, or with the displacement's values (three
  // a node) in its place
  for (const bool removed : {true, false})
    {
      const fs::path broken =
        scratch_path() / (removed ? "restart_phase_field_no_damage" : "restart_phase_field_misfit");
      fs::remove_all(broken);
      fs::copy(whole.directory, broken, fs::copy_options::recursive);
      {
        const fs::path file  = broken / "checkpoint" / "rank-0.cbor";
        auto           state = read_cbor(file); // this process's part: the tissue's local state
        ASSERT_TRUE(state.contains("damage")) << "no damage in the checkpoint";
        if (removed)
          state.erase("damage");
        else
          state["damage"] = state["u"];
        write_cbor(file, state);
      }
      const auto refused = restart(args, broken);
      EXPECT_EQ(refused.exit_code, 2) << refused.output;
      const std::string why = removed ? "the checkpoint has no damage (written without Tissue/Phase field)"
                                      : "the checkpoint's damage does not fit this mesh's damage nodes";
      EXPECT_NE(refused.output.find("--restart: " + why), std::string::npos) << refused.output;
    }
}

TEST(Restart, WithoutACheckpointOrOnAScenarioWithoutThemIsRefused)
{
  const fs::path empty = scratch_path() / "restart_nothing";
  fs::remove_all(empty);
  fs::create_directories(empty);
  const auto none = restart(accurate_pass, empty);
  EXPECT_EQ(none.exit_code, 2) << none.output;
  EXPECT_NE(none.output.find("error: --restart " + empty.string() + ": no checkpoint"), std::string::npos)
    << none.output;
  const auto realtime = run_suturesim("checkpoint_realtime",
                                      {suturesim::test_support::source_path("parameters/needle_pass.prm"), "--set",
                                       "Time/Checkpoint steps=10"});
  EXPECT_EQ(realtime.exit_code, 2) << realtime.output;
  EXPECT_NE(realtime.output.find("Time/Checkpoint steps: only the accurate needle pass and stitch write checkpoints"),
            std::string::npos)
    << realtime.output;
}
