#pragma once
/**
 * @file
 * Interaction::element_nodes() of the families with one element per tetrahedron (volume
 * constraints, neo-Hookean elements): their four system nodes in order, element after
 * element, so that vertex block descent finds each node's elements.
 */

#include <suturesim/mesh/simplex_mesh.h>

#include <cstdint>
#include <vector>

namespace suturesim::realtime
{
  /// @p nodes ← the nodes of @p tets, four per element; @p per_element ← 4.
  inline bool
  tetrahedron_element_nodes(const std::vector<mesh::Tetrahedron> &tets, std::vector<std::uint32_t> &nodes,
                            unsigned &per_element)
  {
    per_element = 4;
    nodes.clear();
    nodes.reserve(4 * tets.size());
    for (const auto &t : tets)
      nodes.insert(nodes.end(), t.begin(), t.end());
    return true;
  }
} // namespace suturesim::realtime
