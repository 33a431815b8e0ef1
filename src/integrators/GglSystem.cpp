#include "integrators/GglSystem.hpp"

#include <algorithm>

namespace flexsens {

std::vector<int> gglPinnedRows(const Assembler& as, const std::vector<int>& massless) {
  if (massless.empty() || as.m() == 0) return {};
  std::vector<char> isMassless(as.n(), 0);
  for (int i : massless) isMassless[i] = 1;
  std::vector<int> rows;
  for (size_t c = 0; c < as.constraints().size(); ++c) {
    bool touches = false;
    for (int i : as.constraintDofs(c)) touches = touches || (i >= 0 && isMassless[i]);
    if (!touches) continue;
    for (int r = 0; r < as.constraints()[c]->rows(); ++r) rows.push_back(as.constraintRow(c) + r);
  }
  std::sort(rows.begin(), rows.end());
  return rows;
}

VecX gglResidual(const Assembler& as, const VecX& p, const SpMat& M, const VecX& y, const VecX& yp,
                 const std::vector<int>& pinned) {
  const int n = as.n(), m = as.m();
  const VecX q = y.segment(0, n), v = y.segment(n, n);
  const VecX lam = y.segment(2 * n, m), mu = y.segment(2 * n + m, m);
  VecX r(2 * (n + m));
  r.segment(0, n) = yp.segment(0, n) - v + as.phiQTransposeTimes(q, p, mu);
  r.segment(n, n) = M * yp.segment(n, n) + as.phiQTransposeTimes(q, p, lam) - as.force(q, v, p);
  if (m) {
    r.segment(2 * n, m) = as.phi(q, p);
    r.segment(2 * n + m, m) = as.phiQTimes(q, p, v) + as.phiT(q, p);  // d Phi/dt = 0 (drivers: Phi_t)
    for (int row : pinned) r[2 * n + m + row] = mu[row];
  }
  return r;
}

const SpMat& gglJacobian(const Assembler& as, const VecX& p, const VecX& y, double cj,
                         SparseAccumulator& acc, const std::vector<int>& pinned) {
  const int n = as.n(), m = as.m();
  const VecX q = y.segment(0, n), v = y.segment(n, n);
  const VecX lam = y.segment(2 * n, m), mu = y.segment(2 * n + m, m);
  acc.begin(2 * (n + m), 2 * (n + m));
  for (int i = 0; i < n; ++i) {  // q rows: cj I + H(mu), -I, Phi_q^T (mu)
    acc.add(i, i, cj);
    acc.add(i, n + i, -1.0);
  }
  as.addHessian(acc, q, p, mu, 1.0, 0, 0);
  as.addPhiQ(acc, q, p, 1.0, 0, 2 * n + m, true);
  // v rows: H(lambda) - Q_q, cj M - Q_v, Phi_q^T (lambda)
  as.addHessian(acc, q, p, lam, 1.0, n, 0);
  as.addForceJacobian(acc, q, v, p, 1.0, 1.0, n, 0, n);
  as.addMass(acc, p, cj, n, n);
  as.addPhiQ(acc, q, p, 1.0, n, 2 * n, true);
  // Phi rows: Phi_q; Phi_q v rows: d(Phi_q v)/dq, Phi_q
  as.addPhiQ(acc, q, p, 1.0, 2 * n, 0, false);
  as.addHessianRows(acc, q, p, v, 1.0, 2 * n + m, 0);
  as.addPhiQT(acc, q, p, 1.0, 2 * n + m, 0);
  as.addPhiQ(acc, q, p, 1.0, 2 * n + m, n, false);
  std::vector<int> pinnedRows;
  for (int row : pinned) {
    acc.add(2 * n + m + row, 2 * n + m + row, 0.0);
    pinnedRows.push_back(2 * n + m + row);
  }
  acc.finish();
  acc.setRowsToIdentity(pinnedRows);
  return acc.matrix();
}

void gglForceJacobians(const Assembler& as, const VecX& p, const VecX& y, SparseAccumulator& kq,
                       SparseAccumulator& kv) {
  const int n = as.n();
  const VecX q = y.segment(0, n), v = y.segment(n, n);
  kq.begin(n, n);
  kv.begin(n, n);
  as.addForceJacobians(kq, kv, q, v, p);
  kq.finish();
  kv.finish();
}

VecX gglSensitivityResidual(const Assembler& as, const VecX& p, const SpMat& M, const VecX& y,
                            const VecX& yp, int k, const VecX& s, const VecX& sd,
                            const std::vector<int>& pinned) {
  SparseAccumulator kq, kv;
  gglForceJacobians(as, p, y, kq, kv);
  return gglSensitivityResidual(as, p, M, y, yp, k, s, sd, kq.matrix(), kv.matrix(), pinned);
}

VecX gglSensitivityResidual(const Assembler& as, const VecX& p, const SpMat& M, const VecX& y,
                            const VecX& yp, int k, const VecX& s, const VecX& sd, const SpMat& Qq,
                            const SpMat& Qv, const std::vector<int>& pinned) {
  const int n = as.n(), m = as.m();
  const VecX q = y.segment(0, n), v = y.segment(n, n);
  const VecX lam = y.segment(2 * n, m), mu = y.segment(2 * n + m, m);
  const VecX sq = s.segment(0, n), sv = s.segment(n, n);
  const VecX sl = s.segment(2 * n, m), sm = s.segment(2 * n + m, m);
  VecX r(2 * (n + m));
  r.segment(0, n) = sd.segment(0, n) - sv + as.phiQTransposeTimes(q, p, sm) +
                    as.hessianTimes(q, p, mu, sq) + as.phiQParamDerivativeTransposeTimes(q, p, k, mu);
  r.segment(n, n) = M * sd.segment(n, n) + as.massParamDerivativeTimes(p, k, yp.segment(n, n)) +
                    as.phiQTransposeTimes(q, p, sl) + as.hessianTimes(q, p, lam, sq) +
                    as.phiQParamDerivativeTransposeTimes(q, p, k, lam) - Qq * sq -
                    Qv * sv - as.forceParamDerivative(q, v, p, k);
  if (m) {
    r.segment(2 * n, m) = as.phiQTimes(q, p, sq) + as.phiParamDerivative(q, p, k);
    r.segment(2 * n + m, m) = as.phiQTimes(q, p, sv) + as.hessianRowsTimes(q, p, v, sq) +
                              as.phiQParamDerivativeTimes(q, p, k, v) + as.phiQTTimes(q, p, sq) +
                              as.phiTParamDerivative(q, p, k);
    for (int row : pinned) r[2 * n + m + row] = sm[row];
  }
  return r;
}

}  // namespace flexsens
