// Solvers for the Newton matrices with constraint rows [K, B^T; B, 0] (bench/linear; not a
// test): KLU as flexsens used it for them, SchurFactor (CHOLMOD on K, dense S for the
// multipliers; bench/linear/SchurFactor), MUMPS' symmetric-indefinite LDL^T of the whole
// matrix (Debian's sequential build; flexsens' core/MumpsFactor), and, on K alone (the matrix
// without its constraint rows: what a grounded body gives), CHOLMOD and MUMPS' SPD LDL^T. One table per matrix:
// fill, analysis, factorization (best of 3; KLU: its refactorization, what the integrators
// repeat), one solve of one right-hand side, the flop rate of the factorization and the
// componentwise backward error max_i |b - A x|_i / (|A| |x| + |b|)_i of a plain solve, b = 1.
#include <cholmod.h>
#include <dmumps_c.h>
#include <klu.h>

#include <chrono>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "core/CholeskyFactor.hpp"
#include "core/SaddlePointOrdering.hpp"
#include "SchurFactor.hpp"

using flexsens::SpMat;
using Vec = Eigen::VectorXd;

namespace {

double bestOf(int repeat, const std::function<void()>& f) {
  double best = 1e300;
  for (int r = 0; r < repeat; ++r) {
    const auto t0 = std::chrono::steady_clock::now();
    f();
    best = std::min(best, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
  }
  return best;
}

struct Row {
  std::string name;
  double fill = -1, analyse = 0, factor = 0, solve = 0, gflops = 0, berr = -1;
};

double backwardError(const SpMat& A, const Vec& x, const Vec& b) {
  const Vec r = (b - A * x).cwiseAbs(), s = A.cwiseAbs() * x.cwiseAbs() + b.cwiseAbs();
  double omega = 0;
  for (Eigen::Index i = 0; i < r.size(); ++i)
    if (r[i] != 0) omega = std::max(omega, r[i] / s[i]);
  return omega;
}

Row kluAsFlexsens(const SpMat& A, const Vec& b) {
  Row row{"KLU, saddle-point ordering, tol 1e-6 (flexsens before)"};
  klu_l_common c;
  klu_l_defaults(&c);
  c.tol = 1e-6;
  c.btf = 0;
  auto* Ap = const_cast<int64_t*>(A.outerIndexPtr());
  auto* Ai = const_cast<int64_t*>(A.innerIndexPtr());
  auto* Ax = const_cast<double*>(A.valuePtr());
  std::vector<int64_t> perm;
  klu_l_symbolic* S = nullptr;
  row.analyse = bestOf(1, [&] {
    perm = flexsens::saddlePointOrdering(A);
    S = klu_l_analyze_given(A.rows(), Ap, Ai, perm.data(), perm.data(), &c);
  });
  klu_l_numeric* N = klu_l_factor(Ap, Ai, Ax, S, &c);
  if (!N) return row;
  row.factor = bestOf(3, [&] { klu_l_refactor(Ap, Ai, Ax, S, N, &c); });
  row.fill = double(N->lnz + N->unz - A.rows()) / double(A.nonZeros());
  klu_l_flops(S, N, &c);
  row.gflops = c.flops / row.factor * 1e-9;
  Vec x = b;
  row.solve = bestOf(3, [&] { x = b; klu_l_solve(S, N, A.rows(), 1, x.data(), &c); });
  row.berr = backwardError(A, x, b);
  klu_l_free_numeric(&N, &c);
  klu_l_free_symbolic(&S, &c);
  return row;
}

Row schur(const SpMat& A, const Vec& b) {
  Row row{"SchurFactor: CHOLMOD on K, dense LU of S"};
  flexsens::SchurFactor f;
  row.analyse = bestOf(1, [&] { f.borderOf(A); });
  bool ok = true;
  row.factor = bestOf(3, [&] { ok = f.factor(A); });
  if (!ok) return row;
  row.fill = f.nnzFactors() / double(A.nonZeros());
  row.gflops = f.factorFlops() / row.factor * 1e-9;
  Eigen::MatrixXd x;
  row.solve = bestOf(3, [&] { x = b; f.solve(x); });
  row.berr = backwardError(A, x.col(0), b);
  return row;
}

// CHOLMOD (flexsens' CholeskyFactor) on K, the unknowns with a nonzero diagonal: the bound a
// Schur or null-space method cannot beat; it does not solve A (no backward error).
SpMat blockK(const SpMat& A) {
  std::vector<Eigen::Triplet<double, int64_t>> entries;
  std::vector<int64_t> local(static_cast<size_t>(A.rows()), -1);
  int64_t np = 0;
  for (int64_t j = 0; j < A.rows(); ++j)
    if (A.coeff(j, j) != 0.0) local[size_t(j)] = np++;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j)
    for (SpMat::InnerIterator it(A, j); it; ++it)
      if (local[size_t(it.row())] >= 0 && local[size_t(j)] >= 0)
        entries.emplace_back(local[size_t(it.row())], local[size_t(j)], it.value());
  SpMat K(np, np);
  K.setFromTriplets(entries.begin(), entries.end());
  return K;
}

Row choleskyOfK(const SpMat& K) {
  Row row{"CHOLMOD on K alone (no constraint rows: flexsens' Cholesky path)"};
  const double np = double(K.rows());
  flexsens::CholeskyFactor f;
  row.analyse = bestOf(1, [&] { f.symmetric(K); });
  row.factor = bestOf(3, [&] { f.factor(K); });
  row.fill = (2.0 * f.nnzL() - double(np)) / double(K.nonZeros());
  row.gflops = f.flops() / row.factor * 1e-9;
  Eigen::MatrixXd x = Eigen::MatrixXd::Ones(K.rows(), 1), b = x;
  row.solve = bestOf(3, [&] { x = b; f.solve(x); });
  row.berr = backwardError(K, x.col(0), b.col(0));
  return row;
}

// MUMPS sequential, sym = 2 (general symmetric: LDL^T with 1x1 and 2x2 pivots), the lower
// triangle; ordering ICNTL(7): 0 AMD, 5 METIS.
Row mumps(const SpMat& A, const Vec& b, int ordering, const std::string& name, int sym = 2) {
  Row row{name};
  DMUMPS_STRUC_C id{};
  id.comm_fortran = -987654;  // USE_COMM_WORLD (the sequential library's stub)
  id.par = 1;
  id.sym = sym;  // 2: general symmetric, 1: positive definite (LDL^T without pivoting)
  id.job = -1;
  dmumps_c(&id);
  id.icntl[0] = id.icntl[1] = id.icntl[2] = -1;
  id.icntl[3] = 0;
  id.icntl[6] = ordering;
  id.icntl[15] = 1;  // ICNTL(16): one OpenMP thread (the machine is shared; results reproducible)
  std::vector<int> irn, jcn;
  std::vector<double> a;
  for (Eigen::Index j = 0; j < A.outerSize(); ++j)
    for (SpMat::InnerIterator it(A, j); it; ++it)
      if (it.row() >= j) {
        irn.push_back(int(it.row() + 1));
        jcn.push_back(int(j + 1));
        a.push_back(it.value());
      }
  id.n = int(A.rows());
  id.nnz = int64_t(a.size());
  id.irn = irn.data();
  id.jcn = jcn.data();
  id.a = a.data();
  id.job = 1;
  row.analyse = bestOf(1, [&] { dmumps_c(&id); });
  id.job = 2;
  row.factor = bestOf(3, [&] {
    for (id.icntl[13] = 20; ; id.icntl[13] *= 4) {  // ICNTL(14): workspace margin [%], more on -8/-9
      dmumps_c(&id);
      if ((id.infog[0] != -8 && id.infog[0] != -9) || id.icntl[13] > 1000) break;
    }
  });
  if (id.infog[0] < 0) { std::fprintf(stderr, "MUMPS error %d\n", id.infog[0]); return row; }
  row.name += ", predicted " + std::to_string(int(id.rinfog[0] * 1e-6)) + " MFLOP";
  row.fill = (2.0 * double(id.infog[28]) - double(A.rows())) / double(A.nonZeros());  // INFOG(29): entries of L (and D)
  row.gflops = id.rinfog[2] / row.factor * 1e-9;  // RINFOG(3): flops of the elimination
  Vec x = b;
  id.job = 3;
  id.rhs = x.data();
  row.solve = bestOf(3, [&] { x = b; dmumps_c(&id); });
  row.berr = backwardError(A, x, b);
  id.job = -2;
  dmumps_c(&id);
  return row;
}

}  // namespace

// The table for one matrix with constraint rows (compare.cpp calls it).
void constrainedTable(const SpMat& A) {
  const Vec b = Vec::Ones(A.rows());
  flexsens::SchurFactor probe;
  const long m = long(probe.borderOf(A));
  const SpMat K = blockK(A);
  std::vector<Row> rows = {kluAsFlexsens(A, b), schur(A, b), mumps(A, b, 0, "**MUMPS LDL^T, AMD (flexsens now, from 10 MFLOP)**"),
                           mumps(A, b, 5, "MUMPS LDL^T, METIS"), choleskyOfK(K),
                           mumps(K, Vec::Ones(K.rows()), 0, "MUMPS LDL^T (SPD) on K alone, AMD", 1)};
  std::printf("| solver | fill | analyse [ms] | factor [ms] | solve [ms] | GFLOP/s | backward error |\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  for (const Row& r : rows)
    std::printf("| %s | %.2f | %.1f | %.1f | %.2f | %.2f | %.1e |\n", r.name.c_str(), r.fill, 1e3 * r.analyse,
                1e3 * r.factor, 1e3 * r.solve, r.gflops, r.berr);
  std::printf("n = %ld, m = %ld constraint rows, nnz(A) = %ld\n", long(A.rows()), m, long(A.nonZeros()));
}
