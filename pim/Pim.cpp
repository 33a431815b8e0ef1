#include "pim/Pim.hpp"

#include <algorithm>
#include <limits>
#include <sstream>

#include "core/MemoryBudget.hpp"
#include "core/SparseAccumulator.hpp"
#include "core/SparseLU.hpp"
#include "pim/PimMatrix.hpp"
#include "integrators/InitialState.hpp"

namespace flexsens {

namespace {

/// Rows `rows` of the vector v.
VecX pick(const VecX& v, const std::vector<int>& rows) {
  VecX r(rows.size());
  for (size_t i = 0; i < rows.size(); ++i) r[i] = v[rows[i]];
  return r;
}

/// The massless coordinates' equilibrium in the PIM (Pim.hpp): coordinates mc, constraint
/// rows cr touching them, N (a x e) an orthonormal basis of the null space of Phi_Cm = Phi_q(cr,
/// mc), and, once load() ran, the rows N^T K(mc, :) / kappa of A, K = -Q_q + H(lambda).
struct MasslessRows {
  std::vector<int> mc, cr;
  MatX Jq;  ///< Phi_q (m x n)
  MatX N;
  MatX K;   ///< rows mc of K (a x n)
  MatX rows;
  double kappa = 1.0;
  int e() const { return static_cast<int>(N.cols()); }

  MasslessRows(const Assembler& as, const VecX& q, const VecX& p) : mc(masslessCoordinates(as, p)) {
    if (mc.empty()) return;
    // Massless coordinates take the dense path (Phi_q, K rows, the perturbed start's n x n
    // Gauss-Newton): refused before it is allocated when it exceeds the memory budget.
    const double n = as.n();
    requireMemory(doubles(4.0 * n * n), "the PIM with massless coordinates (dense n x n matrices, n = " +
                  std::to_string(as.n()) + ")", "give the massless coordinates a mass or coarsen the model");
    const int a = static_cast<int>(mc.size());
    Jq = as.m() ? as.phiQDense(q, p) : MatX(0, as.n());
    for (int r = 0; r < as.m(); ++r)
      for (int i : mc)
        if (Jq(r, i) != 0.0) {
          cr.push_back(r);
          break;
        }
    MatX Ct(a, cr.size());  // Phi_Cm^T
    for (int i = 0; i < a; ++i)
      for (size_t j = 0; j < cr.size(); ++j) Ct(i, j) = Jq(cr[j], mc[i]);
    int rank = 0;
    MatX Q = MatX::Identity(a, a);
    if (Ct.cols()) {
      Eigen::ColPivHouseholderQR<MatX> qr(Ct);
      qr.setThreshold(1e-10);
      rank = static_cast<int>(qr.rank());
      Q = qr.householderQ() * MatX::Identity(a, a);
    }
    N = Q.rightCols(a - rank);
  }
  /// K(mc, :) at (q, lambda) (v enters Q only through damping, which massless rows may not carry).
  void load(const Assembler& as, const VecX& q, const VecX& v, const VecX& lambda, const VecX& p) {
    if (mc.empty()) return;
    const int n = as.n();
    SparseAccumulator acc;
    acc.begin(n, n);
    as.addForceJacobian(acc, q, v, p, 1.0, 0.0, 0, 0, 0);
    if (as.m()) as.addHessian(acc, q, p, lambda, 1.0, 0, 0);
    const MatX Kf = MatX(acc.finish());
    K.resize(mc.size(), n);
    for (size_t i = 0; i < mc.size(); ++i) K.row(i) = Kf.row(mc[i]);
    double kMax = 0.0;
    for (size_t i = 0; i < mc.size(); ++i)
      for (int j : mc) kMax = std::max(kMax, std::abs(K(i, j)));
    kappa = kMax > 0.0 ? kMax : 1.0;
    rows = N.transpose() * K / kappa;
  }
  /// Rows mc of x.
  VecX pick(const VecX& x) const {
    VecX r(mc.size());
    for (size_t i = 0; i < mc.size(); ++i) r[i] = x[mc[i]];
    return r;
  }
  /// The equilibrium residual F_m = (Phi_q^T lambda - Q)_m at v = v.
  VecX residual(const Assembler& as, const VecX& q, const VecX& v, const VecX& lambda, const VecX& p) const {
    VecX F = -as.force(q, v, p);
    if (as.m()) F += as.phiQTransposeTimes(q, p, lambda);
    return pick(F);
  }
  /// A label for equilibrium row i: the massless coordinate with the largest entry of N's column.
  std::string label(const Model& m, int i) const {
    int j;
    N.col(i).cwiseAbs().maxCoeff(&j);
    return "massless equilibrium along " + m.coordinateLabel(mc[j]);
  }
};

/// A = [Phi_q; Lambda_q (kept rows); massless equilibrium rows; z_q] (sparse) and the labels of
/// its rows.
SpMat pimMatrix(const Assembler& as, const Assembler& lam, const std::vector<int>& kept, const PimCase& c,
                const MasslessRows& ml, const VecX& q, const VecX& p, std::vector<std::string>* labels) {
  const Model& m = as.model();
  const int mr = static_cast<int>(kept.size()), e = ml.e();
  std::vector<Eigen::Triplet<double, int64_t>> entries;
  auto addRows = [&](const SpMat& M, const std::vector<int>* rows, int offset) {
    std::vector<int> rowOf(M.rows(), -1);
    for (int i = 0; i < M.rows(); ++i) rowOf[i] = rows ? -1 : i;
    if (rows)
      for (size_t i = 0; i < rows->size(); ++i) rowOf[(*rows)[i]] = static_cast<int>(i);
    for (int k = 0; k < M.outerSize(); ++k)
      for (SpMat::InnerIterator it(M, k); it; ++it)
        if (rowOf[it.row()] >= 0) entries.emplace_back(offset + rowOf[it.row()], it.col(), it.value());
  };
  if (as.m()) addRows(as.phiQSparse(q, p), nullptr, 0);
  if (mr) addRows(lam.phiQSparse(q, p), &kept, as.m());
  for (int i = 0; i < e; ++i)
    for (int j = 0; j < m.n; ++j)
      if (ml.rows(i, j) != 0.0) entries.emplace_back(as.m() + mr + i, j, ml.rows(i, j));
  for (size_t i = 0; i < c.sdofs.size(); ++i) {
    const VecX g = c.sdofs[i]->gradient(m, q);
    for (int j = 0; j < m.n; ++j)
      if (g[j] != 0.0) entries.emplace_back(as.m() + mr + e + i, j, g[j]);
  }
  SpMat A(as.m() + mr + e + c.sdofs.size(), m.n);
  A.setFromTriplets(entries.begin(), entries.end());
  if (labels) {
    for (int r = 0; r < as.m(); ++r) labels->push_back("Phi: " + as.rowLabel(r));
    for (int r : kept) labels->push_back("Lambda: " + lam.rowLabel(r));
    for (int i = 0; i < e; ++i) labels->push_back(ml.label(m, i));
    for (const auto& z : c.sdofs) labels->push_back("SDOF: " + z->name);
  }
  return A;
}

void checkCount(const Assembler& as, const Assembler& lam, const LambdaSelection& sel, const MasslessRows& ml,
                const PimCase& c) {
  const int d = as.n() - as.m(), mr = static_cast<int>(sel.kept.size()), e = ml.e();
  const int ds = d - mr - e;
  if (static_cast<int>(c.sdofs.size()) != ds) {
    std::ostringstream os;
    os << c.file << ": case '" << c.name << "': " << c.sdofs.size() << " SDOF(s) given, but d - m_r"
       << (e ? " - e = " : " = ") << d << " - " << mr;
    if (e) os << " - " << e;
    os << " = " << ds << " are required (n = " << as.n() << ", m = " << as.m()
       << ", m_r = " << mr << " independent rigidization equations";
    if (!sel.dropped.empty())
      os << " of " << lam.m() << " generated; " << sel.dropped.size()
         << " are implied by the constraints and left out";
    if (e)
      os << ", e = " << e << " equilibrium equations of the " << ml.mc.size()
         << " massless coordinates (inertia: none), which fix them instead of SDOFs";
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

/// Rows `sel.dropped` of Lambda_q (sparse), for checking that the solution satisfies them.
SpMat droppedRows(const Assembler& lam, const LambdaSelection& sel, const VecX& q, const VecX& p) {
  SpMat Ld(sel.dropped.size(), lam.n());
  if (sel.dropped.empty()) return Ld;
  const SpMat L = lam.phiQSparse(q, p);
  std::vector<int> rowOf(L.rows(), -1);
  for (size_t i = 0; i < sel.dropped.size(); ++i) rowOf[sel.dropped[i]] = static_cast<int>(i);
  std::vector<Eigen::Triplet<double, int64_t>> entries;
  for (int k = 0; k < L.outerSize(); ++k)
    for (SpMat::InnerIterator it(L, k); it; ++it)
      if (rowOf[it.row()] >= 0) entries.emplace_back(rowOf[it.row()], it.col(), it.value());
  Ld.setFromTriplets(entries.begin(), entries.end());
  return Ld;
}

}  // namespace

PimReport pimCounts(const Assembler& as, const PimCase& c, const VecX& q, const VecX& p) {
  const Assembler lam(as.model(), &c.lambda, as.derivatives());
  const LambdaSelection sel = selectRigidizationRows(as, lam, q, p);
  PimReport r;
  r.n = as.n();
  r.m = as.m();
  r.d = r.n - r.m;
  r.mr = static_cast<int>(sel.kept.size());
  const MasslessRows ml(as, q, p);
  r.massless = static_cast<int>(ml.mc.size());
  r.me = ml.e();
  r.ds = r.d - r.mr - r.me;
  r.lambdaGenerated = lam.m();
  r.lambdaDropped = static_cast<int>(sel.dropped.size());
  return r;
}

namespace {

/// The rigidized bodies must be undeformed at t = 0 (InputError naming the worst row).
void requireUndeformed(const Assembler& lam, const PimCase& c, const VecX& q, const VecX& p) {
  if (!lam.m()) return;
  const VecX L = lam.phi(q, p);
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

/// The PIM linearizes the equilibrium of the massless coordinates at the start: it must hold
/// there (consistentState calls equilibrateMassless), in the directions N at least. Loads ml.
void requireMasslessEquilibrium(const Assembler& as, MasslessRows& ml, const PimCase& c, const State& s,
                                const VecX& p) {
  const VecX lambda = s.lambda.size() == as.m() ? s.lambda : VecX::Zero(as.m());
  ml.load(as, s.q, s.v, lambda, p);
  const double err = (ml.N.transpose() * ml.residual(as, s.q, s.v, lambda, p)).lpNorm<Eigen::Infinity>() / ml.kappa;
  if (!(err <= 1e-8 * (1.0 + s.q.lpNorm<Eigen::Infinity>()))) {
    std::ostringstream os;
    os << "case '" << c.name << "': the massless coordinates are not in equilibrium at the start (|N^T F_m| / k = "
       << err << " m); the PIM linearizes their equilibrium there (equilibrateMassless first)";
    throw NumericalError(os.str());
  }
}

/// A factorized with its condition estimate (PimMatrix.hpp), the errors in the case's words.
FactoredPimMatrix factoredPim(const SpMat& A, const std::vector<std::string>& labels, const MasslessRows& ml,
                              const PimCase& c) {
  const std::string what = "case '" + c.name + "': the PIM matrix A = [Phi_q; Lambda_q; " +
                           (ml.e() ? "N^T K_m / k; " : "") + "z_q]";
  return factorPimMatrix(A, labels, what, "Choose SDOFs that are independent of each other and of the constraints");
}

}  // namespace

StateWithSens pimInitialState(const Assembler& as, const PimCase& c, const State& s,
                              const VecX& p, PimReport& rep) {
  const Model& m = as.model();
  const Assembler lam(m, &c.lambda, as.derivatives());
  rep.n = m.n;
  rep.m = as.m();
  rep.d = m.n - as.m();
  rep.lambdaGenerated = lam.m();
  rep.ds = static_cast<int>(c.sdofs.size());
  requireUndeformed(lam, c, s.q, p);
  const LambdaSelection sel = selectRigidizationRows(as, lam, s.q, p);
  rep.mr = static_cast<int>(sel.kept.size());
  rep.lambdaDropped = static_cast<int>(sel.dropped.size());
  MasslessRows ml(as, s.q, p);
  rep.massless = static_cast<int>(ml.mc.size());
  rep.me = ml.e();
  checkCount(as, lam, sel, ml, c);
  if (!ml.mc.empty()) requireMasslessEquilibrium(as, ml, c, s, p);
  std::vector<std::string> labels;
  const SpMat A = pimMatrix(as, lam, sel.kept, c, ml, s.q, p, &labels);
  const FactoredPimMatrix factored = factoredPim(A, labels, ml, c);
  rep.condition = factored.condition;
  const SparseLU& lu = *factored.lu;
  const int np = static_cast<int>(p.size());
  const int mr = rep.mr, e = rep.me;
  const SpMat Ld = droppedRows(lam, sel, s.q, p);  // for the check below
  StateWithSens out;
  out.x = s;
  rep.qp.resize(m.n, np);
  rep.vp.resize(m.n, np);
  for (int k = 0; k < np; ++k) {
    VecX b(m.n);
    b.head(as.m()) = -as.phiParamDerivative(s.q, p, k);
    const VecX lamP = lam.m() ? lam.phiParamDerivative(s.q, p, k) : VecX();
    b.segment(as.m(), mr) = -pick(lamP, sel.kept);
    if (e) {  // N^T K_m. q_p = N^T (Q_p - Phi_qp^T lambda)_m, scaled by 1/kappa
      VecX g = as.forceParamDerivative(s.q, s.v, p, k);
      if (as.m()) g -= as.phiQParamDerivativeTransposeTimes(s.q, p, k, s.lambda);
      b.segment(as.m() + mr, e) = ml.N.transpose() * ml.pick(g) / ml.kappa;
    }
    for (size_t i = 0; i < c.sdofs.size(); ++i) b[as.m() + mr + e + i] = c.sdofs[i]->dp;
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
    if (e) b.segment(as.m() + mr, e).setZero();  // quasi-static rate at fixed K (Pim.hpp)
    for (size_t i = 0; i < c.sdofs.size(); ++i)
      b[as.m() + mr + e + i] = c.sdofs[i]->dv - d.q.dot(c.sdofs[i]->hessian(m, s.q) * s.v);
    d.v = lu.solve(b);
    if (!sel.dropped.empty()) {
      const VecX lv = pick(lamV, sel.dropped);
      const VecX scale = (Ld.cwiseAbs() * d.v.cwiseAbs()) + lv.cwiseAbs();
      const double global = (A.cwiseAbs() * d.v.cwiseAbs() + b.cwiseAbs()).maxCoeff();
      const double nonRigid = lam.phiQTimes(s.q, p, s.v).lpNorm<Eigen::Infinity>();
      checkDroppedRows(c, m, lam, sel, k, Ld * d.v + lv, scale, global, "velocity (q'_p0)",
                       nonRigid > 1e-10 * std::max(1.0, s.v.lpNorm<Eigen::Infinity>()) ? nonRigid : 0.0);
    }
    rep.qp.col(k) = d.q;
    rep.vp.col(k) = d.v;
    out.dp.push_back(d);
  }
  solveAccelerationSensitivities(as, s, p, out.dp);  // a_p, lambda_p of every parameter, one factorization
  return out;
}

VecX perturbedConfiguration(const Assembler& as, const PimCase& c, const VecX& q0,
                            const VecX& p0, const VecX& p, int k) {
  (void)k;  // p differs from p0 in parameter k only: the sum of the differences is p_k - p0_k
  return perturbedConfiguration(as, c, q0, p0, p);
}

VecX perturbedConfiguration(const Assembler& as, const PimCase& c, const VecX& q0,
                            const VecX& p0, const VecX& p) {
  const Model& m = as.model();
  const Assembler lam(m, &c.lambda, as.derivatives());
  const LambdaSelection sel = selectRigidizationRows(as, lam, q0, p0);
  MasslessRows ml(as, q0, p0);
  checkCount(as, lam, sel, ml, c);
  const int mr = static_cast<int>(sel.kept.size()), ns = static_cast<int>(c.sdofs.size());
  VecX target(ns);
  const double dpSum = (p - p0).sum();
  for (int i = 0; i < ns; ++i) target[i] = c.sdofs[i]->value(m, q0) + c.sdofs[i]->dp * dpSum;
  VecX q = q0;
  double previous = std::numeric_limits<double>::infinity();
  if (ml.mc.empty()) {
    for (int it = 0; it < 50; ++it) {
      VecX F(m.n);
      F.head(as.m()) = as.phi(q, p);
      if (mr) F.segment(as.m(), mr) = pick(lam.phi(q, p), sel.kept);
      for (int i = 0; i < ns; ++i) F[as.m() + mr + i] = c.sdofs[i]->value(m, q) - target[i];
      const double r = F.lpNorm<Eigen::Infinity>();
      if (r < 1e-14) return q;
      // Quadratic constraints on large coordinates (|r|^2 ~ 100 m^2) carry round-off above
      // 1e-14: stop once Newton stagnates there (the residual no longer decreases).
      if (r < 1e-11 && r >= previous) return q;
      previous = r;
      SparseLU lu;
      lu.factor(pimMatrix(as, lam, sel.kept, c, ml, q, p, nullptr), "PIM matrix A of case '" + c.name + "'");
      q -= lu.solve(F);
    }
  } else {
    // Unknowns q and the multipliers l of the rows cr; equations Phi, Lambda (kept), the full
    // equilibrium F_m / kappa0 (a rows, not projected: independent of the linear PIM's form) and
    // the SDOFs. With dependent rows in Phi_Cm the multipliers are not unique: least-norm
    // Gauss-Newton steps (complete orthogonal decomposition).
    const int n = m.n, a = static_cast<int>(ml.mc.size()), nc = static_cast<int>(ml.cr.size());
    const VecX v0 = VecX::Zero(n);
    VecX lambda = VecX::Zero(as.m());
    {  // nominal multipliers of the rows cr: least squares of Phi_Cm^T l = Q_m at q0
      MatX Ct(a, nc);
      for (int i = 0; i < a; ++i)
        for (int j = 0; j < nc; ++j) Ct(i, j) = ml.Jq(ml.cr[j], ml.mc[i]);
      const VecX l = Ct.completeOrthogonalDecomposition().solve(VecX(-ml.residual(as, q0, v0, lambda, p0)));
      for (int j = 0; j < nc; ++j) lambda[ml.cr[j]] = l[j];
    }
    ml.load(as, q0, v0, lambda, p0);
    const double kappa = ml.kappa;
    for (int it = 0; it < 50; ++it) {
      MasslessRows cur(as, q, p);
      cur.load(as, q, v0, lambda, p);
      const int rows = as.m() + mr + a + ns;
      VecX F(rows);
      MatX J = MatX::Zero(rows, n + nc);
      F.head(as.m()) = as.phi(q, p);
      J.topLeftCorner(as.m(), n) = cur.Jq;
      if (mr) {
        F.segment(as.m(), mr) = pick(lam.phi(q, p), sel.kept);
        const MatX L = lam.phiQDense(q, p);
        for (int i = 0; i < mr; ++i) J.block(as.m() + i, 0, 1, n) = L.row(sel.kept[i]);
      }
      F.segment(as.m() + mr, a) = cur.residual(as, q, v0, lambda, p) / kappa;
      J.block(as.m() + mr, 0, a, n) = cur.K / kappa;
      for (int i = 0; i < a; ++i)
        for (int j = 0; j < nc; ++j) J(as.m() + mr + i, n + j) = cur.Jq(ml.cr[j], ml.mc[i]) / kappa;
      for (int i = 0; i < ns; ++i) {
        F[as.m() + mr + a + i] = c.sdofs[i]->value(m, q) - target[i];
        J.block(as.m() + mr + a + i, 0, 1, n) = c.sdofs[i]->gradient(m, q).transpose();
      }
      const double r = F.lpNorm<Eigen::Infinity>();
      if (r < 1e-14) return q;
      if (r < 1e-11 && r >= previous) return q;
      previous = r;
      const VecX dz = J.completeOrthogonalDecomposition().solve(F);
      q -= dz.head(n);
      for (int j = 0; j < nc; ++j) lambda[ml.cr[j]] -= dz[n + j];
    }
  }
  throw NumericalError("case '" + c.name + "': the perturbed initial configuration did not converge");
}

}  // namespace flexsens
