#include <suturesim/study/pareto.h>

#include <algorithm>
#include <numeric>

namespace suturesim::study
{
  std::vector<std::size_t>
  pareto_front(const std::vector<TradeOff> &cases)
  {
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < cases.size(); ++i)
      if (cases[i].completed)
        order.push_back(i);
    // By cost, then error: a case is on the front iff its error is below every error
    // met so far (all of those cost no more) — or equals the last front point's pair.
    std::stable_sort(order.begin(), order.end(), [&](const std::size_t a, const std::size_t b) {
      return cases[a].cost < cases[b].cost || (cases[a].cost == cases[b].cost && cases[a].error < cases[b].error);
    });
    std::vector<std::size_t> front;
    for (const std::size_t i : order)
      {
        if (front.empty() || cases[i].error < cases[front.back()].error)
          front.push_back(i);
        else if (cases[i].error == cases[front.back()].error && cases[i].cost == cases[front.back()].cost)
          front.push_back(i); // the same point twice: neither dominates the other
      }
    return front;
  }

  std::optional<std::size_t>
  cheapest_within(const std::vector<TradeOff> &cases, const double tolerance)
  {
    std::optional<std::size_t> best;
    for (std::size_t i = 0; i < cases.size(); ++i)
      if (cases[i].completed && cases[i].error <= tolerance &&
          (!best || cases[i].cost < cases[*best].cost ||
           (cases[i].cost == cases[*best].cost && cases[i].error < cases[*best].error)))
        best = i;
    return best;
  }
} // namespace suturesim::study
