// Builds a compressed-column sparse matrix from (row, col, value) additions whose sequence
// repeats from call to call. The first assembly records the sequence and builds the pattern;
// later assemblies only add values into cached slots (no sorting, no allocation).
#pragma once

#include <vector>

#include "core/Types.hpp"

namespace flexsens {

class SparseAccumulator {
 public:
  void begin(int rows, int cols);
  void add(int64_t r, int64_t c, double v) {
    if (recording_) {
      trip_.push_back({r, c, v});
      return;
    }
    if (k_ >= slot_.size() || trip_[k_].r != r || trip_[k_].c != c) {
      // The sequence changed (different model or different call order): rebuild.
      rebuildFrom(k_, r, c, v);
      return;
    }
    mat_.valuePtr()[slot_[k_++]] += v;
  }
  /// Adds block B at (r0, c0) scaled by s, mapping local indices through map (-1 = skip).
  void addBlock(const std::vector<int>& rowMap, const std::vector<int>& colMap, const MatX& B,
                double s, int64_t r0 = 0, int64_t c0 = 0);
  const SpMat& finish();
  const SpMat& matrix() const { return mat_; }
  /// After finish(): rows `rows` (sorted) of the matrix become rows of the identity, their
  /// other entries explicit zeros (the diagonal must be in the pattern: add it as 0).
  void setRowsToIdentity(const std::vector<int>& rows);

 private:
  struct Trip { int64_t r, c; double v; };
  void rebuildFrom(size_t k, int64_t r, int64_t c, double v);
  void build();
  std::vector<Trip> trip_;
  std::vector<int64_t> slot_;
  SpMat mat_;
  size_t k_ = 0;
  bool recording_ = true;
  int rows_ = 0, cols_ = 0;
};

}  // namespace flexsens
