#include "core/SparseAccumulator.hpp"

#include <algorithm>

namespace flexsens {

void SparseAccumulator::begin(int rows, int cols) {
  if (rows != rows_ || cols != cols_) {
    recording_ = true;
    key_.clear();
    value_.clear();
    slot_.clear();
    rows_ = rows;
    cols_ = cols;
  }
  k_ = 0;
  if (recording_) {
    key_.clear();
    value_.clear();
    slot_.clear();
  }
  if (!recording_) std::fill(mat_.valuePtr(), mat_.valuePtr() + mat_.nonZeros(), 0.0);
}

void SparseAccumulator::addBlock(const std::vector<int>& rowMap, const std::vector<int>& colMap,
                                 const MatX& B, double s, int64_t r0, int64_t c0) {
  size_t j = 0, i = 0;
  if (!recording_) {
    // The replay, with the members in locals (add() reloads them after every store): the
    // Newton matrix's scatter, 5% of the satellite's run, 11% of the five-bar's.
    double* val = mat_.valuePtr();
    const uint64_t* key = key_.data();
    const int64_t* slot = slot_.data();
    const size_t count = slot_.size();
    size_t k = k_;
    for (; j < colMap.size(); ++j) {
      if (colMap[j] < 0) continue;
      const double* Bj = B.col(Eigen::Index(j)).data();
      for (i = 0; i < rowMap.size(); ++i) {
        if (rowMap[i] < 0) continue;
        if (k >= count || key[k] != keyOf(r0 + rowMap[i], c0 + colMap[j])) goto changed;
        val[slot[k++]] += s * Bj[i];
      }
    }
    k_ = k;
    return;
  changed:  // the sequence changed: the rest of the block through add(), which rebuilds
    k_ = k;
  }
  for (; j < colMap.size(); ++j, i = 0) {
    if (colMap[j] < 0) continue;
    for (; i < rowMap.size(); ++i) {
      if (rowMap[i] < 0) continue;
      add(r0 + rowMap[i], c0 + colMap[j], s * B(i, j));
    }
  }
}

void SparseAccumulator::rebuildFrom(size_t k, int64_t r, int64_t c, double v) {
  // Recover the values added so far in this pass, then switch back to recording.
  value_.resize(k);
  for (size_t i = 0; i < k; ++i) value_[i] = mat_.valuePtr()[slot_[i]];
  // Values of duplicates were summed into one slot: keep the sum on the first occurrence.
  std::vector<bool> seen(mat_.nonZeros(), false);
  for (size_t i = 0; i < k; ++i) {
    if (seen[slot_[i]]) value_[i] = 0.0;
    seen[slot_[i]] = true;
  }
  key_.resize(k);
  slot_.clear();
  recording_ = true;
  key_.push_back(keyOf(r, c));
  value_.push_back(v);
}

void SparseAccumulator::build() {
  std::vector<Eigen::Triplet<double, int64_t>> t;
  t.reserve(key_.size());
  for (size_t i = 0; i < key_.size(); ++i)
    t.emplace_back(int64_t(key_[i] >> 32), int64_t(key_[i] & 0xffffffffu), value_[i]);
  mat_.resize(rows_, cols_);
  mat_.setFromTriplets(t.begin(), t.end());
  mat_.makeCompressed();
  slot_.resize(key_.size());
  for (size_t i = 0; i < key_.size(); ++i) {
    const int64_t c = t[i].col();
    const int64_t* begin = mat_.innerIndexPtr() + mat_.outerIndexPtr()[c];
    const int64_t* end = mat_.innerIndexPtr() + mat_.outerIndexPtr()[c + 1];
    slot_[i] = std::lower_bound(begin, end, t[i].row()) - mat_.innerIndexPtr();
  }
  value_.clear();  // in the matrix now; recorded again only after a rebuild
}

const SpMat& SparseAccumulator::finish() {
  if (recording_) {
    build();
    recording_ = false;
  } else if (k_ != slot_.size()) {
    // Fewer additions than recorded: the sequence changed; rebuild from what this pass added.
    rebuildFrom(k_, 0, 0, 0.0);
    key_.pop_back();
    value_.pop_back();
    build();
    recording_ = false;
  }
  k_ = 0;
  return mat_;
}

void SparseAccumulator::setRowsToIdentity(const std::vector<int>& rows) {
  if (rows.empty()) return;
  for (Eigen::Index j = 0; j < mat_.outerSize(); ++j)
    for (SpMat::InnerIterator it(mat_, j); it; ++it)
      if (std::binary_search(rows.begin(), rows.end(), static_cast<int>(it.row())))
        it.valueRef() = it.row() == j ? 1.0 : 0.0;
}

}  // namespace flexsens
