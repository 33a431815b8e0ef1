// Sparse direct solvers on the Newton matrices flexsens factorizes (not a test; bench/linear).
// Reads Matrix Market files written with FLEXSENS_DUMP_MATRIX (see core/SparseLU.cpp) and,
// for each candidate, reports fill nnz(L+U)/nnz(A), the analysis time, the time of one
// numeric factorization (best of 5), the scaled residual of one solve and its rcond.
//
//   compare N_COORDINATES FILE.mtx            (the LU candidates; CHOLMOD too without constraint rows)
//   compare --constrained FILE.mtx           (constrained.cpp's candidates for [K, B^T; B, 0])
//
// The first N_COORDINATES unknowns are coordinates, the rest Lagrange multipliers.
#include <amd.h>
#include <cholmod.h>
#include <klu.h>
#include <umfpack.h>

#include <Eigen/Sparse>
#include <Eigen/SparseLU>
#include <unsupported/Eigen/SparseExtra>
#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "core/SaddlePointOrdering.hpp"

using SpMat = Eigen::SparseMatrix<double, Eigen::ColMajor, int64_t>;
using Vec = Eigen::VectorXd;

namespace {

double seconds(const std::function<void()>& f, int repeat) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

struct Row {
  std::string name;
  double fill = 0, predicted = -1, offDiagonalPivots = -1, analyse = 0, factor = 0, refactor = 0, residual = 0, rcond = 0;
};

double residual(const SpMat& A, const Vec& x, const Vec& b) {
  return (A * x - b).lpNorm<Eigen::Infinity>() /
         (A.cwiseAbs() * x.cwiseAbs() + b.cwiseAbs()).maxCoeff();
}

Row klu(const SpMat& A, const Vec& b, const std::string& name, int ordering, int btf,
        const std::vector<int64_t>* perm, double tol = 0.001) {
  Row row{name};
  klu_l_common c;
  klu_l_defaults(&c);
  c.tol = tol;
  c.ordering = ordering;
  c.btf = btf;
  auto* Ap = const_cast<int64_t*>(A.outerIndexPtr());
  auto* Ai = const_cast<int64_t*>(A.innerIndexPtr());
  auto* Ax = const_cast<double*>(A.valuePtr());
  const int64_t n = A.rows();
  klu_l_symbolic* S = nullptr;
  row.analyse = seconds([&] {
    if (S) klu_l_free_symbolic(&S, &c);
    S = perm ? klu_l_analyze_given(n, Ap, Ai, const_cast<int64_t*>(perm->data()),
                                   const_cast<int64_t*>(perm->data()), &c)
             : klu_l_analyze(n, Ap, Ai, &c);
  }, 1);
  klu_l_numeric* N = nullptr;
  row.factor = seconds([&] {
    if (N) klu_l_free_numeric(&N, &c);
    N = klu_l_factor(Ap, Ai, Ax, S, &c);
  }, 5);
  if (!N) { row.fill = -1; return row; }
  row.refactor = seconds([&] { klu_l_refactor(Ap, Ai, Ax, S, N, &c); }, 5);
  row.fill = double(N->lnz + N->unz - n) / A.nonZeros();
  row.predicted = (S->lnz + S->unz - n) / A.nonZeros();
  row.offDiagonalPivots = c.noffdiag;
  Vec x = b;
  klu_l_solve(S, N, n, 1, x.data(), &c);
  row.residual = residual(A, x, b);
  klu_l_condest(Ap, Ax, S, N, &c);
  row.rcond = 1.0 / c.condest;
  klu_l_free_numeric(&N, &c);
  klu_l_free_symbolic(&S, &c);
  return row;
}

Row umfpack(const SpMat& A, const Vec& b) {
  Row row{"UMFPACK (default strategy)"};
  const int64_t n = A.rows();
  double control[UMFPACK_CONTROL], info[UMFPACK_INFO];
  umfpack_dl_defaults(control);
  void* sym = nullptr;
  void* num = nullptr;
  row.analyse = seconds([&] {
    if (sym) umfpack_dl_free_symbolic(&sym);
    umfpack_dl_symbolic(n, n, A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(), &sym, control, info);
  }, 1);
  row.factor = seconds([&] {
    if (num) umfpack_dl_free_numeric(&num);
    umfpack_dl_numeric(A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(), sym, &num, control, info);
  }, 5);
  row.refactor = row.factor;
  int64_t lnz, unz, nr, nc, nzud;
  umfpack_dl_get_lunz(&lnz, &unz, &nr, &nc, &nzud, num);
  row.fill = double(lnz + unz - n) / A.nonZeros();
  Vec x(n);
  umfpack_dl_solve(UMFPACK_A, A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(), x.data(), b.data(), num,
                   control, info);
  row.residual = residual(A, x, b);
  row.rcond = info[UMFPACK_RCOND];
  umfpack_dl_free_numeric(&num);
  umfpack_dl_free_symbolic(&sym);
  return row;
}

Row eigenSuperLU(const SpMat& A64, const Vec& b) {
  Row row{"Eigen SparseLU (supernodal, COLAMD)"};
  Eigen::SparseMatrix<double> A = A64.cast<double>();
  Eigen::SparseLU<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> lu;
  row.analyse = seconds([&] { lu.analyzePattern(A); }, 1);
  row.factor = seconds([&] { lu.factorize(A); }, 5);
  row.refactor = row.factor;
  if (lu.info() != Eigen::Success) { row.fill = -1; return row; }
  row.fill = double(lu.nnzL() + lu.nnzU() - A.rows()) / A.nonZeros();
  Vec x = lu.solve(b);
  row.residual = residual(A64, x, b);
  return row;
}

// CHOLMOD's Cholesky of the lower triangle (the matrix is symmetric when it has no
// constraint rows); `ordering` CHOLMOD_AMD or CHOLMOD_METIS, `supernodal` CHOLMOD_SUPERNODAL
// or CHOLMOD_SIMPLICIAL. fill = 2 nnz(L) / nnz(A), comparable with the LU rows' nnz(L+U).
Row cholmod(const SpMat& A, const Vec& b, const std::string& name, int ordering, int supernodal) {
  Row row{name};
  cholmod_common c;
  cholmod_l_start(&c);
  c.nmethods = 1;
  c.method[0].ordering = ordering;
  c.postorder = 1;
  c.supernodal = supernodal;
  SpMat lower = A.triangularView<Eigen::Lower>();
  lower.makeCompressed();
  cholmod_sparse As{};
  As.nrow = As.ncol = A.rows();
  As.nzmax = lower.nonZeros();
  As.p = lower.outerIndexPtr();
  As.i = lower.innerIndexPtr();
  As.x = lower.valuePtr();
  As.stype = -1;
  As.itype = CHOLMOD_LONG;
  As.xtype = CHOLMOD_REAL;
  As.dtype = CHOLMOD_DOUBLE;
  As.sorted = 1;
  As.packed = 1;
  cholmod_factor* L = nullptr;
  row.analyse = seconds([&] {
    if (L) cholmod_l_free_factor(&L, &c);
    L = cholmod_l_analyze(&As, &c);
  }, 1);
  row.factor = seconds([&] { cholmod_l_factorize(&As, L, &c); }, 5);
  row.refactor = row.factor;
  if (c.status != CHOLMOD_OK || size_t(L->minor) < size_t(A.rows())) {  // minor < n: not positive definite
    row.fill = -1;
  } else {
    row.fill = 2.0 * c.lnz / A.nonZeros();
    cholmod_dense* B = cholmod_l_zeros(A.rows(), 1, CHOLMOD_REAL, &c);
    std::copy(b.data(), b.data() + b.size(), static_cast<double*>(B->x));
    cholmod_dense* X = cholmod_l_solve(CHOLMOD_A, L, B, &c);
    Vec x = Eigen::Map<Vec>(static_cast<double*>(X->x), A.rows());
    row.residual = residual(A, x, b);
    row.rcond = cholmod_l_rcond(L, &c);
    cholmod_l_free_dense(&X, &c);
    cholmod_l_free_dense(&B, &c);
  }
  cholmod_l_free_factor(&L, &c);
  cholmod_l_finish(&c);
  return row;
}

}  // namespace

void constrainedTable(const SpMat& A);

int main(int argc, char** argv) {
  if (argc == 3 && std::string(argv[1]) == "--constrained") {
    SpMat A;
    if (!Eigen::loadMarket(A, argv[2])) { std::fprintf(stderr, "cannot read %s\n", argv[2]); return 2; }
    A.makeCompressed();
    constrainedTable(A);
    return 0;
  }
  if (argc != 3) { std::fprintf(stderr, "usage: compare N_COORDINATES FILE.mtx\n"); return 2; }
  const int64_t ncoord = std::atol(argv[1]);
  SpMat A;
  if (!Eigen::loadMarket(A, argv[2])) { std::fprintf(stderr, "cannot read %s\n", argv[2]); return 2; }
  A.makeCompressed();
  Vec b = Vec::Ones(A.rows());
  std::vector<int64_t> perm = flexsens::saddlePointOrdering(A);
  std::vector<Row> rows = {
      klu(A, b, "KLU AMD (flexsens before 2026-11-24)", 0, 1, nullptr),
      klu(A, b, "KLU COLAMD", 1, 1, nullptr),
      klu(A, b, "KLU AMD, no BTF", 0, 0, nullptr),
      klu(A, b, "KLU saddle-point ordering, pivot tol 1e-3 (KLU's default)", 0, 0, &perm),
      klu(A, b, "**KLU saddle-point ordering, pivot tol 1e-6 (flexsens now)**", 0, 0, &perm, 1e-6),
      klu(A, b, "KLU saddle-point ordering, pivot tol 1e-10", 0, 0, &perm, 1e-10),
      umfpack(A, b),
      eigenSuperLU(A, b),
  };
  if (ncoord == A.rows()) {  // no constraint rows: symmetric positive definite in these models
    rows.push_back(cholmod(A, b, "CHOLMOD supernodal, AMD", CHOLMOD_AMD, CHOLMOD_SUPERNODAL));
    rows.push_back(cholmod(A, b, "CHOLMOD supernodal, METIS", CHOLMOD_METIS, CHOLMOD_SUPERNODAL));
    rows.push_back(cholmod(A, b, "CHOLMOD simplicial, AMD", CHOLMOD_AMD, CHOLMOD_SIMPLICIAL));
  }
  std::printf("| solver | nnz(L+U)/nnz(A) | predicted | off-diagonal pivots | analyse [ms] | factor [ms] | refactor [ms] | residual | rcond |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows)
    std::printf("| %s | %.2f | %.2f | %.0f | %.2f | %.3f | %.3f | %.1e | %.1e |\n", r.name.c_str(), r.fill, r.predicted, r.offDiagonalPivots, 1e3 * r.analyse,
                1e3 * r.factor, 1e3 * r.refactor, r.residual, r.rcond);
  std::printf("n = %ld (coordinates %ld), nnz(A) = %ld\n", long(A.rows()), long(ncoord), long(A.nonZeros()));
}
