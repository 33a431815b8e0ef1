// The Newton matrices' direct solver, one per matrix structure (bench/linear):
// - symmetric with a positive diagonal (a meshed body without constraint rows): CHOLMOD's
//   supernodal Cholesky (core/CholeskyFactor), when it is positive definite;
// - symmetric with constraint rows and large (a meshed body held by support, symmetry or attach
//   rows, or joined to other bodies: MUMPS predicts at least kLdltFromFlops): MUMPS' sparse
//   LDL^T (core/MumpsFactor);
// - every other matrix (the multibody saddle-point matrices, unsymmetric tangents) and one the
//   others refuse (indefinite, singular): KLU.
// The solve, its refinement against A and the counters are the same for all three.
// FLEXSENS_LINEAR_SOLVER=klu (KLU for every matrix) or =cholesky (no LDL^T) in the environment
// restricts the choice, to compare the paths (tests, bench/linear).
//
// Sparse LU through SuiteSparse KLU (64-bit index routines) in the saddle-point ordering
// (core/SaddlePointOrdering: multipliers after their coordinates) with a small pivot tolerance,
// so that KLU keeps the diagonal pivots the ordering was made for. The symbolic analysis is
// done once per pattern; numeric factorizations reuse it (klu_refactor: same pivots). Singular
// matrices raise NumericalError with the reciprocal condition estimate, so callers can say
// what is singular and where. bench/linear/results.md has the measurements behind the choice.
#pragma once

#include <klu.h>

#include <functional>
#include <memory>
#include <string>

#include "core/CholeskyFactor.hpp"
#include "core/MumpsFactor.hpp"
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
  /// Solves A^T x = b with the same factors, plainly (no refinement): KLU's transposed solve, or
  /// the Cholesky or LDL^T factor's own solve (A symmetric). For estimates such as A's condition number.
  VecX solveTransposed(const VecX& b) const;
  /// Reciprocal condition estimate of the last factorization (KLU's rcond, cheap; CHOLMOD's
  /// (min/max diag L)^2; after LDL^T, 1 / (|A|_1 |A^-1|_1) with Hager's estimate, a few solves).
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
  double solveFlops() const;
  /// A factorization is held (false before the first and after one that failed).
  bool factorized() const {
    return cholesky_ ? cholesky_->factorized() : ldlt_ ? ldlt_->factorized() : numeric_ != nullptr;
  }
  /// Factorizations done by Cholesky and by LDL^T (the rest by KLU).
  long choleskyFactorizations() const { return choleskyCount_; }
  long ldltFactorizations() const { return ldltCount_; }

 private:
  void release();
  bool factorCholesky(const SpMat& A);
  bool factorLDLT(const SpMat& A);
  double inverseNorm1() const;
  bool factorLU(const SpMat& A, const std::function<std::string()>& what);
  void refine(MatX& b) const;
  std::unique_ptr<CholeskyFactor> choleskyOwner_ = std::make_unique<CholeskyFactor>();
  CholeskyFactor* cholesky_ = nullptr;  ///< choleskyOwner_ when the last factorization is its
  long choleskyCount_ = 0;
  std::unique_ptr<MumpsFactor> ldltOwner_;  ///< made when a matrix first qualifies
  MumpsFactor* ldlt_ = nullptr;             ///< ldltOwner_ when the last factorization is its
  long ldltCount_ = 0;
  enum class Choice { Any, NoLdlt, KluOnly } choice_ = Choice::Any;  ///< FLEXSENS_LINEAR_SOLVER
  mutable klu_l_common common_;
  klu_l_symbolic* symbolic_ = nullptr;
  klu_l_numeric* numeric_ = nullptr;
  void plainSolve(MatX& b) const;
  SpMat pattern_;  ///< KLU's analysed structure
  SpMat matrix_;   ///< the matrix factorized last (solve() refines against it)
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  mutable MatX b_, x_;                         ///< solve()'s workspaces (one thread, like common_)
  mutable RowMajor xRows_, rRows_, scaleRows_;  ///< refine()'s, row-major
  long count_ = 0;
  double fill_ = 0.0, maxFill_ = 0.0, seconds_ = 0.0, factorFlops_ = 0.0;
  double kluFlops_ = 0.0;  ///< KLU's flops for the pattern it analysed (0: not factored yet)
};

}  // namespace flexsens
