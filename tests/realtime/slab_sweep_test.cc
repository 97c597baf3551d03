// The threads of the realtime step: the worker team's hand-overs and the slabs' blocks
// (slab_sweep.h, independent_order.h).
#include <suturesim/core/worker_team.h>
#include <suturesim/mesh/simplex_mesh.h>
#include <suturesim/realtime/independent_order.h>
#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/volume_constraints.h>

#include <gtest/gtest.h>

#include "realtime/test_meshes.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <vector>

using namespace suturesim;
using realtime::Matrix3Xd;
using realtime::Vector3d;
using realtime::VectorXd;

TEST(WorkerTeam, RunGivesEveryThreadItsPartAndReturnsWhenAllAreDone)
{
  WorkerTeam team(3);
  ASSERT_EQ(team.size(), 3u);
  for (int round = 0; round < 200; ++round) // many hand-overs, each complete on return
    {
      std::vector<std::thread::id> who(3);
      std::vector<int>             sum(3, 0);
      team.run([&](const unsigned t) {
        who[t] = std::this_thread::get_id();
        for (int k = 0; k <= round % 50; ++k)
          sum[t] += k;
      });
      for (unsigned t = 0; t < 3; ++t)
        ASSERT_EQ(sum[t], (round % 50) * (round % 50 + 1) / 2) << "round " << round << " thread " << t;
      EXPECT_EQ(who[0], std::this_thread::get_id()); // part 0 is the caller's
      EXPECT_NE(who[1], who[0]);
      EXPECT_NE(who[2], who[0]);
      EXPECT_NE(who[1], who[2]);
    }
}

TEST(WorkerTeam, StartRunsBesideTheCallerUntilWait)
{
  WorkerTeam       team(2);
  std::atomic<int> stage{0};
  const auto       job = [&](unsigned) {
    while (stage.load() != 1) // waits for the caller: both run at once
      std::this_thread::yield();
    stage = 2;
  };
  team.start(job);
  stage = 1;
  team.wait();
  EXPECT_EQ(stage.load(), 2);
}

TEST(WorkerTeam, AHelpersExceptionReachesTheCallerAndTheTeamGoesOn)
{
  WorkerTeam team(2);
  EXPECT_THROW(team.run([](const unsigned t) {
    if (t == 1)
      throw std::runtime_error("helper failed");
  }),
               std::runtime_error);
  int parts = 0;
  team.run([&](unsigned) { __atomic_add_fetch(&parts, 1, __ATOMIC_RELAXED); });
  EXPECT_EQ(parts, 2);
}

TEST(BlockOrder, BlocksHoldTheirSlabsConstraintsAndTheInterfaceTheRest)
{
  // a block's tetrahedra, its nodes cut into three slabs along x
  const auto mesh  = test_support::box_mesh(0.03, 0.01, 0.01, 6, 2, 2);
  const auto parts = 3u;
  std::vector<std::uint32_t> part(mesh.vertices.cols());
  for (Eigen::Index i = 0; i < mesh.vertices.cols(); ++i)
    part[i] = std::min(parts - 1, static_cast<unsigned>(mesh.vertices(0, i) / 0.03 * parts));
  const auto blocked = realtime::block_order(mesh.tetrahedra, part, parts);
  ASSERT_EQ(blocked.blocks.size(), parts + 2);
  EXPECT_EQ(blocked.blocks.front(), 0u);
  EXPECT_EQ(blocked.blocks.back(), mesh.tetrahedra.size());
  // a permutation
  auto sorted = blocked.order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::size_t> all(mesh.tetrahedra.size());
  std::iota(all.begin(), all.end(), 0);
  EXPECT_EQ(sorted, all);
  std::size_t spanning = 0;
  for (unsigned p = 0; p <= parts; ++p)
    {
      if (p < parts)
        {
          EXPECT_GT(blocked.blocks[p + 1], blocked.blocks[p]) << "slab " << p << " has constraints";
        }
      for (auto k = blocked.blocks[p]; k < blocked.blocks[p + 1]; ++k)
        {
          const auto &t    = mesh.tetrahedra[blocked.order[k]];
          bool        same = true;
          for (const auto v : t)
            same = same && part[v] == part[t[0]];
          if (p < parts)
            {
              for (const auto v : t)
                ASSERT_EQ(part[v], p) << "tetrahedron " << blocked.order[k] << " in block " << p;
            }
          else
            {
              EXPECT_FALSE(same) << "the interface holds only tetrahedra spanning slabs";
              ++spanning;
            }
        }
    }
  EXPECT_GT(spanning, 0u);
  // within a block consecutive tetrahedra share no node where the colouring allows
  // (independent_order): the first two of block 0
  const auto &a = mesh.tetrahedra[blocked.order[0]], &b = mesh.tetrahedra[blocked.order[1]];
  for (const auto v : a)
    EXPECT_EQ(std::count(b.begin(), b.end(), v), 0);
}

TEST(WorkerTeam, TheCallersExceptionWaitsForTheHelpersParts)
{
  WorkerTeam       team(2);
  std::atomic<int> helper_done{0};
  EXPECT_THROW(team.run([&](const unsigned t) {
    if (t == 0)
      throw std::runtime_error("caller failed");
    std::this_thread::sleep_for(std::chrono::milliseconds(20)); // still working when the caller throws
    helper_done = 1;
  }),
               std::runtime_error);
  EXPECT_EQ(helper_done.load(), 1) << "run() returned before the helper's part ended";
  int parts = 0;
  team.run([&](unsigned) { __atomic_add_fetch(&parts, 1, __ATOMIC_RELAXED); });
  EXPECT_EQ(parts, 2);
}

TEST(SpinGate, HelpersPassOnceTheCallerOpensItAndSeeWhatItWroteBefore)
{
  // the first sweep's hand-over (SlabSweep::sweep_beside_detection): the helper has work
  // of its own first, then needs what the caller wrote before open()
  WorkerTeam    team(2);
  SpinGate      gate;
  std::uint64_t written = 0, seen = 0;
  bool          passed  = false;
  gate.close();
  team.run([&](const unsigned t) {
    if (t == 0)
      {
        std::this_thread::sleep_for(std::chrono::milliseconds(20)); // the helper waits at the gate meanwhile
        written = 0x5eed;
        gate.open();
      }
    else
      {
        passed = gate.pass();
        seen   = written;
      }
  });
  EXPECT_TRUE(passed);
  EXPECT_EQ(seen, 0x5eedu) << "the helper passed before the caller opened the gate";
  // abandoned: the helper's part returns without the caller's work, and run() rethrows
  gate.close();
  bool swept = false;
  EXPECT_THROW(team.run([&](const unsigned t) {
    if (t == 0)
      {
        gate.abandon();
        throw std::runtime_error("start failed");
      }
    if (gate.pass())
      swept = true;
  }),
               std::runtime_error);
  EXPECT_FALSE(swept);
}

namespace
{
  /// Sweeps @p whole with project() and @p parted block by block, each on a copy of its
  /// slab's nodes, then the interface, both partitioned alike, and checks that the two
  /// are the same sweep bit for bit (positions and multipliers, through the constraint
  /// forces); then that a second partition() keeps the constraint forces (every array
  /// permuted alike).
  template <typename Family>
  void
  check_blocks_sweep_as_the_whole(Family &whole, Family &parted, const mesh::SimplexMesh &mesh)
  {
    const unsigned     parts = 2;
    const Eigen::Index n     = mesh.vertices.cols();
    std::vector<std::uint32_t>              part(n), local(n);
    std::vector<std::vector<std::uint32_t>> slab(parts);
    for (Eigen::Index i = 0; i < n; ++i)
      {
        part[i]  = mesh.vertices(0, i) < 0.015 ? 0 : 1;
        local[i] = static_cast<std::uint32_t>(slab[part[i]].size());
        slab[part[i]].push_back(static_cast<std::uint32_t>(i));
      }
    ASSERT_TRUE(whole.partition(part, local, parts));
    ASSERT_TRUE(parted.partition(part, local, parts));
    ASSERT_NE(parted.blocks(), nullptr);
    Matrix3Xd x = mesh.vertices;
    for (Eigen::Index i = 0; i < n; ++i) // a deterministic perturbation
      x.col(i) += 4e-4 * Vector3d(std::sin(3.0 * i), std::cos(5.0 * i), std::sin(7.0 * i));
    VectorXd w = VectorXd::Constant(n, 40.0);
    w[0]       = 0; // a held node
    const double dt = 1e-3;
    whole.prepare_projection(dt);
    parted.prepare_projection(dt);
    Matrix3Xd a = x, b = x;
    for (int sweep = 0; sweep < 3; ++sweep)
      {
        whole.project(a, w, dt);
        for (unsigned p = 0; p < parts; ++p)
          {
            Matrix3Xd xs(3, slab[p].size());
            VectorXd  ws(slab[p].size());
            for (std::size_t k = 0; k < slab[p].size(); ++k)
              xs.col(k) = b.col(slab[p][k]), ws[k] = w[slab[p][k]];
            parted.project_block(p, xs, ws, dt);
            for (std::size_t k = 0; k < slab[p].size(); ++k)
              b.col(slab[p][k]) = xs.col(k);
          }
        parted.project_range(b, w, dt, (*parted.blocks())[parts], parted.blocks()->back());
      }
    EXPECT_GT((a - x).norm(), 0) << "the sweeps moved the nodes";
    EXPECT_TRUE((a.array() == b.array()).all()) << "largest difference " << (a - b).cwiseAbs().maxCoeff();
    Matrix3Xd fa = Matrix3Xd::Zero(3, n), fb = Matrix3Xd::Zero(3, n);
    whole.add_constraint_forces(a, fa, dt);
    parted.add_constraint_forces(b, fb, dt);
    EXPECT_GT(fa.norm(), 0);
    EXPECT_TRUE((fa.array() == fb.array()).all()) << "the multipliers differ";
    // the forces block by block on the slabs' copies, then the interface (the warm
    // start's refresh on threads): the same terms at each node in another order
    Matrix3Xd fd = Matrix3Xd::Zero(3, n);
    for (unsigned p = 0; p < parts; ++p)
      {
        Matrix3Xd xs(3, slab[p].size()), fs = Matrix3Xd::Zero(3, slab[p].size());
        for (std::size_t k = 0; k < slab[p].size(); ++k)
          xs.col(k) = b.col(slab[p][k]);
        parted.add_constraint_forces_block(p, xs, fs, dt);
        for (std::size_t k = 0; k < slab[p].size(); ++k)
          fd.col(slab[p][k]) = fs.col(k);
      }
    parted.add_constraint_forces_range(b, fd, dt, (*parted.blocks())[parts], parted.blocks()->back());
    EXPECT_LT((fd - fb).cwiseAbs().maxCoeff(), 1e-13 * fb.cwiseAbs().maxCoeff());
    // a new partition (another order) keeps every constraint's data together
    for (auto &p : part)
      p = 1 - p;
    ASSERT_TRUE(parted.partition(part, local, parts));
    Matrix3Xd fc = Matrix3Xd::Zero(3, n);
    parted.add_constraint_forces(b, fc, dt);
    EXPECT_LT((fc - fb).cwiseAbs().maxCoeff(), 1e-12 * fb.cwiseAbs().maxCoeff());
  }
} // namespace

TEST(SlabSweep, BlocksOnSlabCopiesThenTheInterfaceAreTheWholeSweepInTheSameOrder)
{
  const auto                 mesh = test_support::box_mesh(0.03, 0.01, 0.01, 6, 2, 2);
  std::vector<std::uint32_t> node(mesh.vertices.cols());
  std::iota(node.begin(), node.end(), 0);
  realtime::SpringSet springs_a("a"), springs_b("b");
  realtime::add_volume_springs(springs_a, mesh, node, 6e3);
  realtime::add_volume_springs(springs_b, mesh, node, 6e3);
  springs_a.sort();
  springs_b.sort();
  check_blocks_sweep_as_the_whole(springs_a, springs_b, mesh);
  realtime::VolumeConstraints volumes_a, volumes_b;
  volumes_a.add_mesh(mesh, node, 2e4);
  volumes_b.add_mesh(mesh, node, 2e4);
  check_blocks_sweep_as_the_whole(volumes_a, volumes_b, mesh);
}
