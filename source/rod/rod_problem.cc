#include <suturesim/rod/rod_integrator.h>

namespace suturesim::rod
{
  RodProblem::RodProblem(const RodParameters &parameters, const TimeParameters &time)
    : model(parameters.create_model())
    , initial(model)
    , parameters(parameters)
    , time(time)
  {}

  void
  RodProblem::set_time(const double t)
  {
    parameters.apply_loads(model, t, time.end_time);
    parameters.apply_motion(model, initial, t);
  }

  std::vector<std::size_t>
  RodProblem::prescribed_nodes() const
  {
    std::vector<std::size_t> nodes;
    if (parameters.start_end.type == "prescribed")
      nodes.push_back(0);
    if (parameters.last_end.type == "prescribed")
      nodes.push_back(model.n_nodes() - 1);
    return nodes;
  }
} // namespace suturesim::rod
