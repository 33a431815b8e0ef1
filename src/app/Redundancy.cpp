#include "app/Redundancy.hpp"

#include <Eigen/QR>

namespace flexsens {

RedundancyReport constraintRedundancy(const Assembler& as, const VecX& q, const VecX& p) {
  RedundancyReport r;
  r.rows = as.m();
  if (r.rows == 0) {
    r.checked = true;
    return r;
  }
  if (static_cast<double>(as.n()) * r.rows > kMaxRedundancyEntries) return r;
  const MatX JT = as.phiQDense(q, p).transpose();  // n x m: columns are constraint rows
  Eigen::ColPivHouseholderQR<MatX> qr(JT);
  // A row is dependent when its pivot is below 1e-10 of the largest: far above round-off of
  // O(1) entries (1e-16) and far below any physical independence (a 1e-10 rad offset).
  r.tolerance = 1e-10;
  qr.setThreshold(r.tolerance);
  r.rank = static_cast<int>(qr.rank());
  const auto& perm = qr.colsPermutation().indices();
  for (int k = r.rank; k < r.rows; ++k) r.dependent.push_back(as.rowLabel(perm[k]));
  r.checked = true;
  return r;
}

}  // namespace flexsens
