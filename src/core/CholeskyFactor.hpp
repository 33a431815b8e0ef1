// Supernodal sparse Cholesky through SuiteSparse CHOLMOD (64-bit index routines, AMD
// ordering, CHOLMOD's own choice of supernodal or simplicial), for the Newton matrices that
// are symmetric positive definite: M/(beta h^2) + K of bodies without constraint rows (a meshed
// body held by grounded nodes). CHOLMOD's supernodes run the dense blocks through BLAS; on the
// solid pendulum's Newton matrix at n = 11265 one factorization takes 74 ms against KLU's
// 534 ms refactorization (bench/linear/results.md). SparseLU decides when to use it.
#pragma once

#include <cholmod.h>

#include <vector>

#include "core/Types.hpp"

namespace flexsens {

/// Same dimensions and the same stored entries (the values may differ).
bool samePattern(const SpMat& a, const SpMat& b);
/// For each stored entry A(i, j), the position of A(j, i); empty when some entry has no
/// transpose (a structurally unsymmetric A).
std::vector<int64_t> transposePositions(const SpMat& A);

class CholeskyFactor {
 public:
  CholeskyFactor();
  ~CholeskyFactor();
  CholeskyFactor(const CholeskyFactor&) = delete;
  CholeskyFactor& operator=(const CholeskyFactor&) = delete;

  /// Whether A (compressed, structurally symmetric with its whole diagonal) is numerically
  /// symmetric to round-off: the test each factorization makes before trying Cholesky. The
  /// pattern's transpose map is made once per pattern.
  bool symmetric(const SpMat& A);
  /// Factorizes A (symmetric() true); false when A is not positive definite (nothing held).
  bool factor(const SpMat& A);
  /// Solves A x = b in place, all columns of b at once.
  void solve(MatX& b) const;
  bool factorized() const { return factor_ != nullptr && factor_->minor == factor_->n; }
  /// nnz(L) of the last factorization, its flop count, and CHOLMOD's crude reciprocal
  /// condition estimate (min/max of diag(L))^2.
  double nnzL() const { return common_.lnz; }
  double flops() const { return common_.fl; }
  double rcond() const;

 private:
  void analyse(const SpMat& A);
  bool positivePivots() const;
  void release();
  mutable cholmod_common common_;
  cholmod_factor* factor_ = nullptr;
  SpMat pattern_;                        ///< the pattern analysed (values unused)
  std::vector<int64_t> transposeOf_;     ///< position of A(j, i) for each stored A(i, j), -1: none
  SpMat lower_;                          ///< lower triangle of A (CHOLMOD's stype -1 input)
  std::vector<int64_t> lowerFrom_;       ///< position in A of each entry of lower_
};

}  // namespace flexsens
