// Sparse LU through SuiteSparse KLU (64-bit index routines) in the saddle-point ordering
// (core/SaddlePointOrdering: multipliers after their coordinates) with a small pivot tolerance,
// so that KLU keeps the diagonal pivots the ordering was made for. The symbolic analysis is
// done once per pattern; numeric factorizations reuse it (klu_refactor: same pivots). Singular
// matrices raise NumericalError with the reciprocal condition estimate, so callers can say
// what is singular and where. bench/linear/results.md has the measurements behind the choice.
#pragma once

#include <klu.h>

#include <functional>
#include <string>

#include "core/Types.hpp"

namespace flexsens {

/// Componentwise backward error above which a solve is refined (~45 ulp).
inline constexpr double kRefineAbove = 1e-14;

class SparseLU {
 public:
  SparseLU();
  ~SparseLU();
  SparseLU(const SparseLU&) = delete;
  SparseLU& operator=(const SparseLU&) = delete;

  /// Factorizes A; `what` names the matrix in error messages (e.g. "Newton matrix at t = 0.5 s").
  void factor(const SpMat& A, const std::string& what);
  /// The same with the name made only when needed (an error): formatting it per factorization
  /// cost 4% of a small model's run.
  void factor(const SpMat& A, const std::function<std::string()>& what);
  /// Solves A x = b in place (b may hold several columns), refined against A while the
  /// backward error is above kRefineAbove; `refine` false: one plain solve (a preconditioner
  /// inside an iteration that measures its own residual).
  void solve(MatX& b, bool refine = true) const;
  VecX solve(const VecX& b, bool refine = true) const;
  /// Reciprocal condition estimate of the last factorization (KLU's rcond, cheap).
  double rcond() const;
  long factorizations() const { return count_; }
  /// nnz(L + U) / nnz(A) of the last factorization (1 + fill per entry of A; the diagonal once).
  double fill() const { return fill_; }
  /// Largest fill() over all factorizations so far.
  double maxFill() const { return maxFill_; }
  /// Wall time spent in numeric factorizations so far [s].
  double factorSeconds() const { return seconds_; }
  /// Pivots KLU took off the diagonal in the last fresh factorization (0 when the ordering
  /// worked as intended; each one costs fill).
  long offDiagonalPivots() const { return common_.noffdiag; }
  /// Work of one numeric factorization of the held pattern (KLU's flop count of the last fresh
  /// factorization: a refactorization keeps its pivots) and of one solve with it (a multiply
  /// and an add per entry of L and U) [flops]: machine-independent costs, for choosing between
  /// factoring a matrix and iterating with this factorization.
  double factorFlops() const { return factorFlops_; }
  double solveFlops() const { return numeric_ ? 2.0 * double(numeric_->lnz + numeric_->unz) : 0.0; }
  /// A factorization is held (false before the first and after one that failed).
  bool factorized() const { return numeric_ != nullptr; }

 private:
  void release();
  mutable klu_l_common common_;
  klu_l_symbolic* symbolic_ = nullptr;
  klu_l_numeric* numeric_ = nullptr;
  SpMat pattern_;  ///< the matrix factorized last (its structure is the one analysed)
  mutable MatX b_, x_, r_, scale_;  ///< solve()'s workspaces (one thread, like common_)
  long count_ = 0;
  double fill_ = 0.0, maxFill_ = 0.0, seconds_ = 0.0, factorFlops_ = 0.0;
};

}  // namespace flexsens
