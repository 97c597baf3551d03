#pragma once
/**
 * @file
 * An order of constraints in which consecutive ones share no node (where the colouring
 * allows): greedy colouring, constraints grouped by colour, each group sorted by its
 * first node for locality. A Gauss–Seidel sweep in this order is the same sequential
 * algorithm (any order is a valid Gauss–Seidel order); what changes is that the
 * processor can overlap a projection with the next one instead of waiting for the node
 * it just wrote (a store-to-load chain through sqrt and division, ~60 cycles per
 * constraint otherwise). The same ordering makes colour groups Jacobi-parallel, the
 * usual route of GPU XPBD (Fratarcangeli et al. 2016, "Vivace").
 */

#include <algorithm>
#include <array>
#include <cstdint>
#include <numeric>
#include <vector>

namespace suturesim::realtime
{
  /// Reorders @p v by @p order (new position → old index), as the families apply the
  /// orders below to each of their per-constraint arrays.
  template <typename Vector>
  void
  permute(Vector &v, const std::vector<std::size_t> &order)
  {
    const Vector copy = v;
    for (std::size_t k = 0; k < order.size(); ++k)
      v[k] = copy[order[k]];
  }

  /// The permutation (new position → old index) of @p items over @p n_nodes nodes.
  template <std::size_t n>
  std::vector<std::size_t>
  independent_order(const std::vector<std::array<std::uint32_t, n>> &items, const std::size_t n_nodes)
  {
    // colours used at each node, as a bit set; past 63 colours items share colour 63
    std::vector<std::uint64_t> used(n_nodes, 0);
    std::vector<unsigned>      colour(items.size());
    for (std::size_t c = 0; c < items.size(); ++c)
      {
        std::uint64_t taken = 0;
        for (const auto v : items[c])
          taken |= used[v];
        unsigned k = 0;
        while (k < 63 && (taken >> k) & 1U)
          ++k;
        colour[c] = k;
        for (const auto v : items[c])
          used[v] |= std::uint64_t(1) << k;
      }
    std::vector<std::size_t> order(items.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](const std::size_t a, const std::size_t b) {
      return colour[a] != colour[b] ? colour[a] < colour[b] : items[a][0] < items[b][0];
    });
    return order;
  }
  /// An order of constraints in blocks for @p parts threads, given each node's part
  /// @p node_part: block p (p < parts) holds the items whose nodes all lie in part p,
  /// the last block the items that span parts; each block in independent_order(). Blocks
  /// below parts share no node with each other, so threads may sweep them at once (a
  /// domain decomposition: Gauss–Seidel within each block, the interface after them).
  struct BlockOrder
  {
    std::vector<std::size_t> order;  ///< new position → old index
    std::vector<std::size_t> blocks; ///< block k is [blocks[k], blocks[k + 1]), parts + 1 blocks
  };

  template <std::size_t n>
  BlockOrder
  block_order(const std::vector<std::array<std::uint32_t, n>> &items, const std::vector<std::uint32_t> &node_part,
              const unsigned parts)
  {
    std::vector<std::vector<std::size_t>> members(parts + 1);
    for (std::size_t c = 0; c < items.size(); ++c)
      {
        const std::uint32_t p    = node_part[items[c][0]];
        bool                same = true;
        for (const auto v : items[c])
          same = same && node_part[v] == p;
        members[same && p < parts ? p : parts].push_back(c);
      }
    BlockOrder result;
    result.blocks.push_back(0);
    for (const auto &m : members)
      {
        std::vector<std::array<std::uint32_t, n>> subset(m.size());
        for (std::size_t k = 0; k < m.size(); ++k)
          subset[k] = items[m[k]];
        for (const auto k : independent_order(subset, node_part.size()))
          result.order.push_back(m[k]);
        result.blocks.push_back(result.order.size());
      }
    return result;
  }
} // namespace suturesim::realtime
