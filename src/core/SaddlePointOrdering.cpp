#include "core/SaddlePointOrdering.hpp"

#include <amd.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace flexsens {

std::vector<int64_t> saddlePointOrdering(const SpMat& A) {
  const int64_t N = A.rows();
  // Primal unknowns (nonzero diagonal) get consecutive indices in the condensed graph.
  std::vector<int64_t> primalIndex(N, -1), primalUnknown;
  for (int64_t j = 0; j < N; ++j)
    if (A.coeff(j, j) != 0.0) {
      primalIndex[j] = int64_t(primalUnknown.size());
      primalUnknown.push_back(j);
    }
  const int64_t n = int64_t(primalUnknown.size());
  // Primal neighbours of each multiplier (from its column and its row: the pattern may be
  // unsymmetric), and the primal-primal edges.
  std::vector<std::vector<int64_t>> neighbours(N);
  std::vector<std::pair<int64_t, int64_t>> edges;
  for (int64_t j = 0; j < N; ++j)
    for (SpMat::InnerIterator it(A, j); it; ++it) {
      const int64_t i = it.row(), pi = primalIndex[i], pj = primalIndex[j];
      if (pi >= 0 && pj >= 0) edges.emplace_back(pi, pj);
      else if (pi < 0 && pj >= 0) neighbours[i].push_back(pj);
      else if (pi >= 0 && pj < 0) neighbours[j].push_back(pi);
    }
  for (auto& c : neighbours) {
    std::sort(c.begin(), c.end());
    c.erase(std::unique(c.begin(), c.end()), c.end());
    for (int64_t a : c)
      for (int64_t b : c) edges.emplace_back(a, b);  // B^T B: a clique per constraint
  }
  // Compressed column pattern of the condensed graph (AMD symmetrizes it).
  std::sort(edges.begin(), edges.end(), [](const auto& x, const auto& y) {
    return x.second != y.second ? x.second < y.second : x.first < y.first;
  });
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  std::vector<int64_t> Cp(n + 1, 0), Ci(edges.size());
  for (size_t k = 0; k < edges.size(); ++k) {
    Ci[k] = edges[k].first;
    ++Cp[edges[k].second + 1];
  }
  for (int64_t j = 0; j < n; ++j) Cp[j + 1] += Cp[j];
  std::vector<int64_t> order(n);
  if (n > 0 && amd_l_order(n, Cp.data(), Ci.data(), order.data(), nullptr, nullptr) < AMD_OK)
    throw std::runtime_error("AMD failed on the condensed graph of a saddle-point matrix");
  std::vector<int64_t> pos(n);
  for (int64_t k = 0; k < n; ++k) pos[order[k]] = k;
  // A multiplier follows the last of its primal neighbours, not counting dense ones (AMD's
  // rule: degree above 10 sqrt(n)), such as a large body's coordinates that hundreds of
  // constraints share: otherwise all those multipliers would meet in a dense border at the end.
  const int64_t dense = std::max<int64_t>(16, int64_t(10 * std::sqrt(double(n))));
  std::vector<std::vector<int64_t>> after(n + 1);
  for (int64_t j = 0; j < N; ++j) {
    if (primalIndex[j] >= 0) continue;
    int64_t lastLight = -1, last = -1;
    for (int64_t c : neighbours[j]) {
      last = std::max(last, pos[c]);
      if (Cp[c + 1] - Cp[c] <= dense) lastLight = std::max(lastLight, pos[c]);
    }
    after[lastLight >= 0 ? lastLight : last >= 0 ? last : n].push_back(j);
  }
  std::vector<int64_t> perm;
  perm.reserve(N);
  for (int64_t k = 0; k < n; ++k) {
    perm.push_back(primalUnknown[order[k]]);
    perm.insert(perm.end(), after[k].begin(), after[k].end());
  }
  perm.insert(perm.end(), after[n].begin(), after[n].end());
  return perm;
}

}  // namespace flexsens
