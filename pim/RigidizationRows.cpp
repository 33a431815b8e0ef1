// Which rigidization rows enter the PIM matrix (selectRigidizationRows, Pim.hpp), without dense
// n x n work. The generator (Rigidization.hpp) gives every non-basic point of a body its own
// rows, each with a unit entry on a coordinate of that point that no other rigidization row
// touches. When no constraint row touches that coordinate either, nothing else can cancel it:
// the row is independent of all others and kept, as the greedy choice would keep it, and it
// plays no part in any other row's choice. The greedy choice of Pim.hpp (Phi's rows first, then
// the rigidization rows in order, a row kept when it adds a direction) runs densely on the rest
// only: the basic points' rows, points held by ground nodes, points a joint touches.
#include <algorithm>
#include <sstream>

#include "core/MemoryBudget.hpp"
#include "pim/Pim.hpp"

namespace flexsens {

namespace {

using RowMajor = Eigen::SparseMatrix<double, Eigen::RowMajor, int64_t>;

/// Per row of L, whether it has an entry on a coordinate that no other row of L or J touches:
/// nothing can cancel that entry, so the row is independent of all others and takes no part in
/// their choice. The entry must not be small against the row's largest (a round-off entry
/// would not make the row independent in floating point).
std::vector<bool> ownsACoordinate(const RowMajor& J, const RowMajor& L) {
  std::vector<int> rowsTouching(L.cols(), 0);
  for (const RowMajor* M : {&J, &L})
    for (int r = 0; r < M->rows(); ++r)
      for (RowMajor::InnerIterator it(*M, r); it; ++it)
        if (it.value() != 0.0) ++rowsTouching[it.col()];
  std::vector<bool> owns(L.rows(), false);
  for (int r = 0; r < L.rows(); ++r) {
    double rowMax = 0.0;
    for (RowMajor::InnerIterator it(L, r); it; ++it) rowMax = std::max(rowMax, std::abs(it.value()));
    for (RowMajor::InnerIterator it(L, r); it; ++it)
      if (rowsTouching[it.col()] == 1 && std::abs(it.value()) >= 1e-3 * rowMax) owns[r] = true;
  }
  return owns;
}

/// The rows the greedy choice must look at, densely on the columns they touch: Phi's rows, then
/// the rigidization rows that own no coordinate (those can be implied by the others), in order.
struct ReducedRows {
  MatX phi;                   ///< Phi_q's rows
  MatX lambda;                ///< the rigidization rows in question
  std::vector<int> lambdaRow; ///< their row numbers in L
};

ReducedRows reduce(const RowMajor& J, const RowMajor& L, const std::vector<bool>& owns) {
  const int n = static_cast<int>(L.cols());
  ReducedRows red;
  for (int r = 0; r < L.rows(); ++r)
    if (!owns[r]) red.lambdaRow.push_back(r);
  std::vector<int> columnOf(n, -1);
  int columns = 0;
  auto touchAll = [&](const RowMajor& M, int r) {
    for (RowMajor::InnerIterator it(M, r); it; ++it)
      if (columnOf[it.col()] < 0) columnOf[it.col()] = columns++;
  };
  for (int r = 0; r < J.rows(); ++r) touchAll(J, r);
  for (int r : red.lambdaRow) touchAll(L, r);
  std::ostringstream what;
  what << "the rigidization rows' selection (" << J.rows() + red.lambdaRow.size() << " rows x " << columns
       << " coordinates)";
  requireMemory(doubles(3.0 * double(J.rows() + red.lambdaRow.size()) * columns), what.str(),
                "rigidize fewer bodies or constrain fewer of their nodes");
  auto dense = [&](const RowMajor& M, const std::vector<int>& rows) {
    MatX D = MatX::Zero(rows.size(), columns);
    for (size_t i = 0; i < rows.size(); ++i)
      for (RowMajor::InnerIterator it(M, rows[i]); it; ++it) D(i, columnOf[it.col()]) = it.value();
    return D;
  };
  std::vector<int> allJ(J.rows());
  for (int r = 0; r < J.rows(); ++r) allJ[r] = r;
  red.phi = dense(J, allJ);
  red.lambda = dense(L, red.lambdaRow);
  return red;
}

/// The greedy choice on the reduced rows: project onto the complement of the constraint rows'
/// span, then keep a row if it adds a direction to the rows kept so far (Gram-Schmidt twice).
/// Returns, per reduced rigidization row, whether it is kept.
std::vector<bool> greedyKeep(const ReducedRows& red, double tol) {
  MatX P = red.lambda;
  if (red.phi.rows() && P.rows()) {
    const MatX Jt = red.phi.transpose();
    Eigen::ColPivHouseholderQR<MatX> qr(Jt);
    qr.setThreshold(1e-12);
    const int r = static_cast<int>(qr.rank());
    if (r > 0) {
      const MatX Q = qr.householderQ() * MatX::Identity(Jt.rows(), r);
      P -= (P * Q) * Q.transpose();
    }
  }
  std::vector<bool> keep(P.rows(), false);
  MatX B(P.cols(), std::min(P.rows(), P.cols()));  // orthonormal basis of the kept rows
  int kept = 0;
  for (int i = 0; i < P.rows(); ++i) {
    VecX v = P.row(i).transpose();
    for (int pass = 0; pass < 2 && kept; ++pass) v -= B.leftCols(kept) * (B.leftCols(kept).transpose() * v);
    const double nv = v.norm();
    if (nv > tol && kept < B.cols()) {
      B.col(kept++) = v / nv;
      keep[i] = true;
    }
  }
  return keep;
}

}  // namespace

LambdaSelection selectRigidizationRows(const Assembler& as, const Assembler& lam, const VecX& q, const VecX& p) {
  LambdaSelection sel;
  if (!lam.m()) return sel;
  const RowMajor L = lam.phiQSparse(q, p);
  const RowMajor J = as.m() ? RowMajor(as.phiQSparse(q, p)) : RowMajor(0, L.cols());
  double scale = 0.0;
  for (int r = 0; r < L.rows(); ++r) scale = std::max(scale, L.row(r).norm());
  const ReducedRows red = reduce(J, L, ownsACoordinate(J, L));
  const std::vector<bool> keep = greedyKeep(red, 1e-10 * scale);
  std::vector<bool> kept(L.rows(), true);
  for (size_t i = 0; i < red.lambdaRow.size(); ++i) kept[red.lambdaRow[i]] = keep[i];
  for (int r = 0; r < L.rows(); ++r) (kept[r] ? sel.kept : sel.dropped).push_back(r);
  return sel;
}

}  // namespace flexsens
