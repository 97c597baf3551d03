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

  /// Friction on a sliding point opposes the slip: the thread sliding through the hole
  /// (its anchor ζ_a moving along it at dζ_a/dt) drags the tissue with it, so the force
  /// on the tissue point along the thread has the opposite sign of dζ_a/dt, in every
  /// pierce model (the recorded value is what is compared with the accurate path's).
  /// Counts the sliding points in @p slips.
  inline bool
  friction_dissipates(const realtime::PiercePointState &q, std::size_t &slips)
  {
    if (!q.slipping || q.slip_speed == 0)
      return true;
    ++slips;
    return q.friction * q.slip_speed < 0;
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

  /// A block tissue (@p mesh, its face of tag 1 to be fixed) under a soft suture of
  /// @p links links, 30 mm long, laid along +x 0.2 mm above the top z = 10 mm and folded
  /// back onto itself at its middle, so that suture–tissue contact and self-collision are
  /// active from the first step; gravity on. The integrator and models by name.
  inline realtime::WorldSetup
  block_under_folded_suture(const mesh::SimplexMesh &mesh, const std::string &tissue, const std::string &integrator,
                            const std::map<std::string, std::string> &integrator_values, const std::string &suture,
                            const std::string &self, const unsigned links,
                            const std::map<std::string, std::string> &tissue_values = {})
  {
    realtime::WorldSetup w;
    w.mesh     = &mesh;
    w.material = {6e3, 0.45, 1060, {}}; // E (Pa), ν, ρ (kg/m³), no regions
    w.tissue   = make_model<realtime::TissueModel::Registry>(tissue, tissue_values);
    w.suture   = make_model<realtime::SutureModel::Registry>(suture);
    // soft enough for the force-based integrators at 1 kHz
    w.suture_geometry = straight_suture(links, 0.03, Eigen::Vector3d(0.002, 0.01, 0.0102), Eigen::Vector3d::UnitX(),
                                        1e-3, 1e-9, 1e-4, 1140);
    for (std::size_t i = links / 2 + 1; i < w.suture_geometry.points.size(); ++i)
      w.suture_geometry.points[i] = w.suture_geometry.points[links - i] + Eigen::Vector3d(0, 0.0002, 0.0002);
    w.self_collision            = self;
    w.self_collision_parameters = parameters_of(self);
    w.contact                   = true;
    w.contact_stiffness         = 1;
    w.contact_depth             = 1e-3;
    w.integrator                = make_model<realtime::Integrator::Registry>(integrator, integrator_values);
    w.gravity                   = Eigen::Vector3d(0, 0, -9.81);
    w.substeps                  = integrator == "symplectic-euler" ? 16 : 4; // below dt_crit
    return w;
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

  /// The needle tests' block world: volume tissue (E = 100 kPa, ν = 0.3) on @p mesh (the
  /// 40 × 40 × 10 mm block, fix its bottom), an ftl suture (100 links, 0.1 m, EA 119 N)
  /// leaving the swage of @p needle at pose @p start backwards along it, suture–tissue
  /// contact, quasi-static (tissue damping 0.5 N s/m, four substeps).
  inline realtime::WorldSetup
  needle_block(const mesh::SimplexMesh &mesh, const tools::CurvedNeedle &needle, const tools::Pose &start)
  {
    realtime::WorldSetup w;
    w.mesh              = &mesh;
    w.material          = {1e5, 0.3, 1100, {}};
    w.tissue            = make_model<realtime::TissueModel::Registry>("volume");
    w.suture            = make_model<realtime::SutureModel::Registry>("ftl");
    w.suture_geometry   = straight_suture(100, 0.1, needle.swage(start), -needle.tangent(start, needle.length()), 119,
                                          3e-9, 1.1e-4, 1100);
    w.contact_stiffness = 100;
    w.contact_depth     = 1e-3;
    w.integrator        = make_model<realtime::Integrator::Registry>("quasi-static", {{"Tissue damping", "0.5"}});
    w.substeps          = 4;
    return w;
  }

  /// Its needle coupling: puncture at 0.5 N (k_c 2000 N/m, reach 1 mm), friction @p mu
  /// with k_t 500 N/m and grip 0.05 N, k⊥ 500 N/m.
  inline realtime::NeedleCouplingParameters
  needle_block_coupling(const double mu)
  {
    realtime::NeedleCouplingParameters p;
    p.puncture             = {0.5, 2000, 1e-3};
    p.friction             = {mu, 500, 0.05};
    p.transverse_stiffness = 500;
    return p;
  }

  /// A 20 mm FTL suture of @p links links along x, held by the tools "left" (at the origin)
  /// and "right" (at x = 20 mm), initialised; @p ftl overrides its parameters (gravity off).
  inline std::unique_ptr<realtime::World>
  held_ftl_suture(const std::string &integrator, std::map<std::string, std::string> ftl, const unsigned links = 20)
  {
    ftl.emplace("Gravity speed", "0");
    realtime::WorldSetup w;
    w.suture          = make_model<realtime::SutureModel::Registry>("ftl", ftl);
    w.suture_geometry = straight_suture(links, 0.02, Eigen::Vector3d::Zero(), Eigen::Vector3d::UnitX());
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
