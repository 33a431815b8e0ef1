// Builds a compressed-column sparse matrix from (row, col, value) additions whose sequence
// repeats from call to call. The first assembly records the sequence and builds the pattern;
// later assemblies only add values into cached slots (no sorting, no allocation).
#pragma once

#include <cstdint>
#include <vector>

#include "core/Types.hpp"

namespace flexsens {

class SparseAccumulator {
 public:
  void begin(int rows, int cols);
  void add(int64_t r, int64_t c, double v) {
    const uint64_t key = keyOf(r, c);
    if (recording_) {
      key_.push_back(key);
      value_.push_back(v);
      return;
    }
    if (k_ >= slot_.size() || key_[k_] != key) {
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
  /// (row, column) in one word: the check of each addition against the recorded sequence reads
  /// 8 bytes, not a 24-byte triplet (the Newton matrix's ~50k additions, 5% of the satellite's
  /// run). Rows and columns are below 2^31 (begin() takes ints).
  static uint64_t keyOf(int64_t r, int64_t c) { return (uint64_t(r) << 32) | uint64_t(c); }
  void rebuildFrom(size_t k, int64_t r, int64_t c, double v);
  void build();
  std::vector<uint64_t> key_;  ///< the recorded sequence of (row, column)
  std::vector<double> value_;  ///< the values added while recording
  std::vector<int64_t> slot_;
  SpMat mat_;
  size_t k_ = 0;
  bool recording_ = true;
  int rows_ = 0, cols_ = 0;
};

}  // namespace flexsens
