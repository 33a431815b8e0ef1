#include "core/SparseLU.hpp"

#include <cstring>
#include <sstream>

namespace flexsens {

SparseLU::SparseLU() { klu_l_defaults(&common_); }
SparseLU::~SparseLU() { release(); }

void SparseLU::release() {
  if (numeric_) klu_l_free_numeric(&numeric_, &common_);
  if (symbolic_) klu_l_free_symbolic(&symbolic_, &common_);
}

namespace {
bool samePattern(const SpMat& a, const SpMat& b) {
  return a.rows() == b.rows() && a.cols() == b.cols() && a.nonZeros() == b.nonZeros() &&
         std::memcmp(a.outerIndexPtr(), b.outerIndexPtr(), sizeof(int64_t) * (a.cols() + 1)) == 0 &&
         std::memcmp(a.innerIndexPtr(), b.innerIndexPtr(), sizeof(int64_t) * a.nonZeros()) == 0;
}
}  // namespace

void SparseLU::factor(const SpMat& A, const std::string& what) {
  if (!A.isCompressed()) throw std::logic_error("SparseLU::factor needs a compressed matrix");
  auto* Ap = const_cast<int64_t*>(A.outerIndexPtr());
  auto* Ai = const_cast<int64_t*>(A.innerIndexPtr());
  auto* Ax = const_cast<double*>(A.valuePtr());
  if (!symbolic_ || !samePattern(A, pattern_)) {
    release();
    symbolic_ = klu_l_analyze(A.rows(), Ap, Ai, &common_);
    if (!symbolic_) throw NumericalError("KLU could not analyse the " + what);
    pattern_ = A;
  }
  // klu_rcond is min |u_ii| / max |u_ii|: cheap, but it can be ~1e-17 for a matrix whose
  // condition number is 1e5 (the satellite with 60-segment springs: light nodes next to a
  // 100 kg body). When it looks bad, klu_condest (a 1-norm estimate, a few solves) decides.
  auto conditioned = [&](double rcondLimit) {
    klu_l_rcond(symbolic_, numeric_, &common_);
    if (common_.rcond > rcondLimit) return true;
    klu_l_condest(Ap, Ax, symbolic_, numeric_, &common_);
    common_.rcond = 1.0 / common_.condest;
    return common_.condest < 1e15;
  };
  bool ok;
  if (numeric_) {
    ok = klu_l_refactor(Ap, Ai, Ax, symbolic_, numeric_, &common_) == 1 &&
         common_.status == KLU_OK;
    // Refactoring keeps the old pivot order; on trouble, factor afresh with new pivoting.
    if (ok) ok = conditioned(1e-14);
    if (!ok) klu_l_free_numeric(&numeric_, &common_);
  }
  if (!numeric_) {
    numeric_ = klu_l_factor(Ap, Ai, Ax, symbolic_, &common_);
    ok = numeric_ && common_.status == KLU_OK && conditioned(1e-16);
  }
  ++count_;
  if (!ok || common_.status == KLU_SINGULAR) {
    std::ostringstream os;
    os << "the " << what << " is singular or nearly so (KLU status " << common_.status
       << ", reciprocal condition estimate " << (numeric_ ? common_.rcond : 0.0) << ")";
    if (numeric_) klu_l_free_numeric(&numeric_, &common_);
    throw NumericalError(os.str());
  }
}

void SparseLU::solve(MatX& b) const {
  if (!numeric_) throw std::logic_error("SparseLU::solve before factor");
  klu_l_solve(symbolic_, numeric_, b.rows(), b.cols(), b.data(), &common_);
}

VecX SparseLU::solve(const VecX& b) const {
  MatX x = b;
  solve(x);
  return x.col(0);
}

double SparseLU::rcond() const { return common_.rcond; }

}  // namespace flexsens
