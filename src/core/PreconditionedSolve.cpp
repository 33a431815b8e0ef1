#include "core/PreconditionedSolve.hpp"

#include <cmath>
#include <vector>

namespace flexsens {

double infNorm(const SpMat& A) {
  VecX rows = VecX::Zero(A.rows());
  for (int64_t c = 0; c < A.outerSize(); ++c)
    for (SpMat::InnerIterator it(A, c); it; ++it) rows[it.row()] += std::abs(it.value());
  return rows.size() ? rows.maxCoeff() : 0.0;
}

namespace {

/// GMRES (no restart) on (P^-1 A) d = z0 = P^-1 r from d = 0, at most `budget` iterations,
/// until the preconditioned residual is below rel |z0|. Modified Gram-Schmidt with Givens
/// rotations; returns d and the number of P^-1 applications.
int gmres(const SpMat& A, const SparseLU& P, const VecX& z0, double rel, int budget, VecX& d) {
  const double beta = z0.norm();
  d = VecX::Zero(z0.size());
  if (!(beta > 0) || budget < 1) return 0;
  std::vector<VecX> V{z0 / beta};
  MatX H = MatX::Zero(budget + 1, budget);
  VecX g = VecX::Zero(budget + 1), cs = VecX::Zero(budget), sn = VecX::Zero(budget);
  g[0] = beta;
  int k = 0;
  while (k < budget) {
    VecX w = P.solve(VecX(A * V[k]), false);
    for (int i = 0; i <= k; ++i) {
      H(i, k) = w.dot(V[i]);
      w -= H(i, k) * V[i];
    }
    H(k + 1, k) = w.norm();
    for (int i = 0; i < k; ++i) {  // earlier rotations on the new column
      const double t = cs[i] * H(i, k) + sn[i] * H(i + 1, k);
      H(i + 1, k) = -sn[i] * H(i, k) + cs[i] * H(i + 1, k);
      H(i, k) = t;
    }
    const double den = std::hypot(H(k, k), H(k + 1, k));
    cs[k] = den > 0 ? H(k, k) / den : 1.0;
    sn[k] = den > 0 ? H(k + 1, k) / den : 0.0;
    H(k, k) = den;
    H(k + 1, k) = 0.0;
    g[k + 1] = -sn[k] * g[k];
    g[k] *= cs[k];
    const double hNext = w.norm();
    ++k;
    if (std::abs(g[k]) <= rel * beta || !(hNext > 0) || !std::isfinite(g[k])) break;
    V.push_back(w / hNext);
  }
  const VecX y = H.topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(g.head(k));
  for (int i = 0; i < k; ++i) d += y[i] * V[i];
  return k;
}

}  // namespace

PreconditionedSolveResult preconditionedSolve(const SpMat& A, double normA, const SparseLU& P,
                                              const VecX& b, VecX& x, double tol, int maxSolves) {
  PreconditionedSolveResult res;
  if (x.size() != b.size()) x = VecX::Zero(b.size());
  const double normB = b.lpNorm<Eigen::Infinity>();
  while (true) {
    const VecX r = b - A * x;
    const double scale = normA * x.lpNorm<Eigen::Infinity>() + normB;
    res.backwardError = scale > 0 ? r.lpNorm<Eigen::Infinity>() / scale : 0.0;
    if (!std::isfinite(res.backwardError)) return res;
    if (res.backwardError <= tol) {
      res.converged = true;
      return res;
    }
    const int budget = maxSolves - res.preconditionerSolves - 1;
    if (budget < 1) return res;
    const VecX z0 = P.solve(r, false);
    ++res.preconditionerSolves;
    // Inner tolerance: a tenth of the reduction still needed; the outer loop checks the true
    // residual and refines away what round-off in the recurrences left.
    VecX d;
    res.preconditionerSolves += gmres(A, P, z0, 0.1 * tol / res.backwardError, budget, d);
    x += d;
  }
}

}  // namespace flexsens
