// Symmetric-indefinite sparse LDL^T through MUMPS 5.5 (Debian's sequential build,
// libmumps-seq-dev; multifrontal, 1x1 and 2x2 pivots, AMD ordering, one thread), for the
// Newton matrices of constrained continua: [M/(beta h^2) + K + (Phi_q^T l)_q, Phi_q^T; Phi_q, 0]
// of meshed bodies held by support, symmetry or attach rows or joined to other bodies. On
// those matrices it factors 2.8-11x faster than KLU (n = 1.7k-25k) and 1.9-6.2x faster than
// CHOLMOD on the elastic block with a dense Schur complement for the multipliers
// (bench/linear/constrained.md). SparseLU decides when to use it; it reads only the lower triangle, so A
// must be symmetric (symmetric() checks, each factorization).
#pragma once

#include <memory>
#include <vector>

#include "core/Types.hpp"

namespace flexsens {

class MumpsFactor {
 public:
  MumpsFactor();
  ~MumpsFactor();
  MumpsFactor(const MumpsFactor&) = delete;
  MumpsFactor& operator=(const MumpsFactor&) = delete;

  /// Whether A's pattern is symmetric and MUMPS analysed it (its ordering and symbolic
  /// factorization, done here once per pattern).
  bool analysed(const SpMat& A);
  /// MUMPS' predicted flops for factoring the analysed pattern.
  double predictedFlops() const { return predictedFlops_; }
  /// Whether A (analysed(A) true) is symmetric to round-off; its diagonal may hold zeros.
  bool symmetric(const SpMat& A) const;
  /// Factorizes A (symmetric(A) true); false when MUMPS finds A singular or fails (nothing held).
  bool factor(const SpMat& A);
  /// Solves A x = b in place, all columns at once (A^T = A: also the transposed solve).
  void solve(MatX& b) const;
  bool factorized() const { return factorized_; }
  /// Entries of L and L^T (the diagonal once) and the flops of the last factorization.
  double nnzFactors() const;
  double flops() const;

 private:
  struct Mumps;
  void analyse(const SpMat& A);
  void run(int job) const;
  std::unique_ptr<Mumps> mumps_;
  SpMat pattern_;                    ///< the pattern analysed (values unused)
  std::vector<int64_t> transposeOf_;  ///< position of A(j, i) for each A(i, j); empty: unsymmetric pattern
  std::vector<int> rows_, cols_;     ///< A's lower triangle, 1-based (MUMPS' coordinate format)
  std::vector<double> lower_;
  std::vector<int64_t> lowerFrom_;   ///< position in A of each entry of lower_
  double predictedFlops_ = 0.0;
  bool analysed_ = false, factorized_ = false;
};

}  // namespace flexsens
