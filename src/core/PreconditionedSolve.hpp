// A x = b with the LU of a nearby matrix P as the preconditioner: the modified Newton's
// factorization of an earlier iterate (or step) stands in for a factorization of A itself.
// Refinement steps x += d, each d from left-preconditioned GMRES on P^-1 A d = P^-1 (b - A x):
// P^-1 A = I + E with E small, so a few GMRES iterations (one product with A and one LU solve
// each) replace a new factorization. Convergence is judged on the true residual.
#pragma once

#include "core/SparseLU.hpp"

namespace flexsens {

struct PreconditionedSolveResult {
  bool converged = false;
  int preconditionerSolves = 0;  ///< applications of P^-1 (GMRES iterations + refinements)
  double backwardError = 0.0;    ///< |b - A x|_inf / (|A|_inf |x|_inf + |b|_inf) at the end
};

/// Starts from x (resized to zero if its size differs). Converged when the normwise backward
/// error is <= tol within at most maxSolves applications of P^-1; otherwise x is the best
/// iterate and the caller factors A. normA = |A|_inf (row sums), computed once per matrix.
PreconditionedSolveResult preconditionedSolve(const SpMat& A, double normA, const SparseLU& P,
                                              const VecX& b, VecX& x, double tol, int maxSolves);

/// |A|_inf: the largest absolute row sum.
double infNorm(const SpMat& A);

}  // namespace flexsens
