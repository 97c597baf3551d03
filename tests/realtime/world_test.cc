// The realtime world as a haptic loop uses it: the force a tool feels, and a step that
// never allocates.
#include <gtest/gtest.h>

#include "realtime/allocation_counter.h"
#include "realtime/test_meshes.h"
#include "realtime/test_worlds.h"

#include <cctype>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

using namespace suturesim;
using namespace suturesim::realtime;

TEST(RealtimeWorld, XpbdToolFeelsTheWeightItHoldsEvenWithFewIterations)
{
  // A real 3-0 suture (EA = 118 N) hangs from a tool under gravity. Two XPBD iterations
  // cannot resolve its stretch (k = EA/l = 2.4e4 N/m per link), so k·C of the residual
  // stretch is no force to render; the multipliers λ/dt² are (Macklin et al. 2016 §4),
  // and at rest they carry exactly the suture's weight.
  WorldSetup w;
  w.suture          = test_support::make_model<SutureModel::Registry>("xpbd-rod");
  w.suture_geometry = test_support::straight_suture(20, 0.1, Vector3d::Zero(), -Vector3d::UnitZ(),
                                                    118, 3.7e-7, 1.12e-4, 1140);
  w.integrator      = test_support::make_model<Integrator::Registry>(
    "xpbd", {{"Iterations", "2"}, {"Damping rate", "20"}});
  w.gravity         = Vector3d(0, 0, -9.81);
  World world(std::move(w));
  const auto s = world.system().suture;
  world.add_tool("grasper", {s.begin}, {});
  world.initialize();
  ToolPose pose;
  for (int k = 0; k < 3000; ++k)
    world.step({pose});
  // the grasper carries the whole suture, the node it holds included
  double weight = 0;
  for (auto i = s.begin; i < s.end; ++i)
    weight += world.system().nodes.mass[i] * 9.81;
  const Vector3d f = world.tool_forces()[0].force;
  std::printf("[ tool force ] %.6e N against the suture's weight %.6e N\n", -f[2], weight);
  EXPECT_NEAR(-f[2], weight, 1e-3 * weight);
  EXPECT_LT(f.head<2>().norm(), 1e-6 * weight);
}

namespace
{
  /// The system nodes of the box's fixed face (tag 1).
  std::vector<std::uint32_t>
  reactions_nodes(const World &world, const mesh::SimplexMesh &mesh)
  {
    return world.nodes_of_vertices(mesh::vertices_with_tag(mesh::extract_boundary(mesh), 1));
  }

  /// −Σ over @p nodes of every interaction's and contact's force (as the integrator
  /// applied them), the external loads and the weight: the reaction the long way; the
  /// sum of the nodes' force magnitudes Σ|fᵢ| into @p scale.
  Vector3d
  whole_reaction(const World &world, const std::vector<std::uint32_t> &nodes, double &scale)
  {
    const System     &sys    = world.system();
    const bool        xpbd   = world.integrator().position_based();
    const std::size_t primal = world.integrator().first_constraint_interaction(sys); // vbd's tissue
    Matrix3Xd         f      = Matrix3Xd::Zero(3, sys.nodes.size());
    for (std::size_t k = 0; k < sys.interactions.size(); ++k)
      xpbd && k >= primal ? sys.interactions[k]->add_constraint_forces(sys.nodes.x, f, world.dt())
                          : sys.interactions[k]->add_forces(sys.nodes.x, f);
    for (const auto &c : sys.contacts)
      xpbd ? c->add_constraint_forces(sys.nodes.x, f, world.dt()) : c->add_forces(sys.nodes.x, f);
    f += sys.nodes.external;
    f.noalias() += sys.gravity * sys.nodes.mass.transpose();
    Vector3d r = Vector3d::Zero();
    scale      = 0;
    for (const auto i : nodes)
      {
        r -= f.col(i);
        scale += f.col(i).norm();
      }
    return r;
  }
} // namespace

/// tissue, integrator, suture, self-collision, and the integrator's settings
/// ("key=value;key=value")
class NoAllocation
  : public ::testing::TestWithParam<std::tuple<std::string, std::string, std::string, std::string, std::string>>
{};

TEST_P(NoAllocation, StepDoesNotAllocate)
{
  const auto [tissue_and_settings, integrator, suture, self, settings] = GetParam();
  const auto settings_of = [](const std::string &text) {
    std::map<std::string, std::string> values;
    std::stringstream                  list(text);
    for (std::string item; std::getline(list, item, ';');)
      values[item.substr(0, item.find('='))] = item.substr(item.find('=') + 1);
    return values;
  };
  // "model;key=value;…": the tissue model's own settings after its name
  const auto tissue = tissue_and_settings.substr(0, tissue_and_settings.find(';'));
  const auto tissue_values
    = settings_of(tissue == tissue_and_settings ? "" : tissue_and_settings.substr(tissue.size() + 1));
  auto       values = settings_of(settings);
  // the world's own setting among them: the ftl thread's contact load, whose step takes
  // the links' tensions at the nodes the contact holds (this thread, held at one end
  // only, has no section and no tension: the check is on the step's work arrays, not
  // on the load)
  const bool contact_load = values.count("Contact load") != 0 && values.at("Contact load") == "true";
  values.erase("Contact load");
  const auto mesh = test_support::box_mesh(0.02, 0.02, 0.01, 4, 4, 2);
  // a 40-link suture folded onto itself over the tissue: contact and self-collision act
  WorldSetup w
    = test_support::block_under_folded_suture(mesh, tissue, integrator, values, suture, self, 40, tissue_values);
  w.contact_load = contact_load;
  // the counter sees what the realtime library allocates (World's set-up is in it): an
  // allocator hook that failed to take would count nothing below, and pass
  test_support::start_counting_allocations();
  World world(std::move(w));
  world.fix_vertices(mesh::vertices_with_tag(mesh::extract_boundary(mesh), 1));
  const auto s = world.system().suture;
  world.add_tool("grasper", {s.end - 1}, {world.system().nodes.x.col(s.end - 1)});
  world.initialize();
  const auto setup = test_support::stop_counting_allocations();
  EXPECT_GT(setup.malloc, 0u) << "Eigen's matrices";
  EXPECT_EQ(setup.operator_new > 0, test_support::operator_new_counted_apart)
    << "std::vector's buffers";
  const SelfCollision *self_collision = nullptr;
  for (const auto &c : world.system().contacts)
    if (const auto *p = dynamic_cast<const SelfCollision *>(c.get()))
      self_collision = p;
  ASSERT_EQ(self_collision != nullptr, self != "off");
  ASSERT_NE(world.surface_contact(), nullptr);
  if (values.count("Threads") != 0) // the tissue's springs cut into slabs before the first step
    {
      EXPECT_NE(world.system().interactions[0]->blocks(), nullptr) << world.system().interactions[0]->name();
    }
  // the fixed boundary's reaction, as a forces.csv row records it every tick
  auto reactions = world.reaction_set(
    world.nodes_of_vertices(mesh::vertices_with_tag(mesh::extract_boundary(mesh), 1)));
  std::vector<ToolPose> poses(1);
  poses[0].position = world.system().nodes.x.col(s.end - 1);
  const auto move = [&] {
    poses[0].position += Vector3d(-1e-5, 0, 1e-5);
    world.step(poses);
  };
  for (int k = 0; k < 5; ++k) // warm-up: first contacts and pairs size the work lists
    {
      move();
      // the reaction renews its element lists once a family was reordered (the slabs of
      // Threads = 2 at the first step)
      world.reaction(reactions);
    }
  // the interactions the set-up means to exercise: suture-tissue contacts and
  // self-collision pairs (their number after each step, summed)
  std::size_t contacts = 0, self_pairs = 0;
  test_support::start_counting_allocations();
  for (int k = 0; k < 200; ++k)
    {
      move();
      world.reaction(reactions);
      contacts += world.surface_contact()->active();
      self_pairs += self_collision ? self_collision->active() : 0;
    }
  const auto step = test_support::stop_counting_allocations();
  std::printf("[ allocation ] %s/%s/%s/%s: %zu contacts, %zu self-collision pairs (summed over "
              "the steps); %zu operator new, %zu malloc in 200 steps\n",
              tissue.c_str(), integrator.c_str(), suture.c_str(), self.c_str(), contacts,
              self_pairs, step.operator_new, step.malloc);
  EXPECT_GT(contacts, 0u);
  EXPECT_EQ(self_pairs > 0, self != "off");
  EXPECT_EQ(step.total(), 0u);
  // the reaction from the elements touching the boundary is the sum over all, to
  // round-off: the springs and volumes sum over the boundary's nodes themselves
  // (Interaction::add_constraint_forces_on), in another order than node by node
  double         scale = 0;
  const Vector3d some = world.reaction(reactions), all = whole_reaction(world, reactions_nodes(world, mesh), scale);
  std::printf("[ reaction ] (%.17g, %.17g, %.17g) N, off the sum over all by %.3g N (sum of |f_i| %.3g N)\n", some[0],
              some[1], some[2], (some - all).cwiseAbs().maxCoeff(), scale);
  EXPECT_GT(some.norm(), 0);
  for (int d = 0; d < 3; ++d)
    EXPECT_NEAR(some[d], all[d], 1e-13 * scale) << "component " << d;
}

INSTANTIATE_TEST_SUITE_P(
  RealtimeWorld, NoAllocation,
  ::testing::Values(std::tuple{"volume", "xpbd", "xpbd-rod", "transient-constraint", ""},
                    std::tuple{"volume", "xpbd", "xpbd-rod", "transient-constraint", "Warm start=true;Threads=2"},
                    std::tuple{"volume", "vbd", "xpbd-rod", "transient-constraint", ""},
                    std::tuple{"fe", "vbd", "xpbd-rod", "transient-constraint", ""},
                    std::tuple{"fe;Volumetric energy=nodal", "vbd", "xpbd-rod", "transient-constraint", ""},
                    std::tuple{"volume", "xpbd", "xpbd-rod", "repelling-force", ""},
                    std::tuple{"surface", "quasi-static", "mass-spring", "repelling-force", ""},
                    std::tuple{"surface", "quasi-static", "ftl", "transient-constraint", ""},
                    std::tuple{"surface", "quasi-static", "ftl", "transient-constraint", "Contact load=true"},
                    std::tuple{"volume", "symplectic-euler", "mass-spring", "off", ""}),
  [](const auto &info) {
    std::string name = std::get<0>(info.param) + "_" + std::get<1>(info.param) + "_" +
                       std::get<2>(info.param) + "_" + std::get<3>(info.param) +
                       (std::get<4>(info.param).empty()                                  ? ""
                        : std::get<4>(info.param).find("Threads") != std::string::npos ? "_warm_2_threads"
                                                                                          : "_contact_load");
    for (auto &c : name)
      if (!std::isalnum(static_cast<unsigned char>(c)))
        c = '_';
    return name;
  });
