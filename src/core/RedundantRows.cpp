#include "core/RedundantRows.hpp"

#include <algorithm>

#include <Eigen/QR>
#include <Eigen/SparseQR>

#include "constraints/SelectedRows.hpp"
#include "core/Assembler.hpp"
#include "core/SparseAccumulator.hpp"

namespace flexsens {

DependentRows dependentRows(const Model& m, const VecX& q0, const VecX& p) {
  DependentRows d;
  if (m.m == 0) {
    d.checked = true;
    return d;
  }
  const Assembler as(m);
  if (static_cast<double>(m.n) * m.m * m.m <= kDenseRedundancyWork) {
    const MatX JT = as.phiQDense(q0, p).transpose();  // n x m: columns are constraint rows
    Eigen::ColPivHouseholderQR<MatX> qr(JT);
    qr.setThreshold(kRedundancyThreshold);
    d.rank = static_cast<int>(qr.rank());
    const auto& perm = qr.colsPermutation().indices();
    for (int k = d.rank; k < m.m; ++k) d.rows.push_back(perm[k]);
  } else {
    SparseAccumulator acc;
    acc.begin(m.n, m.m);
    as.addPhiQ(acc, q0, p, 1.0, 0, 0, true);  // Phi_q^T
    const Eigen::SparseMatrix<double> JT = acc.finish().cast<double>();
    double largest = 0.0;
    for (int j = 0; j < JT.outerSize(); ++j) largest = std::max(largest, JT.col(j).norm());
    Eigen::SparseQR<Eigen::SparseMatrix<double>, Eigen::COLAMDOrdering<int>> qr;
    qr.setPivotThreshold(kRedundancyThreshold * largest);
    qr.compute(JT);
    d.rank = static_cast<int>(qr.rank());
    const auto& perm = qr.colsPermutation().indices();
    for (int k = d.rank; k < m.m; ++k) d.rows.push_back(perm[k]);
  }
  std::sort(d.rows.begin(), d.rows.end());
  for (int r : d.rows) d.labels.push_back(as.rowLabel(r));
  d.checked = true;
  return d;
}

DependentRows leaveOutRedundantRows(Model& m) {
  const DependentRows d = dependentRows(m, m.initialPositions(), m.nominalParameters());
  if (d.rows.empty()) return d;
  std::vector<std::unique_ptr<Constraint>> kept;
  int row0 = 0;
  for (auto& c : m.constraints) {
    const int rows = c->rows();
    std::vector<int> keep;
    for (int i = 0; i < rows; ++i)
      if (!std::binary_search(d.rows.begin(), d.rows.end(), row0 + i)) keep.push_back(i);
    row0 += rows;
    if (static_cast<int>(keep.size()) == rows) kept.push_back(std::move(c));
    else if (!keep.empty()) kept.push_back(std::make_unique<SelectedRows>(std::move(c), keep));
    else m.leftOut.push_back(std::move(c));  // still evaluated by the monitor
  }
  m.constraints = std::move(kept);
  m.redundantRows = d.labels;
  m.finalize();
  return d;
}

}  // namespace flexsens

namespace flexsens {

double leftOutViolation(const Model& m, const Assembler& as, const VecX& q, const VecX& p) {
  double worst = 0.0;
  const VecX v = VecX::Zero(q.size());
  for (const auto& c : m.constraints)
    if (const auto* sel = dynamic_cast<const SelectedRows*>(c.get()))
      worst = std::max(worst, sel->leftOutViolation(as.localState(*sel, q, v, p)));
  VecX phi;
  for (const auto& c : m.leftOut) {
    c->phi(as.localState(*c, q, v, p), phi);
    worst = std::max(worst, phi.lpNorm<Eigen::Infinity>());
  }
  return worst;
}

}  // namespace flexsens
