// Anderson acceleration (type II, Walker and Ni 2011) of modified Newton's chord iteration
// x <- x + f(x), f(x) = -LU^-1 r(x) with a kept factorization: the next step is
//   f_k - (dX + dF) gamma,  gamma = argmin |f_k - dF gamma|_2,
// from the last `depth` differences of iterates (dX) and of chord steps (dF). Where the chord
// contracts slowly because the kept matrix is off along a few directions (the satellite's light
// spring nodes turning within a step), the fit removes those directions and fewer refreshes are
// needed. The history belongs to one matrix: reset() whenever it is refactorized.
// The fit is over the first `fitRows` entries (the positions; the multipliers are scaled
// otherwise), O(k^2 n) per iteration against the LU solve's O(nnz(L+U)), and no heap traffic.
#pragma once

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "core/Types.hpp"

namespace flexsens {

class AndersonMixing {
 public:
  static constexpr int kMaxDepth = 8;
  AndersonMixing(int depth, Eigen::Index size, Eigen::Index fitRows)
      : depth_(std::min(depth, kMaxDepth)), rows_(fitRows), dX_(size, depth_), dF_(size, depth_),
        xPrev_(size), fPrev_(size) {}
  void reset() {
    count_ = next_ = 0;
    has_ = false;
  }
  /// The step from iterate x whose chord step is f (both of the size given).
  template <class X, class F>
  VecX step(const X& x, const F& f) {
    if (depth_ == 0) return f;
    if (has_) {  // columns kept in a ring: the newest at next_
      dX_.col(next_) = x - xPrev_;
      dF_.col(next_) = f - fPrev_;
      count_ = std::min(count_ + 1, depth_);
      // Inner products of the new column with the kept ones (over the fit rows): O(k n) per
      // step instead of recomputing F^T F, O(k^2 n) (3-6% of a 3D solid's modified Newton).
      for (int i = 0; i < count_; ++i)
        gram_(i, next_) = gram_(next_, i) = dF_.col(i).head(rows_).dot(dF_.col(next_).head(rows_));
      next_ = (next_ + 1) % depth_;
    }
    xPrev_ = x;
    fPrev_ = f;
    has_ = true;
    if (count_ == 0) return f;
    // Least squares by the normal equations of the column-scaled differences (k x k, inline
    // storage): the differences of a converging iteration shrink geometrically, and unscaled
    // the small ones were lost to the large ones (test: linear problem, error 2e-4 instead of
    // 1e-10 after dim + 1 steps). A QR of the n x k block fits the same, at twice the time of
    // the satellite's modified Newton iteration.
    using Small = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, kMaxDepth, kMaxDepth>;
    using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxDepth, 1>;
    const auto Fq = dF_.topLeftCorner(rows_, count_);
    SmallVec scale(count_);
    for (int j = 0; j < count_; ++j) scale[j] = gram_(j, j) > 0.0 ? 1.0 / std::sqrt(gram_(j, j)) : 0.0;
    Small G = scale.asDiagonal() * gram_.topLeftCorner(count_, count_) * scale.asDiagonal();
    G.diagonal().array() += 1e-14;  // unit diagonal: nearly dependent differences stay solvable
    const SmallVec gamma = scale.asDiagonal() * G.ldlt().solve(scale.asDiagonal() * (Fq.transpose() * f.head(rows_)));
    if (!gamma.allFinite()) return f;
    VecX s = f;
    s.noalias() -= dX_.leftCols(count_) * gamma;
    s.noalias() -= dF_.leftCols(count_) * gamma;
    return s;
  }

 private:
  int depth_;
  Eigen::Index rows_;
  MatX dX_, dF_;
  Eigen::Matrix<double, kMaxDepth, kMaxDepth> gram_;  ///< dF_i . dF_j over the fit rows
  VecX xPrev_, fPrev_;
  int count_ = 0, next_ = 0;
  bool has_ = false;
};

}  // namespace flexsens
