#include <suturesim/realtime/spring_set.h>
#include <suturesim/realtime/suture_model.h>

#include <cmath>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>

namespace suturesim::realtime
{
  double
  SutureGeometry::mass_per_length() const
  {
    return density * M_PI * radius * radius;
  }

  namespace
  {
    /// The suture's links as springs (the models that have them name them so), or nullptr.
    template <typename SystemT>
    auto *
    suture_springs(SystemT &s)
    {
      using Springs = std::conditional_t<std::is_const_v<SystemT>, const SpringSet, SpringSet>;
      for (auto &i : s.interactions)
        if (auto *springs = dynamic_cast<Springs *>(i.get()); springs != nullptr && springs->name() == "suture springs")
          return springs;
      return static_cast<Springs *>(nullptr);
    }
  } // namespace

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
    // from the suture's SpringSet: k (L − L0)
    tension.assign(s.suture.size() - 1, 0.0);
    if (const auto *springs = suture_springs(s))
      for (std::size_t e = 0; e < springs->size(); ++e)
        {
          const auto a = springs->first_ends()[e], b = springs->second_ends()[e];
          if (s.suture.contains(a) && b == a + 1)
            tension[a - s.suture.begin] =
              springs->stiffnesses()[e] * ((s.nodes.x.col(b) - s.nodes.x.col(a)).norm() - springs->rest_lengths()[e]);
        }
  }

  namespace
  {
    /// The suture's springs and the index of link @p segment's, or std::invalid_argument.
    template <typename SystemT>
    auto
    link_spring(SystemT &s, const std::uint32_t segment)
    {
      auto *springs = suture_springs(s);
      if (springs == nullptr)
        throw std::invalid_argument("this suture model has no links as springs to leave out (use mass-spring or "
                                    "xpbd-rod)");
      if (segment + 1 >= s.suture.size())
        throw std::invalid_argument("no suture link " + std::to_string(segment));
      const std::uint32_t i = s.suture.begin + segment;
      const std::size_t   e = springs->find(i, i + 1);
      if (e == springs->size())
        throw std::invalid_argument("suture link " + std::to_string(segment) + " has no spring");
      return std::pair{springs, e};
    }
  } // namespace

  double
  SutureModel::link_stiffness(const System &s, const std::uint32_t segment) const
  {
    const auto [springs, e] = link_spring(s, segment);
    return segment < left_out.size() && left_out[segment] > 0 ? left_out[segment] : springs->stiffnesses()[e];
  }

  void
  SutureModel::leave_out_link(System &s, const std::uint32_t segment, const bool out)
  {
    const auto [springs, e] = link_spring(s, segment);
    left_out.resize(s.suture.size() - 1, 0.0);
    if (out == (left_out[segment] > 0))
      return; // already so
    if (out)
      {
        left_out[segment] = springs->stiffnesses()[e];
        springs->set_stiffness(e, 0);
      }
    else
      {
        springs->set_stiffness(e, left_out[segment]);
        left_out[segment] = 0;
      }
  }
} // namespace suturesim::realtime
