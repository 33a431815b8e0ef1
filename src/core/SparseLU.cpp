#include "core/SparseLU.hpp"

#include "core/SaddlePointOrdering.hpp"

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <sstream>

namespace flexsens {

SparseLU::SparseLU() {
  klu_l_defaults(&common_);
  // The ordering makes every diagonal pivot nonzero in exact arithmetic (a Schur entry for a
  // multiplier), but one can be small next to its column: a light node's M/(beta h^2) beside
  // a stiff element's entries. KLU's default tolerance (1e-3) then pivots off the diagonal and
  // fills (satellite refine 5: 104 such pivots, 14x the fill); 1e-6 keeps the diagonal there
  // with a backward error of 2e-16 (bench/linear). Newton and the sensitivity solve's
  // backward-error test (core/PreconditionedSolve) see any loss of accuracy.
  common_.tol = 1e-6;
  common_.btf = 0;  // one block: BTF finds none in these matrices and costs an analysis pass
  if (const char* choice = std::getenv("FLEXSENS_LINEAR_SOLVER")) {
    const std::string c = choice;
    if (c == "klu") choice_ = Choice::KluOnly;
    else if (c == "cholesky") choice_ = Choice::NoLdlt;
    else if (c != "auto" && !c.empty())
      throw InputError("FLEXSENS_LINEAR_SOLVER='" + c + "' in the environment: expected auto, cholesky or klu");
  }
}
SparseLU::~SparseLU() { release(); }

void SparseLU::release() {
  if (numeric_) klu_l_free_numeric(&numeric_, &common_);
  if (symbolic_) klu_l_free_symbolic(&symbolic_, &common_);
}

namespace {
/// Flops of a factorization from which a symmetric matrix with constraint rows is factored by
/// MUMPS instead of KLU: MUMPS' predicted flops, or KLU's own count once KLU has factored the
/// pattern (KLU can fill far beyond MUMPS: the five-bar's link modelled rigid, 90 MFLOP and
/// 52 ms in KLU, 7 ms in MUMPS, whose analysis predicted 0.4 MFLOP). MUMPS costs ~0.5 ms more
/// per factorization than KLU on small matrices (the five-bar's meshed link, n = 1499,
/// 0.4 MFLOP: KLU 0.3 ms, MUMPS 1.0 ms; the satellite refined 10 times, n = 5640, 3.6 MFLOP:
/// 1.6 against 3.2 ms) and runs at 2-4x KLU's flop rate on large ones (the solid pendulum held
/// by support rows, n = 1721, 14 MFLOP: 9.0 against 3.2 ms; n = 20870: 1078 against 125 ms):
/// from 10 MFLOP on MUMPS is clearly ahead (bench/linear/constrained.md).
constexpr double kLdltFromFlops = 1e7;
/// Matrices with fewer entries than this are never analysed for LDL^T: their factorization
/// costs at most a few MFLOP in the models measured (multibody matrices, fill ~1.3).
constexpr Eigen::Index kLdltFromNonzeros = 20000;
/// Scales below this are round-off at the underflow level (1e3 DBL_MIN / DBL_EPSILON ~ 1e-289).
constexpr double kUnderflowScale = 1e3 * std::numeric_limits<double>::min() / std::numeric_limits<double>::epsilon();
}  // namespace

namespace {
/// Benchmark aid (bench/linear): FLEXSENS_DUMP_MATRIX=PREFIX writes the matrices handed to
/// factor() number FLEXSENS_DUMP_AT (default 100) and every 100th after it, up to three, as
/// PREFIX_<k>.mtx (Matrix Market, 1-based), so solvers can be compared on real matrices.
void dumpIfAsked(const SpMat& A, long count) {
  static const char* prefix = std::getenv("FLEXSENS_DUMP_MATRIX");
  if (!prefix) return;
  static const long first = std::getenv("FLEXSENS_DUMP_AT") ? std::atol(std::getenv("FLEXSENS_DUMP_AT")) : 100;
  if (count < first || (count - first) % 100 != 0 || count > first + 200) return;
  std::ofstream f(std::string(prefix) + "_" + std::to_string(count) + ".mtx");
  f << "%%MatrixMarket matrix coordinate real general\n" << A.rows() << " " << A.cols() << " " << A.nonZeros() << "\n";
  f.precision(17);
  for (Eigen::Index j = 0; j < A.outerSize(); ++j)
    for (SpMat::InnerIterator it(A, j); it; ++it) f << it.row() + 1 << " " << j + 1 << " " << it.value() << "\n";
}
}  // namespace

void SparseLU::factor(const SpMat& A, const std::string& what) {
  factor(A, [&what] { return what; });
}

void SparseLU::factor(const SpMat& A, const std::function<std::string()>& what) {
  if (!A.isCompressed()) throw std::logic_error("SparseLU::factor needs a compressed matrix");
  dumpIfAsked(A, count_);
  // A, for solve()'s refinement (values only when the pattern is the last one)
  if (samePattern(A, matrix_)) std::copy(A.valuePtr(), A.valuePtr() + A.nonZeros(), matrix_.valuePtr());
  else matrix_ = A;
  const auto start = std::chrono::steady_clock::now();
  ldlt_ = nullptr;
  const bool cholesky = factorCholesky(A);
  bool ldlt = !cholesky && factorLDLT(A);
  // KLU throws NumericalError for a singular A. A pattern KLU filled beyond kLdltFromFlops goes
  // to LDL^T at once: a run under modified Newton may factor it only once and then pay KLU's
  // filled solves at every iteration (the five-bar's rigid link, 0.3 s: 15.0 s against 3.4 s).
  if (!cholesky && !ldlt) ldlt = factorLU(A, what) && factorLDLT(A);
  ++count_;
  seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const double nnzFactor = cholesky ? 2.0 * cholesky_->nnzL() - double(A.rows())
                           : ldlt   ? ldlt_->nnzFactors()
                                    : double(numeric_->lnz + numeric_->unz - A.rows());
  fill_ = nnzFactor / double(std::max<Eigen::Index>(1, A.nonZeros()));
  maxFill_ = std::max(maxFill_, fill_);
}

// Cholesky when A is symmetric with a positive diagonal and turns out positive definite.
bool SparseLU::factorCholesky(const SpMat& A) {
  cholesky_ = nullptr;
  if (choice_ == Choice::KluOnly) return false;
  if (!choleskyOwner_->symmetric(A) || !choleskyOwner_->factor(A)) return false;
  cholesky_ = choleskyOwner_.get();
  ++choleskyCount_;
  factorFlops_ = cholesky_->flops();
  return true;
}

// LDL^T when A is large, symmetric (with a zero diagonal block: positive definite ones went to
// Cholesky) and MUMPS factors it; MUMPS is made when the first matrix qualifies.
bool SparseLU::factorLDLT(const SpMat& A) {
  ldlt_ = nullptr;
  if (choice_ != Choice::Any || A.nonZeros() < kLdltFromNonzeros) return false;
  if (!ldltOwner_) ldltOwner_ = std::make_unique<MumpsFactor>();
  MumpsFactor& f = *ldltOwner_;
  if (!f.analysed(A)) return false;
  const double kluFlops = symbolic_ && samePattern(A, pattern_) ? kluFlops_ : 0.0;
  if (std::max(f.predictedFlops(), kluFlops) < kLdltFromFlops || !f.symmetric(A) || !f.factor(A)) return false;
  ldlt_ = &f;
  ++ldltCount_;
  factorFlops_ = f.flops();
  return true;
}

// KLU; true when it factored afresh (a new pattern, or new pivots): its flop count is new.
bool SparseLU::factorLU(const SpMat& A, const std::function<std::string()>& what) {
  bool fresh = false;
  auto* Ap = const_cast<int64_t*>(A.outerIndexPtr());
  auto* Ai = const_cast<int64_t*>(A.innerIndexPtr());
  auto* Ax = const_cast<double*>(A.valuePtr());
  if (!symbolic_ || !samePattern(A, pattern_)) {
    release();
    kluFlops_ = 0.0;
    std::vector<int64_t> perm = saddlePointOrdering(A);
    symbolic_ = klu_l_analyze_given(A.rows(), Ap, Ai, perm.data(), perm.data(), &common_);
    if (!symbolic_) throw NumericalError("KLU could not analyse the " + what());
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
    if (numeric_ && klu_l_flops(symbolic_, numeric_, &common_)) factorFlops_ = kluFlops_ = common_.flops;
    fresh = true;
  }
  if (!ok || common_.status == KLU_SINGULAR) {
    std::ostringstream os;
    os << "the " << what() << " is singular or nearly so (KLU status " << common_.status
       << ", reciprocal condition estimate " << (numeric_ ? common_.rcond : 0.0) << ")";
    if (numeric_) klu_l_free_numeric(&numeric_, &common_);
    ++count_;
    throw NumericalError(os.str());
  }
  return fresh;
}

double SparseLU::solveFlops() const {
  if (cholesky_) return 4.0 * cholesky_->nnzL();  // L and L^T, a multiply and an add each
  if (ldlt_) return 2.0 * ldlt_->nnzFactors();
  return numeric_ ? 2.0 * double(numeric_->lnz + numeric_->unz) : 0.0;
}

void SparseLU::solve(MatX& b, bool refine) const {
  if (!factorized()) throw std::logic_error("SparseLU::solve before factor");
  if (!refine) {
    plainSolve(b);
    return;
  }
  this->refine(b);
}

void SparseLU::plainSolve(MatX& b) const {
  if (cholesky_) cholesky_->solve(b);
  else if (ldlt_) ldlt_->solve(b);
  else klu_l_solve(symbolic_, numeric_, b.rows(), b.cols(), b.data(), &common_);
}

// Iterative refinement, up to twice, while the componentwise backward error
// max_i |b - A x|_i / (|A| |x| + |b|)_i is above kRefineAbove (componentwise: the constraint
// rows are ~1e6 times smaller than the dynamic rows M/(beta h^2), so a normwise measure would
// not see their error). The saddle-point ordering pivots on the diagonal; near a singular
// Phi_q (a mechanism at its toggle) a multiplier's Schur pivot is small and a plain solve can
// lose digits there; refined, the backward error stays at round-off (test_sparse_lu: 1.6e-16
// as two constraint rows become parallel). An accurate solve costs one pass over A for all
// right-hand sides together: x and r are held row-major, so that each entry of A meets the
// row of every column in one cache line (a pass per column was 22% of a ten-parameter run).
void SparseLU::refine(MatX& b) const {
  MatX& x = x_;
  x = b;
  plainSolve(x);
  const auto* outer = matrix_.outerIndexPtr();
  const auto* inner = matrix_.innerIndexPtr();
  const double* value = matrix_.valuePtr();
  const Eigen::Index k = b.cols();
  for (int pass = 0; pass < 2; ++pass) {
    xRows_ = x;        // row-major copies: row j holds x(j, 0..k-1)
    rRows_ = b;        // r = b - A x
    scaleRows_ = b.cwiseAbs();  // |A| |x| + |b|
    for (Eigen::Index j = 0; j < matrix_.outerSize(); ++j) {
      const double* xj = xRows_.row(j).data();
      for (auto e = outer[j]; e < outer[j + 1]; ++e) {
        double* ri = rRows_.row(inner[e]).data();
        double* si = scaleRows_.row(inner[e]).data();
        for (Eigen::Index c = 0; c < k; ++c) {
          const double t = value[e] * xj[c];
          ri[c] -= t;
          si[c] += std::abs(t);
        }
      }
    }
    // Componentwise backward error; a scale at the underflow level (the tiny entries of a
    // parameter's solution outside the body it acts on: residual and scale both ~1e-323 gave
    // omega = 1 and a useless second pass on every sensitivity solve) counts as kUnderflowScale.
    double omega = 0.0;
    for (Eigen::Index i = 0; i < rRows_.rows(); ++i)
      for (Eigen::Index c = 0; c < k; ++c)
        if (rRows_(i, c) != 0.0) omega = std::max(omega, std::abs(rRows_(i, c)) / std::max(scaleRows_(i, c), kUnderflowScale));
    if (omega <= kRefineAbove) break;
    MatX r = rRows_;
    plainSolve(r);
    x += r;
  }
  b = x;
}

VecX SparseLU::solveTransposed(const VecX& b) const {
  if (!factorized()) throw std::logic_error("SparseLU::solveTransposed before factor");
  MatX x = b;
  if (cholesky_) cholesky_->solve(x);
  else if (ldlt_) ldlt_->solve(x);  // A^T = A
  else klu_l_tsolve(symbolic_, numeric_, x.rows(), x.cols(), x.data(), &common_);
  return x.col(0);
}

VecX SparseLU::solve(const VecX& b, bool refine) const {
  MatX& x = b_;
  x = b;
  solve(x, refine);
  return x.col(0);
}

double SparseLU::rcond() const {
  if (cholesky_) return cholesky_->rcond();
  if (!ldlt_) return common_.rcond;
  double norm1 = 0.0;  // |A|_1, the largest column sum
  for (Eigen::Index j = 0; j < matrix_.outerSize(); ++j) norm1 = std::max(norm1, matrix_.col(j).cwiseAbs().sum());
  return 1.0 / (norm1 * inverseNorm1());
}

// Hager's estimate of |A^-1|_1 (Higham, Accuracy and Stability, alg. 15.1), for a symmetric A:
// a few solves, the estimate a lower bound that is rarely off by more than 3x.
double SparseLU::inverseNorm1() const {
  const Eigen::Index n = matrix_.rows();
  MatX x = MatX::Constant(n, 1, 1.0 / double(n));
  double estimate = 0.0;
  for (int iteration = 0; iteration < 5; ++iteration) {
    MatX y = x;
    plainSolve(y);
    estimate = y.lpNorm<1>();
    MatX z = y.unaryExpr([](double v) { return v >= 0.0 ? 1.0 : -1.0; });
    plainSolve(z);  // A^-T sign(y) = A^-1 sign(y)
    Eigen::Index j;
    if (z.col(0).cwiseAbs().maxCoeff(&j) <= z.col(0).dot(x.col(0))) break;
    x.setZero();
    x(j, 0) = 1.0;
  }
  return estimate;
}

}  // namespace flexsens
