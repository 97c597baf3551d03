#include <suturesim/realtime/divergence_guard.h>

#include <cmath>
#include <sstream>

namespace suturesim::realtime
{
  void
  DivergenceGuard::setup(const System &s, const double h, std::string likely_cause)
  {
    const double L = s.length_scale();
    energy_bound   = 0.5 * s.nodes.mass.sum() * (L / h) * (L / h);
    cause          = std::move(likely_cause);
  }

  std::string
  DivergenceGuard::describe_node(const System &s, const std::uint32_t node) const
  {
    std::ostringstream d;
    if (s.suture.contains(node))
      d << "suture node " << node - s.suture.begin;
    else
      d << "tissue node " << node - s.tissue.begin;
    const Vector3d X = s.nodes.reference.col(node);
    d << " (rest position " << X[0] << ", " << X[1] << ", " << X[2] << " m)";
    return d.str();
  }

  std::string
  DivergenceGuard::check(const System &s, const std::size_t step) const
  {
    const Nodes &n = s.nodes;
    if (!n.x.allFinite() || !n.v.allFinite())
      {
        std::uint32_t node = 0;
        while (node < n.size() && n.x.col(node).allFinite() && n.v.col(node).allFinite())
          ++node;
        std::ostringstream d;
        d << "diverged at step " << step << ": " << describe_node(s, node)
          << " has a non-finite position or velocity; likely cause: " << cause;
        return d.str();
      }
    const double kinetic = s.kinetic_energy();
    if (kinetic > energy_bound)
      {
        Eigen::Index node;
        n.v.colwise().squaredNorm().maxCoeff(&node);
        std::ostringstream d;
        d << "diverged at step " << step << ": runaway kinetic energy " << kinetic
          << " J (bound " << energy_bound << " J), fastest " << describe_node(s, node) << " at "
          << n.v.col(node).norm() << " m/s; likely cause: " << cause;
        return d.str();
      }
    return "";
  }
} // namespace suturesim::realtime
