#include <suturesim/coupling/pierce_order.h>

#include <algorithm>
#include <stdexcept>

namespace suturesim::coupling
{
  bool
  keep_order(std::vector<double> &zeta, const double gap, const double lower, const double upper)
  {
    const std::size_t n = zeta.size();
    if (n == 0)
      return false;
    if (upper - lower < (n - 1) * gap)
      throw std::invalid_argument("pierce points: no room for them between the hard constraints");
    // shifted values y_k = ζ_k − k g must be non-decreasing within [lower, upper − (n−1) g]
    struct Block
    {
      double      sum;
      std::size_t count;
      double
      mean() const
      {
        return sum / count;
      }
    };
    std::vector<Block> blocks;
    blocks.reserve(n);
    for (std::size_t k = 0; k < n; ++k)
      {
        blocks.push_back({zeta[k] - k * gap, 1});
        while (blocks.size() > 1 && blocks[blocks.size() - 2].mean() > blocks.back().mean())
          {
            blocks[blocks.size() - 2].sum += blocks.back().sum;
            blocks[blocks.size() - 2].count += blocks.back().count;
            blocks.pop_back();
          }
      }
    bool        changed = false;
    std::size_t k       = 0;
    for (const auto &b : blocks)
      {
        // clamping a non-decreasing sequence keeps it non-decreasing
        const double y = std::clamp(b.mean(), lower, upper - (n - 1) * gap);
        if (b.count == 1 && y == b.mean())
          {
            ++k; // a point that violates nothing keeps its value bit for bit
            continue;
          }
        for (std::size_t j = 0; j < b.count; ++j, ++k)
          {
            const double z = y + k * gap;
            changed        = changed || z != zeta[k];
            zeta[k]        = z;
          }
      }
    return changed;
  }
} // namespace suturesim::coupling
