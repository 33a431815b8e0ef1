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
  // Plain refinement x += P^-1 (b - A x) while each step cuts the backward error by at least
  // kRefineCut: with P the LU of the last Newton iterate (full Newton) P^-1 A = I + O(1e-10).
  // Refinement takes one step more than tol asks, so that it ends where GMRES' two Arnoldi
  // steps did (the same two-dimensional space, near round-off: with the step stopped at tol,
  // modified and full Newton's sensitivities parted by 1.6e-8 over 300 steps of the four-bar)
  // with two LU solves instead of three (flexible five-bar, one parameter: 3000 -> 2000 in
  // 1000 steps). A slower cut (P from an earlier step) hands over to GMRES from there.
  constexpr double kRefineCut = 1e-3;
  bool refining = true, beyond = false;
  double previous = 0.0;  // backward error before the last refinement step (0: none yet)
  while (true) {
    const VecX r = b - A * x;
    const double scale = normA * x.lpNorm<Eigen::Infinity>() + normB;
    res.backwardError = scale > 0 ? r.lpNorm<Eigen::Infinity>() / scale : 0.0;
    if (!std::isfinite(res.backwardError)) return res;
    if (refining && previous > 0.0 && !(res.backwardError <= kRefineCut * previous)) refining = false;
    const int budget = maxSolves - res.preconditionerSolves - 1;
    if (res.backwardError <= tol && (!refining || beyond || budget < 1)) {
      res.converged = true;
      return res;
    }
    if (res.backwardError <= tol) beyond = true;  // refining: the one step more
    if (budget < 1) return res;
    const VecX z0 = P.solve(r, false);
    ++res.preconditionerSolves;
    if (refining) {
      previous = res.backwardError;
      x += z0;
      continue;
    }
    // Inner tolerance: a tenth of the reduction still needed; the outer loop checks the true
    // residual and refines away what round-off in the recurrences left.
    VecX d;
    res.preconditionerSolves += gmres(A, P, z0, 0.1 * tol / res.backwardError, budget, d);
    x += d;
  }
}

}  // namespace flexsens
