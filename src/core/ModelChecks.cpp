#include "core/ModelChecks.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <Eigen/LU>

#include "core/Assembler.hpp"
#include "core/SparseAccumulator.hpp"

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

UnrestrainedMassless unrestrainedMasslessDirection(const Model& m) {
  UnrestrainedMassless out;
  if (m.n == 0) return out;
  const Assembler as(m);
  const VecX p = m.nominalParameters();
  const VecX q = m.initialPositions(), v = m.initialVelocities();
  // Coordinates whose row of M is zero: they have no inertia of their own.
  const SpMat M = as.mass(p);
  VecX rowAbs = VecX::Zero(m.n);
  for (int c = 0; c < M.outerSize(); ++c)
    for (SpMat::InnerIterator it(M, c); it; ++it) rowAbs[it.row()] += std::abs(it.value());
  std::vector<int> z;
  for (int i = 0; i < m.n; ++i)
    if (rowAbs[i] == 0.0) z.push_back(i);
  if (z.empty()) return out;
  const int64_t rows = 2 * int64_t(m.n) + m.m;
  if (rows * int64_t(z.size()) > 40000000) return out;
  // [K; C; Phi_q] restricted to the massless columns: a null vector moves the massless
  // coordinates without any force or constraint noticing.
  SparseAccumulator acc;
  acc.begin(rows, m.n);
  as.addForceJacobian(acc, q, v, p, 1.0, 0.0, 0, 0, 0);
  as.addForceJacobian(acc, q, v, p, 0.0, 1.0, m.n, 0, 0);
  as.addPhiQ(acc, q, p, 1.0, 2 * int64_t(m.n), 0, false);
  const SpMat A = acc.finish();
  MatX Az = MatX::Zero(rows, static_cast<Eigen::Index>(z.size()));
  for (size_t j = 0; j < z.size(); ++j) Az.col(j) = MatX(A.col(z[j]));
  // Unit columns (stiffness in N/m and constraint rows in 1 differ by many orders); a zero
  // column is itself the answer. Then a relative pivot threshold means the same everywhere.
  VecX colNorm(z.size());
  for (size_t j = 0; j < z.size(); ++j) {
    colNorm[j] = Az.col(j).norm();
    if (colNorm[j] > 0.0) Az.col(j) /= colNorm[j];
  }
  Eigen::FullPivLU<MatX> lu(Az);
  lu.setThreshold(1e-10);
  if (lu.rank() == static_cast<Eigen::Index>(z.size())) return out;
  MatX ker = lu.kernel();
  for (size_t j = 0; j < z.size(); ++j)
    if (colNorm[j] > 0.0) ker.row(j) /= colNorm[j];
  const VecX w = ker.col(0).normalized();
  std::vector<int> idx(z.size());
  for (size_t i = 0; i < idx.size(); ++i) idx[i] = static_cast<int>(i);
  std::sort(idx.begin(), idx.end(), [&](int a, int b) { return std::abs(w[a]) > std::abs(w[b]); });
  for (size_t k = 0; k < idx.size() && k < 4 && std::abs(w[idx[k]]) > 0.1 * std::abs(w[idx[0]]); ++k) {
    char coef[32];
    std::snprintf(coef, sizeof coef, "%.2g ", std::abs(w[idx[k]]));
    out.direction += (k ? (w[idx[k]] * w[idx[0]] < 0 ? " - " : " + ") : "") +
                     std::string(std::abs(std::abs(w[idx[k]]) - 1.0) < 1e-12 ? "" : coef) +
                     m.coordinateLabel(z[idx[k]]);
    for (size_t nd = 0; nd < m.nodes.size(); ++nd) {
      const Node& N = m.nodes[nd];
      const int c = z[idx[k]];
      const bool owns = (N.firstDof >= 0 && c >= N.firstDof && c < N.firstDof + m.dim) ||
                        (N.slopeDof >= 0 && c >= N.slopeDof && c < N.slopeDof + N.slope.size());
      if (owns && std::find(out.nodes.begin(), out.nodes.end(), int(nd)) == out.nodes.end())
        out.nodes.push_back(static_cast<int>(nd));
    }
  }
  return out;
}

}  // namespace flexsens
