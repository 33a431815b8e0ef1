#include "elements/ShellMesh.hpp"

#include <map>
#include <stdexcept>

#include "elements/ShellClampHinge.hpp"
#include "elements/ShellHinge.hpp"
#include "elements/ShellTriangle.hpp"

namespace flexsens {

ShellMeshCounts buildShell(const std::string& name, const std::vector<Eigen::Vector3d>& rest,
                           const std::vector<std::array<int, 3>>& tris, const std::vector<int>& ids,
                           const std::shared_ptr<ShellProperties>& props, bool flatRest,
                           std::vector<std::unique_ptr<Element>>& out, const std::function<std::string(int)>& label,
                           const std::vector<bool>& clamped, const KirchhoffSettings* kirchhoff) {
  ShellMeshCounts n;
  auto nodesOf = [&](const std::vector<int>& mesh) {
    std::string s;
    for (int i : mesh) s += (s.empty() ? "" : " ") + label(i);
    return s;
  };
  // edge (i < j) -> (triangle, third node) of every triangle that has it
  std::map<std::pair<int, int>, std::vector<std::pair<int, int>>> edges;
  for (size_t k = 0; k < tris.size(); ++k) {
    const auto& t = tris[k];
    VecX X(9);
    for (int j = 0; j < 3; ++j) X.segment<3>(3 * j) = rest[t[j]];
    try {
      const bool own = kirchhoff && !kirchhoff->perTriangle.empty();
      out.push_back(std::make_unique<ShellTriangle>(name + ".tri" + std::to_string(k),
                                                    std::vector<int>{ids[t[0]], ids[t[1]], ids[t[2]]},
                                                    own ? kirchhoff->perTriangle[k] : props, X));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string(e.what()) + " (nodes " + nodesOf({t[0], t[1], t[2]}) + ")");
    }
    ++n.triangles;
    for (int j = 0; j < 3; ++j) {
      const int a = t[j], b = t[(j + 1) % 3], c = t[(j + 2) % 3];
      edges[{std::min(a, b), std::max(a, b)}].push_back({static_cast<int>(k), c});
    }
  }
  if (kirchhoff) {
    for (const auto& [e, wings] : edges) {
      if (wings.size() == 1) ++n.boundaryEdges;
      if (wings.size() > 2)
        throw std::invalid_argument("shell " + name + ": the edge between nodes " + nodesOf({e.first, e.second}) +
                                    " is shared by " + std::to_string(wings.size()) +
                                    " triangles (a non-manifold edge); expected at most 2");
    }
    if (kirchhoff->patchMembrane)
      for (auto it = out.end() - n.triangles; it != out.end(); ++it) static_cast<ShellTriangle&>(**it).disableMembrane();
    n.kirchhoff = buildKirchhoffBending(name, rest, tris, ids, props, flatRest, out, label, kirchhoff->boundary,
                                        kirchhoff->patchMembrane, kirchhoff->perTriangle);
    return n;
  }
  for (const auto& [e, wings] : edges) {
    if (wings.size() == 1) {
      ++n.boundaryEdges;
      if (!clamped.empty() && clamped[e.first] && clamped[e.second]) {
        const std::array<int, 3> c{e.first, e.second, wings[0].second};
        VecX X(9);
        for (int j = 0; j < 3; ++j) X.segment<3>(3 * j) = rest[c[j]];
        out.push_back(std::make_unique<ShellClampHinge>(name + ".clamp" + std::to_string(n.clamps),
                                                        std::vector<int>{ids[c[0]], ids[c[1]], ids[c[2]]}, props, X));
        ++n.clamps;
      }
      continue;
    }
    if (wings.size() > 2)
      throw std::invalid_argument("shell " + name + ": the edge between nodes " + nodesOf({e.first, e.second}) +
                                  " is shared by " + std::to_string(wings.size()) +
                                  " triangles (a non-manifold edge); expected at most 2 (one dihedral angle per edge)");
    const std::array<int, 4> h{e.first, e.second, wings[0].second, wings[1].second};
    VecX X(12);
    for (int j = 0; j < 4; ++j) X.segment<3>(3 * j) = rest[h[j]];
    out.push_back(std::make_unique<ShellHinge>(name + ".hinge" + std::to_string(n.hinges),
                                               std::vector<int>{ids[h[0]], ids[h[1]], ids[h[2]], ids[h[3]]}, props, X,
                                               flatRest));
    ++n.hinges;
  }
  return n;
}

std::vector<std::pair<int, int>> shellBoundaryEdges(const std::vector<std::array<int, 3>>& tris) {
  std::map<std::pair<int, int>, int> count;
  for (const auto& t : tris)
    for (int j = 0; j < 3; ++j) ++count[{std::min(t[j], t[(j + 1) % 3]), std::max(t[j], t[(j + 1) % 3])}];
  std::vector<std::pair<int, int>> out;
  for (const auto& [e, c] : count)
    if (c == 1) out.push_back(e);
  return out;
}

}  // namespace flexsens
