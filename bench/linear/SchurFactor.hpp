// A candidate solver for the Newton matrices of constrained continua, measured in
// bench/linear/constrained.cpp (flexsens itself factors them with MUMPS' LDL^T, core/MumpsFactor,
// 1.9-6.2x faster than this on the same matrices):
//   A = [K  C]   K: the unknowns with a nonzero diagonal (coordinates), symmetric positive
//       [B  D]      definite (M/(beta h^2) + K_t of a meshed body, its constraint rows' Hessian);
//                the border: the m others (Lagrange multipliers: D = 0, C = B^T when A is symmetric),
// factored as K's supernodal Cholesky (core/CholeskyFactor) and the dense LU, with partial
// pivoting, of the m x m Schur complement S = D - B K^-1 C. Making S costs m solves with K's
// factor (4 nnz(L) flops each).
#pragma once

#include <Eigen/LU>

#include <vector>

#include "core/CholeskyFactor.hpp"
#include "core/Types.hpp"

namespace flexsens {

class SchurFactor {
 public:
  /// The border size of A's pattern (unknowns with a zero diagonal), analysing it when new.
  Eigen::Index borderOf(const SpMat& A);
  /// Factorizes A (after borderOf(A)); false when the method does not apply to these values:
  /// no border, K not symmetric or not positive definite, S numerically singular. Nothing is
  /// held then and the caller factors A otherwise.
  bool factor(const SpMat& A);
  /// Solves A x = b in place, all columns at once (two solves with K's factor per column).
  void solve(MatX& b) const { solveBlocks(b, false); }
  /// Solves A^T x = b in place (K symmetric: the same factor; S^T from S's LU).
  void solveTransposed(MatX& b) const { solveBlocks(b, true); }
  bool factorized() const { return factorized_; }
  /// Entries of the factors: L and L^T of K (the diagonal once) and S's dense LU.
  double nnzFactors() const;
  /// Flops of the last factorization (Cholesky, S's m solves and product, S's LU) and of one
  /// solve of one right-hand side.
  double factorFlops() const;
  double solveFlops() const;
  /// min of K's crude estimate and S's LU estimate (both reciprocal 1-norm condition numbers).
  double rcond() const;

 private:
  void analyse(const SpMat& A);
  void gather(const SpMat& A);
  void makeSchurComplement();
  void solveBlocks(MatX& b, bool transposed) const;
  SpMat pattern_;                       ///< A's pattern analysed (values unused)
  std::vector<int64_t> primal_, border_;  ///< A's unknowns in K and in the border, ascending
  SpMat K_, C_, B_;                     ///< the sparse blocks, values gathered from A
  std::vector<int64_t> kFrom_, cFrom_, bFrom_;  ///< position in A of each block entry
  std::vector<int64_t> dAt_, dFrom_;    ///< D's entries: index in D (column-major) and in A
  MatX D_;
  CholeskyFactor cholesky_;
  Eigen::PartialPivLU<MatX> schur_;
  bool factorized_ = false;
};

}  // namespace flexsens
