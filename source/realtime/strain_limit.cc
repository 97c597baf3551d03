#include <suturesim/realtime/integrator.h>
#include <suturesim/realtime/spring_set.h>

namespace suturesim::realtime
{
  std::size_t
  limit_strain(System &system, const double limit, const unsigned sweeps)
  {
    std::size_t corrected = 0;
    for (const auto &i : system.interactions)
      if (const auto *springs = dynamic_cast<const SpringSet *>(i.get()))
        corrected += springs->limit_strain(system.nodes.x, system.nodes.inverse_mass, limit, sweeps);
    return corrected;
  }
} // namespace suturesim::realtime
