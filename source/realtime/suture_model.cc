#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/suture_model.h>

#include <cmath>
#include <stdexcept>

namespace suturesim::realtime
{
  double
  SutureGeometry::mass_per_length() const
  {
    return density * M_PI * radius * radius;
  }

  void
  SutureModel::build(System &s, const SutureGeometry &g)
  {
    if (g.points.size() < 3)
      throw ParameterError("Elements", "the realtime suture needs at least 2 segments");
    if (!(g.density > 0))
      throw ParameterError("Density", "the realtime suture needs a density > 0 kg/m^3");
    shape = g;
    double length = 0;
    for (std::size_t i = 0; i + 1 < g.points.size(); ++i)
      length += (g.points[i + 1] - g.points[i]).norm();
    link            = length / (g.points.size() - 1);
    axial_stiffness = g.EA / link;
    const double m  = g.mass_per_length() * link;
    const auto   first = s.nodes.size();
    for (std::size_t i = 0; i < g.points.size(); ++i)
      {
        const bool end = i == 0 || i + 1 == g.points.size();
        s.nodes.add(g.points[i], end ? m / 2 : m, 0);
      }
    s.suture = {first, s.nodes.size()};
    add_interactions(s, first);
  }

  void
  SutureModel::segment_tension(const System &s, std::vector<double> &tension) const
  {
    // from the suture's SpringSet (its first one): k (L − L0)
    tension.assign(s.suture.size() - 1, 0.0);
    for (const auto &i : s.interactions)
      if (const auto *springs = dynamic_cast<const SpringSet *>(i.get()))
        if (springs->name() == "suture springs")
          for (std::size_t e = 0; e < springs->size(); ++e)
            {
              const auto a = springs->first_ends()[e], b = springs->second_ends()[e];
              if (s.suture.contains(a) && b == a + 1)
                tension[a - s.suture.begin] =
                  springs->stiffnesses()[e] *
                  ((s.nodes.x.col(b) - s.nodes.x.col(a)).norm() - springs->rest_lengths()[e]);
            }
  }
} // namespace suturesim::realtime
