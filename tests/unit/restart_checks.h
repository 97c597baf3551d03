#pragma once
// A run restarted from its checkpoint (--restart) against the run that was never stopped:
// the same record to the solvers' tolerance (tests/unit/interruption_test.cc, and the
// accurate interrupted series in accurate_needle_test.cc).
#include "run_scene.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

namespace suturesim::test_support
{
  /// What a stopped or restarted run left: its exit code, output, summary.json and
  /// forces.csv.
  struct Stopped
  {
    int                              exit_code = -1;
    std::string                      output, directory;
    nlohmann::json                   summary;
    std::vector<std::vector<double>> rows;
  };

  /// `suturesim args... --restart dir`: its exit code, output, summary.json and forces.csv.
  inline Stopped
  restart(const std::vector<std::string> &args, const std::filesystem::path &dir)
  {
    Stopped s;
    s.directory = dir.string();
    s.exit_code = run_logged(join(join({suturesim_binary()}, args), {"--restart", dir.string()}),
                             dir.string() + "_restart.log", s.output, {"OPENBLAS_NUM_THREADS=1"});
    RunResult r;
    r.directory = dir.string();
    s.rows      = read_forces(r);
    std::ifstream summary(dir / "summary.json");
    if (summary)
      summary >> s.summary;
    return s;
  }

  /// restart() of a copy of @p run's folder (<folder>_restarted), which keeps the run's
  /// own outputs to compare with: a run that wrote periodic checkpoints goes on from its
  /// last.
  inline Stopped
  restart_copy(const std::vector<std::string> &args, const RunResult &run)
  {
    namespace fs         = std::filesystem;
    const fs::path copy = run.directory + "_restarted";
    fs::remove_all(copy);
    fs::copy(run.directory, copy, fs::copy_options::recursive);
    return restart(args, copy);
  }

  /// Every number under @p a (metrics, events, the steps' account) equals the one under
  /// @p b to the solvers' tolerance: relative 1e-6, absolute @p floor (N, m, m/s, N m;
  /// the scene's, see its caller). A lost friction history is seen at this tolerance: a
  /// restart whose pierce points lost their stick anchors (set to their current ζ)
  /// differed by 2.2e-3 m/s in a slip velocity. The restart is also bit for bit (below):
  /// these comparisons say where and by how much it is not.
  inline void
  expect_same_numbers(const nlohmann::json &a, const nlohmann::json &b, const std::string &path, const double floor)
  {
    ASSERT_EQ(a.type(), b.type()) << path;
    if (a.is_number())
      EXPECT_NEAR(a.get<double>(), b.get<double>(), 1e-6 * std::abs(b.get<double>()) + floor) << path;
    else if (a.is_object())
      {
        ASSERT_EQ(a.size(), b.size()) << path;
        for (auto it = b.begin(); it != b.end(); ++it)
          {
            ASSERT_TRUE(a.contains(it.key())) << path << "/" << it.key();
            expect_same_numbers(a[it.key()], it.value(), path + "/" + it.key(), floor);
          }
      }
    else if (a.is_array())
      {
        ASSERT_EQ(a.size(), b.size()) << path;
        for (std::size_t k = 0; k < a.size(); ++k)
          expect_same_numbers(a[k], b[k], path + "/" + std::to_string(k), floor);
      }
    else
      EXPECT_EQ(a, b) << path;
  }

  /// A restarted run's record against the uninterrupted one's (in another folder): status,
  /// metrics, events, the steps' solver account, the .pvd series and forces.csv row by
  /// row, numbers as expect_same_numbers() with @p floor; and forces.csv to the byte.
  /// The restart takes the same steps from the same state, each double as saved, the
  /// suture's rotations too (rod::RodModel::restore_node()). Normalised again when they
  /// were set back, they changed in their last bit; the stick-slip steps after it
  /// amplified that to 3.1e-10 N on the accurate series, and on the path it took on
  /// 2026-12-05 (closed at 5.29 s) flipped a pierce point from stick to slip. Since, the
  /// four restart tests' forces.csv are identical to the byte.
  inline void
  expect_as_uninterrupted(const Stopped &restarted, const RunResult &whole, const double floor)
  {
    namespace fs = std::filesystem;
    EXPECT_EQ(restarted.exit_code, 0) << restarted.output;
    ASSERT_FALSE(restarted.summary.is_null()) << restarted.output;
    ASSERT_NE(fs::canonical(restarted.directory), fs::canonical(whole.directory));
    EXPECT_EQ(restarted.summary["status"], "completed");
    for (const char *part : {"metrics", "events", "steps"})
      expect_same_numbers(restarted.summary[part], whole.summary[part], part, floor);
    expect_same_numbers(restarted.summary["solver"]["steps"], whole.summary["solver"]["steps"], "solver/steps", floor);
    // the series list the uninterrupted run's states, no more (after deal.II's comment
    // with the time the file was written)
    const auto collection = [](const std::string &file) {
      const std::string text = read_text(file);
      return text.substr(std::min(text.size(), text.find("<VTKFile")));
    };
    for (const char *series : {"tissue.pvd", "suture.pvd"})
      EXPECT_EQ(collection((fs::path(restarted.directory) / series).string()),
                collection((fs::path(whole.directory) / series).string()))
        << series;
    const auto rows = read_forces(whole);
    ASSERT_EQ(restarted.rows.size(), rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i)
      for (std::size_t j = 0; j < rows[i].size(); ++j)
        if (std::isnan(rows[i][j])) // a tear criterion before its first tract
          EXPECT_TRUE(std::isnan(restarted.rows[i][j])) << "row " << i << " column " << j;
        else
          EXPECT_NEAR(restarted.rows[i][j], rows[i][j], 1e-6 * std::abs(rows[i][j]) + floor)
            << "row " << i << " column " << j;
    const std::string ours = read_text(restarted.directory + "/forces.csv");
    EXPECT_TRUE(ours == read_text(whole.directory + "/forces.csv"))
      << "the restarted run's forces.csv is not the uninterrupted run's to the byte";
  }
} // namespace suturesim::test_support
