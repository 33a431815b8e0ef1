#include "core/MumpsFactor.hpp"

#include <dmumps_c.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "core/CholeskyFactor.hpp"

namespace flexsens {

namespace {
/// |A(i, j) - A(j, i)| above this times sqrt(c_i c_j) (c: a column's largest |entry|) makes A
/// unsymmetric: a follower load's or a damper's dQ/dq, the midpoint rule's tangent. Assembled
/// symmetric tangents agree to ~1e-16 of that scale; the refinement against A (SparseLU) sees
/// what a tolerated asymmetry costs.
constexpr double kSymmetryTolerance = 1e-11;
/// Relative pivot size (of the scaled matrix's largest entry) below which a pivot is null. The
/// Newton matrices' smallest pivots are 1e-10-1e-6 after MUMPS' scaling (the multipliers' Schur
/// entries); a false alarm costs only KLU's slower factorization.
constexpr double kNullPivot = 1e-12;
/// MUMPS' job codes and its USE_COMM_WORLD (the sequential library's stand-in communicator).
constexpr int kInit = -1, kEnd = -2, kAnalyse = 1, kFactor = 2, kSolve = 3, kCommWorld = -987654;
/// MUMPS errors that ask for a larger workspace (ICNTL(14), a margin in % over its estimate).
bool workspaceTooSmall(int info) { return info == -8 || info == -9 || info == -14 || info == -15 || info == -17 || info == -20; }
}  // namespace

struct MumpsFactor::Mumps {
  DMUMPS_STRUC_C id{};
};

MumpsFactor::MumpsFactor() : mumps_(std::make_unique<Mumps>()) {
  DMUMPS_STRUC_C& id = mumps_->id;
  id.comm_fortran = kCommWorld;
  id.par = 1;
  id.sym = 2;  // general symmetric: LDL^T with 1x1 and 2x2 pivots (the zero diagonal of the multipliers)
  run(kInit);
  id.icntl[0] = id.icntl[1] = id.icntl[2] = -1;  // ICNTL(1-3): no messages
  id.icntl[3] = 0;
  id.icntl[6] = 0;   // ICNTL(7): AMD; METIS orders as well (same factor time) at 3-9x the analysis
  id.icntl[15] = 1;  // ICNTL(16): one OpenMP thread: reproducible sums, and the machine's other work
  // ICNTL(24), CNTL(3): pivots below kNullPivot |A_pre|_inf of the scaled matrix count as null.
  // MUMPS' default (1e-5 eps) misses the round-off pivot of an exactly singular A (a repeated
  // constraint row: it then "solved" with a backward error of 1); a null pivot sends A to KLU,
  // whose condition estimate decides and names what is singular.
  id.icntl[23] = 1;
  id.cntl[2] = kNullPivot;
}

MumpsFactor::~MumpsFactor() { run(kEnd); }

void MumpsFactor::run(int job) const {
  mumps_->id.job = job;
  dmumps_c(&mumps_->id);
}

// The transpose map, the lower triangle in MUMPS' 1-based coordinates, and MUMPS' analysis.
void MumpsFactor::analyse(const SpMat& A) {
  pattern_ = A;
  analysed_ = factorized_ = false;
  transposeOf_ = transposePositions(A);
  if (transposeOf_.empty()) return;
  rows_.clear();
  cols_.clear();
  lowerFrom_.clear();
  for (int64_t j = 0; j < A.cols(); ++j)
    for (int64_t k = A.outerIndexPtr()[j]; k < A.outerIndexPtr()[j + 1]; ++k)
      if (A.innerIndexPtr()[k] >= j) {
        rows_.push_back(int(A.innerIndexPtr()[k] + 1));
        cols_.push_back(int(j + 1));
        lowerFrom_.push_back(k);
      }
  lower_.resize(lowerFrom_.size());
  for (size_t e = 0; e < lowerFrom_.size(); ++e) lower_[e] = A.valuePtr()[lowerFrom_[e]];
  DMUMPS_STRUC_C& id = mumps_->id;
  id.n = int(A.rows());
  id.nnz = int64_t(lower_.size());
  id.irn = rows_.data();
  id.jcn = cols_.data();
  id.a = lower_.data();
  run(kAnalyse);
  analysed_ = id.infog[0] >= 0;
  predictedFlops_ = analysed_ ? id.rinfog[0] : 0.0;  // RINFOG(1)
}

bool MumpsFactor::analysed(const SpMat& A) {
  if (A.nonZeros() > std::numeric_limits<int>::max() / 2) return false;  // MUMPS' 32-bit indices
  if (!samePattern(A, pattern_)) analyse(A);
  return analysed_;
}

bool MumpsFactor::symmetric(const SpMat& A) const {
  const int64_t* outer = A.outerIndexPtr();
  const double* a = A.valuePtr();
  std::vector<double> scale(size_t(A.cols()), 0.0);
  for (int64_t j = 0; j < A.cols(); ++j)
    for (int64_t k = outer[j]; k < outer[j + 1]; ++k) scale[size_t(j)] = std::max(scale[size_t(j)], std::abs(a[k]));
  for (double& c : scale) c = std::sqrt(c);
  for (int64_t j = 0; j < A.cols(); ++j)
    for (int64_t k = outer[j]; k < outer[j + 1]; ++k) {
      const double bound = kSymmetryTolerance * scale[size_t(A.innerIndexPtr()[k])] * scale[size_t(j)];
      if (!(std::abs(a[k] - a[transposeOf_[size_t(k)]]) <= bound)) return false;
    }
  return true;
}

bool MumpsFactor::factor(const SpMat& A) {
  if (!analysed_ || !samePattern(A, pattern_)) throw std::logic_error("MumpsFactor::factor before analysed()");
  for (size_t e = 0; e < lowerFrom_.size(); ++e) lower_[e] = A.valuePtr()[lowerFrom_[e]];
  DMUMPS_STRUC_C& id = mumps_->id;
  id.a = lower_.data();
  // MUMPS sizes its workspace from the analysis; delayed pivots can need more: retry larger.
  for (id.icntl[13] = 20;; id.icntl[13] *= 4) {
    run(kFactor);
    if (!workspaceTooSmall(id.infog[0]) || id.icntl[13] > 1000) break;
  }
  factorized_ = id.infog[0] >= 0 && id.infog[27] == 0;  // -10 or INFOG(28) null pivots: KLU then says where
  return factorized_;
}

void MumpsFactor::solve(MatX& b) const {
  if (!factorized_) throw std::logic_error("MumpsFactor::solve before factor");
  DMUMPS_STRUC_C& id = mumps_->id;
  id.rhs = b.data();
  id.nrhs = int(b.cols());
  id.lrhs = int(b.rows());
  run(kSolve);
  if (id.infog[0] < 0)
    throw std::runtime_error("MUMPS could not solve (error " + std::to_string(id.infog[0]) + ")");
}

// INFOG(29): the factors' entries (L and D); negative: in millions.
double MumpsFactor::nnzFactors() const {
  const int entries = mumps_->id.infog[28];
  const double nnzL = entries >= 0 ? double(entries) : -1e6 * double(entries);
  return 2.0 * nnzL - double(pattern_.rows());
}

double MumpsFactor::flops() const { return mumps_->id.rinfog[2]; }  // RINFOG(3)

}  // namespace flexsens
