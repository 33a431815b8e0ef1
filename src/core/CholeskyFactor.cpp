#include "core/CholeskyFactor.hpp"

#include <omp.h>

#include <cmath>
#include <cstring>
#include <stdexcept>

namespace flexsens {

namespace {
/// Entries whose transpose differs by more than this times sqrt(|A_ii| |A_jj|) (the bound of
/// an off-diagonal entry of a positive definite matrix) make A unsymmetric: a follower load's
/// or a damper's dQ/dq. Element matrices assembled as B^T D B agree to ~1e-16 of that scale.
constexpr double kSymmetryTolerance = 1e-11;
/// From this many rows on, CHOLMOD orders with AMD and with METIS and keeps the one of fewer
/// flops. Measured on dumped Newton matrices (bench/linear): METIS factors the shell panel at
/// n = 24495 in 0.71x AMD's time (fill 9.53 against 10.76) but loses at n = 1800 (11.1 against
/// 9.4 ms) and costs 2.5x AMD's analysis; on the solid pendulum the two are even.
constexpr size_t kTryMetisFrom = 20000;

/// CHOLMOD's view of a compressed lower triangle (no copy).
cholmod_sparse lowerView(SpMat& lower) {
  cholmod_sparse s{};
  s.nrow = s.ncol = size_t(lower.rows());
  s.nzmax = size_t(lower.nonZeros());
  s.p = lower.outerIndexPtr();
  s.i = lower.innerIndexPtr();
  s.x = lower.valuePtr();
  s.stype = -1;  // symmetric, lower triangle stored
  s.itype = CHOLMOD_LONG;
  s.xtype = CHOLMOD_REAL;
  s.dtype = CHOLMOD_DOUBLE;
  s.sorted = 1;
  s.packed = 1;
  return s;
}
}  // namespace

bool samePattern(const SpMat& a, const SpMat& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && a.nonZeros() == b.nonZeros() &&
         std::memcmp(a.outerIndexPtr(), b.outerIndexPtr(), sizeof(int64_t) * (a.cols() + 1)) == 0 &&
         std::memcmp(a.innerIndexPtr(), b.innerIndexPtr(), sizeof(int64_t) * a.nonZeros()) == 0;
}

std::vector<int64_t> transposePositions(const SpMat& A) {
  const int64_t n = A.cols();
  const int64_t* outer = A.outerIndexPtr();
  const int64_t* inner = A.innerIndexPtr();
  std::vector<int64_t> map(size_t(A.nonZeros()), -1);
  std::vector<int64_t> cursor(outer, outer + n);  // next unmatched entry of each column
  for (int64_t j = 0; j < n; ++j)
    for (int64_t k = outer[j]; k < outer[j + 1]; ++k) {
      const int64_t i = inner[k];  // A(i, j) is at k; A(j, i) is in column i, rows ascending
      while (cursor[i] < outer[i + 1] && inner[cursor[i]] < j) ++cursor[i];
      if (cursor[i] < outer[i + 1] && inner[cursor[i]] == j) map[size_t(k)] = cursor[i];
    }
  for (int64_t t : map)
    if (t < 0) return {};
  return map;
}

CholeskyFactor::CholeskyFactor() {
  cholmod_l_start(&common_);
  common_.print = 0;
  common_.nmethods = 1;  // AMD, and METIS beside it on large matrices (kTryMetisFrom)
  common_.method[0].ordering = CHOLMOD_AMD;
  common_.method[1].ordering = CHOLMOD_METIS;
  common_.postorder = 1;
  common_.quick_return_if_not_posdef = 1;
  common_.error_handler = nullptr;
  // Debian's CHOLMOD runs its supernodal assembly loops on 4 OpenMP threads (compiled in,
  // CHOLMOD_OMP_NUM_THREADS), more than the machines flexsens measures on have cores; their
  // wake-ups and spins were 15-20% of the solid pendulum's run at n = 24603 and the
  // factorizations took 1.7-2.2x longer than on one thread (bench/scaling/meshed_per_step.md).
  // flexsens runs one thread per process (MPI ranks spread sweeps and cases), so OpenMP
  // parallel regions run serially: max-active-levels 0 makes every region inactive.
  omp_set_max_active_levels(0);
}

CholeskyFactor::~CholeskyFactor() {
  release();
  cholmod_l_finish(&common_);
}

void CholeskyFactor::release() {
  if (factor_) cholmod_l_free_factor(&factor_, &common_);
}

// The pattern's transpose map and lower triangle; transposeOf_ empty when an entry has no
// transpose or a diagonal entry is missing (then A is never tried).
void CholeskyFactor::analyse(const SpMat& A) {
  release();
  pattern_ = A;
  const int64_t n = A.cols();
  const int64_t* outer = A.outerIndexPtr();
  const int64_t* inner = A.innerIndexPtr();
  std::vector<int64_t> map = transposePositions(A);
  bool complete = true;
  for (int64_t j = 0; j < n && complete; ++j) {
    bool diagonal = false;
    for (int64_t k = outer[j]; k < outer[j + 1]; ++k) diagonal |= inner[k] == j;
    complete = diagonal;
  }
  transposeOf_ = complete ? std::move(map) : std::vector<int64_t>();
  lower_ = A.triangularView<Eigen::Lower>();
  lower_.makeCompressed();
  lowerFrom_.clear();
  for (int64_t j = 0; j < n; ++j)
    for (int64_t k = outer[j]; k < outer[j + 1]; ++k)
      if (inner[k] >= j) lowerFrom_.push_back(k);
}

bool CholeskyFactor::symmetric(const SpMat& A) {
  if (!samePattern(A, pattern_)) analyse(A);
  if (transposeOf_.empty()) return false;
  const int64_t* outer = A.outerIndexPtr();
  const int64_t* inner = A.innerIndexPtr();
  const double* a = A.valuePtr();
  std::vector<double> diagonal(size_t(A.cols()));
  for (int64_t j = 0; j < A.cols(); ++j)
    for (int64_t k = outer[j]; k < outer[j + 1]; ++k)
      if (inner[k] == j) diagonal[size_t(j)] = a[k];
  for (double& d : diagonal) {
    if (!(d > 0.0)) return false;  // a multiplier's zero pivot, or not positive definite
    d = std::sqrt(d);
  }
  for (int64_t j = 0; j < A.cols(); ++j)
    for (int64_t k = outer[j]; k < outer[j + 1]; ++k) {
      const double scale = diagonal[size_t(inner[k])] * diagonal[size_t(j)];
      if (!(std::abs(a[k] - a[transposeOf_[size_t(k)]]) <= kSymmetryTolerance * scale)) return false;
    }
  return true;
}

bool CholeskyFactor::factor(const SpMat& A) {
  if (!samePattern(A, pattern_)) throw std::logic_error("CholeskyFactor::factor before symmetric()");
  double* lx = lower_.valuePtr();
  for (size_t e = 0; e < lowerFrom_.size(); ++e) lx[e] = A.valuePtr()[lowerFrom_[e]];
  cholmod_sparse view = lowerView(lower_);
  if (!factor_) {
    common_.nmethods = view.nrow >= kTryMetisFrom ? 2 : 1;
    factor_ = cholmod_l_analyze(&view, &common_);
  }
  if (!factor_) return false;
  cholmod_l_factorize(&view, factor_, &common_);
  return common_.status == CHOLMOD_OK && factorized() && positivePivots();
}

// A supernodal factor is LL' and stops at a pivot that is not positive (minor < n); a
// simplicial one (CHOLMOD's choice for small or very sparse matrices) is LDL', which goes
// through an indefinite matrix without pivoting: then D must be checked, and a negative entry
// sends the matrix to KLU's pivoting LU.
bool CholeskyFactor::positivePivots() const {
  if (factor_->is_ll) return true;
  const auto* start = static_cast<const int64_t*>(factor_->p);
  const auto* x = static_cast<const double*>(factor_->x);
  for (size_t j = 0; j < factor_->n; ++j)
    if (!(x[start[j]] > 0.0)) return false;  // D(j, j), the first entry of column j
  return true;
}

void CholeskyFactor::solve(MatX& b) const {
  cholmod_dense rhs{};
  rhs.nrow = size_t(b.rows());
  rhs.ncol = size_t(b.cols());
  rhs.nzmax = rhs.nrow * rhs.ncol;
  rhs.d = rhs.nrow;
  rhs.x = b.data();
  rhs.xtype = CHOLMOD_REAL;
  rhs.dtype = CHOLMOD_DOUBLE;
  cholmod_dense* x = cholmod_l_solve(CHOLMOD_A, factor_, &rhs, &common_);
  if (!x) throw std::runtime_error("CHOLMOD could not solve (out of memory)");
  std::memcpy(b.data(), x->x, sizeof(double) * rhs.nzmax);
  cholmod_l_free_dense(&x, &common_);
}

double CholeskyFactor::rcond() const { return factor_ ? cholmod_l_rcond(factor_, &common_) : 0.0; }

}  // namespace flexsens
