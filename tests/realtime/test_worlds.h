#pragma once
// Builds registered realtime models and small worlds for the tests.
#include <suturesim/realtime/self_collision.h>
#include <suturesim/realtime/world.h>
#include <suturesim/tools/surgical_pass.h>

#include <cmath>
#include <map>
#include <memory>
#include <string>

namespace suturesim::test_support
{
  /// The registered model @p name of @p Registry with its default parameters, some
  /// overridden by @p values.
  template <typename Registry, typename... Args>
  auto
  make_model(const std::string &name, const std::map<std::string, std::string> &values = {},
             const Args &...args)
  {
    const auto                      &entry = Registry::instance().get(name);
    ParameterDeclarations d;
    if (entry.declare_parameters)
      entry.declare_parameters(d);
    auto p = ParameterValues::defaults(d);
    for (const auto &[k, v] : values)
      p.set(k, v);
    return entry.create(p, args...);
  }

  inline ParameterValues
  parameters_of(const std::string &self_collision, const std::map<std::string, std::string> &values = {})
  {
    ParameterDeclarations d;
    if (self_collision != "off")
      if (const auto &f = realtime::SelfCollision::Registry::instance().get(self_collision).declare_parameters)
        f(d);
    auto p = ParameterValues::defaults(d);
    for (const auto &[k, v] : values)
      p.set(k, v);
    return p;
  }

  /// A straight suture of @p n segments from @p start along @p direction.
  inline realtime::SutureGeometry
  straight_suture(const unsigned n, const double length, const Eigen::Vector3d &start,
                  const Eigen::Vector3d &direction, const double EA = 100, const double EI = 1e-6,
                  const double radius = 1e-4, const double density = 1100)
  {
    realtime::SutureGeometry g;
    for (unsigned i = 0; i <= n; ++i)
      g.points.push_back(start + length * i / n * direction.normalized());
    g.radius  = radius;
    g.EA      = EA;
    g.EI      = EI;
    g.density = density;
    return g;
  }

  /// A suture folded across itself, 60 links of 1 mm: strand A along +x from
  /// (−10, 0, 0) mm (nodes 0–20), a connector (10 links along −y rising to z = @p height,
  /// 10 along −x), strand B along +y (nodes 40–60) at z = @p height, crossing above A's
  /// node 10 between its nodes 49 and 50.
  inline realtime::SutureGeometry
  folded_suture(const double height, const double EA, const double EI, const double radius)
  {
    const double             link = 1e-3;
    realtime::SutureGeometry g    = straight_suture(1, link, Eigen::Vector3d(-0.01, 0, 0),
                                                    Eigen::Vector3d::UnitX(), EA, EI, radius, 1100);
    g.points.resize(1);
    const double sine = height / (10 * link), cosine = std::sqrt(1 - sine * sine);
    const auto   walk = [&](const Eigen::Vector3d &direction, const int n) {
      for (int i = 0; i < n; ++i)
        g.points.push_back(g.points.back() + link * direction);
    };
    walk(Eigen::Vector3d::UnitX(), 20);
    walk(Eigen::Vector3d(0, -cosine, sine), 10);
    walk(-Eigen::Vector3d::UnitX(), 10);
    walk(Eigen::Vector3d::UnitY(), 20);
    return g;
  }

  /// The needle tests' pass through the top of the 40 × 40 × 10 mm block: in at
  /// (13, 20.1, 10) mm along +x, @p bite_depth deep, turning at 4 rad/s after a 0.5 mm
  /// approach, then pulled by (10, 0, 20) mm over 0.5 s.
  inline tools::SurgicalPass
  block_pass(const tools::CurvedNeedle &needle, const double bite_depth)
  {
    tools::PassParameters p;
    p.entry          = Eigen::Vector3d(0.013, 0.0201, 0.01);
    p.normal         = Eigen::Vector3d::UnitZ();
    p.bite_direction = Eigen::Vector3d::UnitX();
    p.bite_depth     = bite_depth;
    p.angular_speed  = 4;
    p.approach       = 5e-4;
    p.pull           = Eigen::Vector3d(0.01, 0, 0.02);
    p.pull_duration  = 0.5;
    return tools::plan_pass(needle, p);
  }

  /// A 20 mm FTL suture of 20 links along x, held by the tools "left" (at the origin)
  /// and "right" (at x = 20 mm), initialised; @p ftl overrides its parameters (gravity off).
  inline std::unique_ptr<realtime::World>
  held_ftl_suture(const std::string &integrator, std::map<std::string, std::string> ftl)
  {
    ftl.emplace("Gravity speed", "0");
    realtime::WorldSetup w;
    w.suture          = make_model<realtime::SutureModel::Registry>("ftl", ftl);
    w.suture_geometry = straight_suture(20, 0.02, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
    w.integrator      = make_model<realtime::Integrator::Registry>(integrator);
    auto        world = std::make_unique<realtime::World>(std::move(w));
    const auto &s     = world->system();
    world->add_tool("left", {s.suture.begin}, realtime::ToolPose());
    realtime::ToolPose right;
    right.position = s.nodes.x.col(s.suture.end - 1);
    world->add_tool("right", {s.suture.end - 1}, right);
    world->initialize();
    return world;
  }
} // namespace suturesim::test_support
