#include "SchurFactor.hpp"

#include <algorithm>

namespace flexsens {

namespace {
/// Columns of C solved with K's factor at a time while making S: bounds the dense workspace
/// to n x 64 doubles (12.8 MB at n = 25000) whatever m is.
constexpr Eigen::Index kSchurChunk = 64;
/// S's reciprocal condition estimate below which the factorization is left to KLU: near a
/// singular S (dependent constraint rows) KLU's condition estimate and its error message
/// decide, as for every other matrix.
constexpr double kSchurRcondFloor = 1e-13;

/// A block of A as a compressed matrix whose values are the positions in A of its entries
/// (exact in a double below 2^53), and those positions read back in the block's order.
SpMat positionsBlock(std::vector<Eigen::Triplet<double, int64_t>>& entries, Eigen::Index rows,
                     Eigen::Index cols, std::vector<int64_t>& from) {
  SpMat block(rows, cols);
  block.setFromTriplets(entries.begin(), entries.end());
  block.makeCompressed();
  from.assign(block.valuePtr(), block.valuePtr() + block.nonZeros());
  return block;
}
}  // namespace

Eigen::Index SchurFactor::borderOf(const SpMat& A) {
  if (!samePattern(A, pattern_)) analyse(A);
  return Eigen::Index(border_.size());
}

// Splits the unknowns by their diagonal (zero: border) and records where each block's entries
// sit in A, so that a factorization of the same pattern only copies values.
void SchurFactor::analyse(const SpMat& A) {
  factorized_ = false;
  pattern_ = A;
  const int64_t n = A.cols();
  std::vector<int64_t> local(static_cast<size_t>(n));
  std::vector<bool> inBorder(static_cast<size_t>(n));
  primal_.clear();
  border_.clear();
  for (int64_t j = 0; j < n; ++j) {
    inBorder[size_t(j)] = A.coeff(j, j) == 0.0;
    auto& list = inBorder[size_t(j)] ? border_ : primal_;
    local[size_t(j)] = int64_t(list.size());
    list.push_back(j);
  }
  using Triplet = Eigen::Triplet<double, int64_t>;
  std::vector<Triplet> k, c, b;
  dAt_.clear();
  dFrom_.clear();
  const int64_t m = int64_t(border_.size());
  for (int64_t j = 0; j < n; ++j)
    for (int64_t e = A.outerIndexPtr()[j]; e < A.outerIndexPtr()[j + 1]; ++e) {
      const int64_t i = A.innerIndexPtr()[e], li = local[size_t(i)], lj = local[size_t(j)];
      const bool bi = inBorder[size_t(i)], bj = inBorder[size_t(j)];
      if (!bi && !bj) k.emplace_back(li, lj, double(e));
      else if (!bi) c.emplace_back(li, lj, double(e));
      else if (!bj) b.emplace_back(li, lj, double(e));
      else {
        dAt_.push_back(li + m * lj);
        dFrom_.push_back(e);
      }
    }
  const Eigen::Index np = Eigen::Index(primal_.size());
  K_ = positionsBlock(k, np, np, kFrom_);
  C_ = positionsBlock(c, np, m, cFrom_);
  B_ = positionsBlock(b, m, np, bFrom_);
}

void SchurFactor::gather(const SpMat& A) {
  const double* a = A.valuePtr();
  for (size_t e = 0; e < kFrom_.size(); ++e) K_.valuePtr()[e] = a[kFrom_[e]];
  for (size_t e = 0; e < cFrom_.size(); ++e) C_.valuePtr()[e] = a[cFrom_[e]];
  for (size_t e = 0; e < bFrom_.size(); ++e) B_.valuePtr()[e] = a[bFrom_[e]];
  D_.setZero(Eigen::Index(border_.size()), Eigen::Index(border_.size()));
  for (size_t e = 0; e < dFrom_.size(); ++e) D_.data()[dAt_[e]] = a[dFrom_[e]];
}

bool SchurFactor::factor(const SpMat& A) {
  if (!samePattern(A, pattern_)) analyse(A);
  factorized_ = false;
  if (border_.empty() || primal_.empty()) return false;
  gather(A);
  if (!cholesky_.symmetric(K_) || !cholesky_.factor(K_)) return false;
  makeSchurComplement();
  factorized_ = schur_.rcond() > kSchurRcondFloor;
  return factorized_;
}

// S = D - B K^-1 C, kSchurChunk columns of C at a time; then S's LU.
void SchurFactor::makeSchurComplement() {
  MatX S = D_, X;
  const Eigen::Index m = S.cols();
  for (Eigen::Index first = 0; first < m; first += kSchurChunk) {
    const Eigen::Index width = std::min(kSchurChunk, m - first);
    X = MatX(C_.middleCols(first, width));
    cholesky_.solve(X);
    S.middleCols(first, width).noalias() -= B_ * X;
  }
  schur_.compute(S);
}

// [K C; B D] [xP; xM] = [bP; bM]: y = K^-1 bP, S xM = bM - B y, xP = y - K^-1 C xM. The
// transposed system swaps B and C^T and takes S^T.
void SchurFactor::solveBlocks(MatX& b, bool transposed) const {
  const Eigen::Index np = Eigen::Index(primal_.size()), m = Eigen::Index(border_.size()), k = b.cols();
  MatX y(np, k), r(m, k);
  for (Eigen::Index i = 0; i < np; ++i) y.row(i) = b.row(primal_[size_t(i)]);
  for (Eigen::Index i = 0; i < m; ++i) r.row(i) = b.row(border_[size_t(i)]);
  cholesky_.solve(y);
  if (transposed) {
    r.noalias() -= C_.transpose() * y;
    r = schur_.transpose().solve(r);
  } else {
    r.noalias() -= B_ * y;
    r = schur_.solve(r);
  }
  MatX t = transposed ? MatX(B_.transpose() * r) : MatX(C_ * r);
  cholesky_.solve(t);
  y -= t;
  for (Eigen::Index i = 0; i < np; ++i) b.row(primal_[size_t(i)]) = y.row(i);
  for (Eigen::Index i = 0; i < m; ++i) b.row(border_[size_t(i)]) = r.row(i);
}

double SchurFactor::nnzFactors() const {
  const double m = double(border_.size());
  return 2.0 * cholesky_.nnzL() - double(primal_.size()) + m * m;
}

double SchurFactor::factorFlops() const {
  const double m = double(border_.size());
  return cholesky_.flops() + m * (4.0 * cholesky_.nnzL() + 2.0 * double(B_.nonZeros())) + 2.0 / 3.0 * m * m * m;
}

double SchurFactor::solveFlops() const {
  const double m = double(border_.size());
  return 8.0 * cholesky_.nnzL() + 2.0 * double(B_.nonZeros() + C_.nonZeros()) + 2.0 * m * m;
}

double SchurFactor::rcond() const { return std::min(cholesky_.rcond(), schur_.rcond()); }

}  // namespace flexsens
