#include <suturesim/coupling/node_slip.h>

#include <stdexcept>

namespace suturesim::coupling
{
  std::size_t
  node_slip(std::vector<NodeSlipPoint> &points, const long first, const long last)
  {
    const std::size_t n = points.size();
    for (std::size_t k = 0; k < n; ++k)
      {
        points[k].moved = 0;
        if (k > 0 && points[k].node < points[k - 1].node)
          throw std::invalid_argument("node slip: points out of thread order");
      }
    // runs of points on one node: [begin, end)
    struct Run
    {
      std::size_t begin, end;
      long        node;
      std::size_t forward_from; ///< first point of the suffix that slips forward (end: none)
      std::size_t backward_to;  ///< one past the last point of the prefix that slips back (begin: none)
    };
    std::vector<Run> runs;
    for (std::size_t k = 0; k < n;)
      {
        Run r{k, k, points[k].node, 0, 0};
        while (r.end < n && points[r.end].node == r.node)
          ++r.end;
        r.forward_from = r.end;
        r.backward_to  = r.begin;
        // forward: the largest suffix led by a point whose own pull exceeds its
        // friction and whose combined pull exceeds the combined friction
        double excess = 0;
        for (std::size_t j = r.end; j-- > r.begin;)
          {
            excess += points[j].pull - points[j].limit;
            if (points[j].pull > points[j].limit && excess > 0)
              r.forward_from = j;
          }
        excess = 0;
        for (std::size_t j = r.begin; j < r.end; ++j)
          {
            excess += -points[j].pull - points[j].limit;
            if (-points[j].pull > points[j].limit && excess > 0)
              r.backward_to = j + 1;
          }
        // both ways at once would pull the list apart across itself: the points that
        // want to go forward stand behind those that want to go back; they hold
        if (r.backward_to > r.forward_from)
          {
            r.forward_from = r.end;
            r.backward_to  = r.begin;
          }
        if (r.node >= last)
          r.forward_from = r.end;
        if (r.node <= first)
          r.backward_to = r.begin;
        runs.push_back(r);
        k = r.end;
      }
    // neighbouring nodes whose groups would swap press on each other
    for (std::size_t i = 0; i + 1 < runs.size(); ++i)
      if (runs[i + 1].node == runs[i].node + 1 && runs[i].forward_from < runs[i].end &&
          runs[i + 1].backward_to > runs[i + 1].begin)
        {
          runs[i].forward_from    = runs[i].end;
          runs[i + 1].backward_to = runs[i + 1].begin;
        }
    std::size_t moved = 0;
    for (const auto &r : runs)
      {
        for (std::size_t j = r.begin; j < r.backward_to; ++j, ++moved)
          {
            points[j].moved = -1;
            --points[j].node;
          }
        for (std::size_t j = r.forward_from; j < r.end; ++j, ++moved)
          {
            points[j].moved = +1;
            ++points[j].node;
          }
      }
    return moved;
  }
} // namespace suturesim::coupling
