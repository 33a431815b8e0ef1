#include "core/ModelChecks.hpp"

namespace flexsens {

std::vector<int> nodesActedOnByNothing(const Model& m) {
  std::vector<bool> touched(m.nodes.size(), false);
  for (const auto& el : m.elements)
    for (int nd : el->nodes()) touched[nd] = true;
  for (const auto& c : m.constraints)
    for (int nd : c->nodes()) touched[nd] = true;
  std::vector<int> out;
  for (size_t i = 0; i < m.nodes.size(); ++i)
    if (!m.nodes[i].ground && !touched[i]) out.push_back(static_cast<int>(i));
  return out;
}

}  // namespace flexsens
