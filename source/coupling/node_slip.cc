#include <suturesim/coupling/node_slip.h>

#include <stdexcept>

namespace suturesim::coupling
{
  std::size_t
  node_slip(std::vector<NodeSlipPoint> &points, const long first, const long last)
  {
    // called in the haptic step: no allocation; the tentative moves live in `moved`
    const std::size_t n = points.size();
    for (std::size_t k = 0; k < n; ++k)
      {
        points[k].moved = 0;
        if (k > 0 && points[k].node < points[k - 1].node)
          throw std::invalid_argument("node slip: points out of thread order");
      }
    // per run of points on one node, [begin, end): the largest suffix that slips
    // forward (led by a point whose own pull exceeds its friction, the suffix's combined
    // pull exceeding its combined friction), and the largest prefix that slips back
    for (std::size_t begin = 0, end = 0; begin < n; begin = end)
      {
        const long node = points[begin].node;
        for (end = begin; end < n && points[end].node == node;)
          ++end;
        std::size_t forward_from = end, backward_to = begin;
        double      excess       = 0;
        for (std::size_t j = end; j-- > begin;)
          {
            excess += points[j].pull - points[j].limit;
            if (points[j].pull > points[j].limit && excess > 0)
              forward_from = j;
          }
        excess = 0;
        for (std::size_t j = begin; j < end; ++j)
          {
            excess += -points[j].pull - points[j].limit;
            if (-points[j].pull > points[j].limit && excess > 0)
              backward_to = j + 1;
          }
        // both ways at once would pull the list apart across itself: the points that
        // want to go forward stand behind those that want to go back; they hold
        if (backward_to > forward_from)
          {
            forward_from = end;
            backward_to  = begin;
          }
        if (node >= last)
          forward_from = end;
        if (node <= first)
          backward_to = begin;
        for (std::size_t j = begin; j < backward_to; ++j)
          points[j].moved = -1;
        for (std::size_t j = forward_from; j < end; ++j)
          points[j].moved = +1;
      }
    // neighbouring nodes whose groups would swap press on each other: the last point of
    // a run going forward meets the first of the next node's run going back
    for (std::size_t k = 0; k + 1 < n; ++k)
      if (points[k].moved == +1 && points[k + 1].moved == -1 && points[k + 1].node == points[k].node + 1)
        {
          for (std::size_t j = k + 1; j-- > 0 && points[j].node == points[k].node && points[j].moved == +1;)
            points[j].moved = 0;
          for (std::size_t j = k + 1; j < n && points[j].node == points[k + 1].node && points[j].moved == -1; ++j)
            points[j].moved = 0;
        }
    std::size_t moved = 0;
    for (auto &p : points)
      if (p.moved != 0)
        {
          p.node += p.moved;
          ++moved;
        }
    return moved;
  }
} // namespace suturesim::coupling
