#include "pim/Pim.hpp"

#include <algorithm>
#include <limits>
#include <sstream>

#include "integrators/InitialState.hpp"

namespace flexsens {

namespace {

/// Rows `rows` of the vector v.
VecX pick(const VecX& v, const std::vector<int>& rows) {
  VecX r(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) r[i] = v[rows[i]];
  return r;
}

/// A = [Phi_q; Lambda_q (kept rows); z_q] and the labels of its rows.
MatX pimMatrix(const Assembler& as, const Assembler& lam, const std::vector<int>& kept, const PimCase& c,
               const VecX& q, const VecX& p, std::vector<std::string>* labels) {
  const Model& m = as.model();
  const int mr = static_cast<int>(kept.size());
  MatX A(as.m() + mr + c.sdofs.size(), m.n);
  A.topRows(as.m()) = as.phiQDense(q, p);
  if (mr) {
    const MatX L = lam.phiQDense(q, p);
    for (int i = 0; i < mr; ++i) A.row(as.m() + i) = L.row(kept[i]);
  }
  for (size_t i = 0; i < c.sdofs.size(); ++i)
    A.row(as.m() + mr + i) = c.sdofs[i]->gradient(m, q).transpose();
  if (labels) {
    for (int r = 0; r < as.m(); ++r) labels->push_back("Phi: " + as.rowLabel(r));
    for (int r : kept) labels->push_back("Lambda: " + lam.rowLabel(r));
    for (const auto& z : c.sdofs) labels->push_back("SDOF: " + z->name);
  }
  return A;
}

void checkCount(const Assembler& as, const Assembler& lam, const LambdaSelection& sel, const PimCase& c) {
  const int d = as.n() - as.m(), mr = static_cast<int>(sel.kept.size());
  const int ds = d - mr;
  if (static_cast<int>(c.sdofs.size()) != ds) {
    std::ostringstream os;
    os << c.file << ": case '" << c.name << "': " << c.sdofs.size() << " SDOF(s) given, but d - m_r = "
       << d << " - " << mr << " = " << ds << " are required (n = " << as.n() << ", m = " << as.m()
       << ", m_r = " << mr << " independent rigidization equations";
    if (!sel.dropped.empty())
      os << " of " << lam.m() << " generated; " << sel.dropped.size()
         << " are implied by the constraints and left out";
    os << ")";
    if (ds < 0) os << "; the rigidized bodies over-constrain the mechanism: rigidize fewer bodies";
    throw InputError(os.str());
  }
}

/// Throws InputError if the rigidization rows left out of A are violated by the solution:
/// residual r (one entry per dropped row) against the sizes of the terms it sums.
void checkDroppedRows(const PimCase& c, const Model& m, const Assembler& lam, const LambdaSelection& sel,
                      int k, const VecX& r, const VecX& termScale, double globalScale, const char* level,
                      double nonRigidVelocity = 0.0) {
  std::ostringstream os;
  int bad = 0;
  for (size_t i = 0; i < sel.dropped.size(); ++i) {
    const double tol = 1e-8 * termScale[i] + 1e-11 * globalScale;
    if (std::abs(r[i]) <= tol) continue;
    if (bad < 3) os << (bad ? ", " : "") << "[" << lam.rowLabel(sel.dropped[i]) << "] residual " << r[i];
    ++bad;
  }
  if (!bad) return;
  std::ostringstream msg;
  msg << c.file << ": case '" << c.name << "': the rigidized bodies over-constrain the mechanism for parameter '"
      << m.parameters[k].name << "': " << bad << " rigidization equation(s) implied by the constraints at the "
      << "nominal configuration (left out of A) are violated by the " << level << " sensitivities: " << os.str()
      << (bad > 3 ? ", ..." : "") << "; the parameter changes a dimension the rigidized bodies fix: rigidize fewer bodies";
  if (nonRigidVelocity > 0)
    msg << " (or give the rigidized bodies a rigid initial velocity: their nominal velocities deform them, "
        << "|Lambda_q q'|_inf = " << nonRigidVelocity << ")";
  throw InputError(msg.str());
}

}  // namespace

LambdaSelection selectRigidizationRows(const Assembler& as, const Assembler& lam, const VecX& q, const VecX& p) {
  LambdaSelection sel;
  if (!lam.m()) return sel;
  const MatX L = lam.phiQDense(q, p);
  const double scale = L.rowwise().norm().maxCoeff();
  const double tol = 1e-10 * scale;
  // Project the rows onto the orthogonal complement of Phi_q's row space.
  MatX P = L;
  if (as.m()) {
    const MatX Jt = as.phiQDense(q, p).transpose();  // n x m
    Eigen::ColPivHouseholderQR<MatX> qr(Jt);
    qr.setThreshold(1e-12);
    const int r = static_cast<int>(qr.rank());
    if (r > 0) {
      const MatX Q = qr.householderQ() * MatX::Identity(Jt.rows(), r);
      P -= (P * Q) * Q.transpose();
    }
  }
  // Greedy in row order (earlier rows preferred): keep a row if it adds a direction to the
  // span of the rows kept so far (Gram-Schmidt, twice for orthogonality).
  MatX B(lam.n(), std::min(lam.m(), lam.n()));  // orthonormal basis of the kept rows
  int kept = 0;
  for (int i = 0; i < lam.m(); ++i) {
    VecX v = P.row(i).transpose();
    for (int pass = 0; pass < 2 && kept; ++pass) v -= B.leftCols(kept) * (B.leftCols(kept).transpose() * v);
    const double nv = v.norm();
    if (nv > tol && kept < B.cols()) {
      B.col(kept++) = v / nv;
      sel.kept.push_back(i);
    } else {
      sel.dropped.push_back(i);
    }
  }
  return sel;
}

PimReport pimCounts(const Assembler& as, const PimCase& c, const VecX& q, const VecX& p) {
  const Assembler lam(as.model(), &c.lambda, as.derivatives());
  const LambdaSelection sel = selectRigidizationRows(as, lam, q, p);
  PimReport r;
  r.n = as.n();
  r.m = as.m();
  r.d = r.n - r.m;
  r.mr = static_cast<int>(sel.kept.size());
  r.ds = r.d - r.mr;
  r.lambdaGenerated = lam.m();
  r.lambdaDropped = static_cast<int>(sel.dropped.size());
  return r;
}

StateWithSens pimInitialState(const Assembler& as, const PimCase& c, const State& s,
                              const VecX& p, PimReport& rep) {
  const Model& m = as.model();
  const Assembler lam(m, &c.lambda, as.derivatives());
  rep.n = m.n;
  rep.m = as.m();
  rep.d = m.n - as.m();
  rep.lambdaGenerated = lam.m();
  rep.ds = static_cast<int>(c.sdofs.size());
  if (lam.m()) {
    const VecX L = lam.phi(s.q, p);
    int worst;
    const double err = L.cwiseAbs().maxCoeff(&worst);
    if (err > 1e-8) {
      std::ostringstream os;
      os << c.file << ": case '" << c.name << "': a rigidized body is not undeformed at t = 0 ("
         << lam.rowLabel(worst) << " = " << err << "); the PIM rigidizes only initially "
         << "undeformed bodies: remove it from 'rigidize' or start it undeformed";
      throw InputError(os.str());
    }
  }
  const LambdaSelection sel = selectRigidizationRows(as, lam, s.q, p);
  rep.mr = static_cast<int>(sel.kept.size());
  rep.lambdaDropped = static_cast<int>(sel.dropped.size());
  checkCount(as, lam, sel, c);
  std::vector<std::string> labels;
  const MatX A = pimMatrix(as, lam, sel.kept, c, s.q, p, &labels);
  const Eigen::BDCSVD<MatX> svd(A, Eigen::ComputeFullU);
  const VecX sv = svd.singularValues();
  rep.condition = sv[0] / sv[sv.size() - 1];
  if (!(sv[sv.size() - 1] > 1e-12 * sv[0])) {
    // Rows taking part in the dependency: large entries of the left null vector.
    const VecX u = svd.matrixU().col(sv.size() - 1);
    std::ostringstream os;
    os << "case '" << c.name << "': the PIM matrix A = [Phi_q; Lambda_q; z_q] is rank-deficient "
       << "(smallest singular value " << sv[sv.size() - 1] << ", largest " << sv[0]
       << "); dependent rows:";
    for (int r = 0; r < u.size(); ++r)
      if (std::abs(u[r]) > 0.1 * u.cwiseAbs().maxCoeff()) os << " [" << labels[r] << "]";
    os << ". Choose SDOFs that are independent of each other and of the constraints";
    throw NumericalError(os.str());
  }
  if (rep.condition > 1e10) {
    std::ostringstream os;
    os << "case '" << c.name << "': the PIM matrix A is near-singular (condition estimate "
       << rep.condition << "); the SDOFs almost depend on each other or on the constraints";
    throw NumericalError(os.str());
  }
  const Eigen::PartialPivLU<MatX> lu(A);
  const int np = static_cast<int>(p.size());
  const int mr = rep.mr;
  MatX Ld(sel.dropped.size(), m.n);  // dropped rows of Lambda_q, for the check below
  if (!sel.dropped.empty()) {
    const MatX L = lam.phiQDense(s.q, p);
    for (size_t i = 0; i < sel.dropped.size(); ++i) Ld.row(i) = L.row(sel.dropped[i]);
  }
  StateWithSens out;
  out.x = s;
  rep.qp.resize(m.n, np);
  rep.vp.resize(m.n, np);
  for (int k = 0; k < np; ++k) {
    VecX b(m.n);
    b.head(as.m()) = -as.phiParamDerivative(s.q, p, k);
    const VecX lamP = lam.m() ? lam.phiParamDerivative(s.q, p, k) : VecX();
    b.segment(as.m(), mr) = -pick(lamP, sel.kept);
    for (size_t i = 0; i < c.sdofs.size(); ++i) b[as.m() + mr + i] = c.sdofs[i]->dp;
    State d;
    d.q = lu.solve(b);
    if (!sel.dropped.empty()) {
      const VecX lp = pick(lamP, sel.dropped);
      const VecX scale = (Ld.cwiseAbs() * d.q.cwiseAbs()) + lp.cwiseAbs();
      const double global = (A.cwiseAbs() * d.q.cwiseAbs() + b.cwiseAbs()).maxCoeff();
      checkDroppedRows(c, m, lam, sel, k, Ld * d.q + lp, scale, global, "position (q_p0)");
    }
    b.head(as.m()) = velocitySensitivityRhs(as, s.q, s.v, p, k, d.q);
    VecX lamV;
    if (lam.m()) {
      lamV = lam.hessianRowsTimes(s.q, p, s.v, d.q) + lam.phiQParamDerivativeTimes(s.q, p, k, s.v);
      b.segment(as.m(), mr) = -pick(lamV, sel.kept);
    }
    for (size_t i = 0; i < c.sdofs.size(); ++i)
      b[as.m() + mr + i] = c.sdofs[i]->dv - d.q.dot(c.sdofs[i]->hessian(m, s.q) * s.v);
    d.v = lu.solve(b);
    if (!sel.dropped.empty()) {
      const VecX lv = pick(lamV, sel.dropped);
      const VecX scale = (Ld.cwiseAbs() * d.v.cwiseAbs()) + lv.cwiseAbs();
      const double global = (A.cwiseAbs() * d.v.cwiseAbs() + b.cwiseAbs()).maxCoeff();
      const double nonRigid = (lam.phiQDense(s.q, p) * s.v).lpNorm<Eigen::Infinity>();
      checkDroppedRows(c, m, lam, sel, k, Ld * d.v + lv, scale, global, "velocity (q'_p0)",
                       nonRigid > 1e-10 * std::max(1.0, s.v.lpNorm<Eigen::Infinity>()) ? nonRigid : 0.0);
    }
    solveAccelerationSensitivity(as, s, p, k, d);
    rep.qp.col(k) = d.q;
    rep.vp.col(k) = d.v;
    out.dp.push_back(d);
  }
  return out;
}

VecX perturbedConfiguration(const Assembler& as, const PimCase& c, const VecX& q0,
                            const VecX& p0, const VecX& p, int k) {
  const Model& m = as.model();
  const Assembler lam(m, &c.lambda, as.derivatives());
  const LambdaSelection sel = selectRigidizationRows(as, lam, q0, p0);
  checkCount(as, lam, sel, c);
  const int mr = static_cast<int>(sel.kept.size());
  VecX target(c.sdofs.size());
  for (size_t i = 0; i < c.sdofs.size(); ++i)
    target[i] = c.sdofs[i]->value(m, q0) + c.sdofs[i]->dp * (p[k] - p0[k]);
  VecX q = q0;
  double previous = std::numeric_limits<double>::infinity();
  for (int it = 0; it < 50; ++it) {
    VecX F(m.n);
    F.head(as.m()) = as.phi(q, p);
    if (mr) F.segment(as.m(), mr) = pick(lam.phi(q, p), sel.kept);
    for (size_t i = 0; i < c.sdofs.size(); ++i) F[as.m() + mr + i] = c.sdofs[i]->value(m, q) - target[i];
    const double r = F.lpNorm<Eigen::Infinity>();
    if (r < 1e-14) return q;
    // Quadratic constraints on large coordinates (|r|^2 ~ 100 m^2) carry round-off above
    // 1e-14: stop once Newton stagnates there (the residual no longer decreases).
    if (r < 1e-11 && r >= previous) return q;
    previous = r;
    q -= pimMatrix(as, lam, sel.kept, c, q, p, nullptr).partialPivLu().solve(F);
  }
  throw NumericalError("case '" + c.name + "': the perturbed initial configuration did not converge");
}

}  // namespace flexsens
