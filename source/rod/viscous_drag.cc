#include <suturesim/rod/viscous_drag.h>

namespace suturesim::rod
{
  ViscousDrag::ViscousDrag(const RodModel &model, const double c)
    : coefficient(c)
    , node_length(model.positions().size(), 0.0)
  {
    for (std::size_t e = 0; e < model.references().size(); ++e)
      {
        node_length[e] += 0.5 * model.references()[e].length;
        node_length[e + 1] += 0.5 * model.references()[e].length;
      }
  }

  void
  ViscousDrag::begin_step(const std::vector<Vec3> *nodes, const double dt)
  {
    start = nodes;
    step  = dt;
  }

  void
  ViscousDrag::add(const std::size_t i, const Vec3 &x, Vec6 &r, Mat6 &J) const
  {
    const double c = coefficient * node_length[i] / step;
    r.head<3>() += c * (x - (*start)[i]);
    J.topLeftCorner<3, 3>() += c * Mat3::Identity();
  }

  double
  ViscousDrag::total_force(const std::vector<Vec3> &x) const
  {
    double total = 0;
    for (std::size_t i = 1; i + 1 < node_length.size(); ++i)
      total += coefficient * node_length[i] / step * (x[i] - (*start)[i]).norm();
    return total;
  }
} // namespace suturesim::rod
