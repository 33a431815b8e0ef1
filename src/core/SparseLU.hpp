// Sparse LU through SuiteSparse KLU (64-bit index routines). The symbolic analysis is done
// once per pattern; numeric factorizations reuse it. Singular matrices raise NumericalError
// with the reciprocal condition estimate, so callers can say what is singular and where.
#pragma once

#include <klu.h>

#include <string>

#include "core/Types.hpp"

namespace flexsens {

class SparseLU {
 public:
  SparseLU();
  ~SparseLU();
  SparseLU(const SparseLU&) = delete;
  SparseLU& operator=(const SparseLU&) = delete;

  /// Factorizes A; `what` names the matrix in error messages (e.g. "Newton matrix at t = 0.5 s").
  void factor(const SpMat& A, const std::string& what);
  /// Solves A x = b in place (b may hold several columns).
  void solve(MatX& b) const;
  VecX solve(const VecX& b) const;
  /// Reciprocal condition estimate of the last factorization (KLU's rcond, cheap).
  double rcond() const;
  long factorizations() const { return count_; }
  /// A factorization is held (false before the first and after one that failed).
  bool factorized() const { return numeric_ != nullptr; }

 private:
  void release();
  mutable klu_l_common common_;
  klu_l_symbolic* symbolic_ = nullptr;
  klu_l_numeric* numeric_ = nullptr;
  SpMat pattern_;  ///< copy of the structure analysed (values unused)
  long count_ = 0;
};

}  // namespace flexsens
