#include "integrators/InitialState.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/SparseLU.hpp"

namespace flexsens {

LeastNorm::LeastNorm(const Assembler& as, const VecX& q, const VecX& p) : n_(as.n()), m_(as.m()) {
  SparseAccumulator acc;
  acc.begin(n_ + m_, n_ + m_);
  for (int i = 0; i < n_; ++i) acc.add(i, i, 1.0);
  as.addPhiQ(acc, q, p, 1.0, 0, n_, true);
  as.addPhiQ(acc, q, p, 1.0, n_, 0, false);
  A_ = acc.finish();
  try {
    lu_ = std::make_unique<SparseLU>();
    lu_->factor(A_, "least-norm projection matrix [I Phi_q^T; Phi_q 0]");
  } catch (const NumericalError&) {
    lu_.reset();
    denseJ_ = as.phiQDense(q, p);
  }
}

VecX LeastNorm::solve(const VecX& r) const {
  if (!lu_) return denseJ_.completeOrthogonalDecomposition().solve(r);
  VecX b = VecX::Zero(n_ + m_);
  b.tail(m_) = r;
  VecX x = lu_->solve(b);
  x += lu_->solve(VecX(b - A_ * x));  // one step of iterative refinement
  return x.head(n_);
}

VecX projectPositions(const Assembler& as, VecX q, const VecX& p, double tol) {
  if (as.m() == 0) return q;
  double err = 0.0;
  for (int it = 0; it < 50; ++it) {
    const VecX r = as.phi(q, p);
    err = r.lpNorm<Eigen::Infinity>();
    if (err <= tol) return q;
    q -= LeastNorm(as, q, p).solve(r);  // dq = -J^T (J J^T)^+ r
  }
  std::ostringstream os;
  os << "the initial positions could not be brought onto the constraints: |Phi|_inf = " << err
     << " after 50 Gauss-Newton iterations; check that the scene's node positions and "
        "constraint lengths are compatible";
  throw NumericalError(os.str());
}

VecX projectVelocities(const Assembler& as, const VecX& q, const VecX& v, const VecX& p) {
  if (as.m() == 0) return v;
  return v - LeastNorm(as, q, p).solve(VecX(as.phiQTimes(q, p, v) + as.phiT(q, p)));
}

VecX velocitySensitivityRhs(const Assembler& as, const VecX& q, const VecX& v, const VecX& p, int k,
                            const VecX& dq) {
  return -(as.hessianRowsTimes(q, p, v, dq) + as.phiQParamDerivativeTimes(q, p, k, v) +
           as.phiQTTimes(q, p, dq) + as.phiTParamDerivative(q, p, k));
}

SpMat augmentedMatrix(const Assembler& as, const VecX& q, const VecX& p) {
  SparseAccumulator acc;
  acc.begin(as.n() + as.m(), as.n() + as.m());
  as.addMass(acc, p, 1.0, 0, 0);
  as.addPhiQ(acc, q, p, 1.0, 0, as.n(), true);
  as.addPhiQ(acc, q, p, 1.0, as.n(), 0, false);
  return acc.finish();
}

namespace {
SparseLU& factorAugmented(const Assembler& as, const VecX& q, const VecX& p, double t) {
  thread_local SparseLU lu;
  std::ostringstream what;
  what << "augmented matrix [M Phi_q^T; Phi_q 0] at t = " << t
       << " s (redundant constraints, or a coordinate without mass)";
  lu.factor(augmentedMatrix(as, q, p), what.str());
  return lu;
}

/// Solves [M Phi_q^T; Phi_q 0] x = rhs. With massless coordinates the matrix is singular in
/// their accelerations (the equilibrium rows carry none): least-norm solution by a dense
/// complete orthogonal decomposition; a_m is then not the quasi-static acceleration, which no
/// integrator reads (M a has no massless rows; IDAS treats them as algebraic).
VecX solveAugmented(const Assembler& as, const VecX& q, const VecX& p, double t, const VecX& rhs) {
  try {
    return factorAugmented(as, q, p, t).solve(rhs);
  } catch (const NumericalError&) {
    if (masslessCoordinates(as, p).empty()) throw;
  }
  const MatX A = MatX(augmentedMatrix(as, q, p));
  const auto cod = A.completeOrthogonalDecomposition();
  const VecX x = cod.solve(rhs);
  const double res = (A * x - rhs).lpNorm<Eigen::Infinity>();
  if (!(res <= 1e-8 * (1.0 + rhs.lpNorm<Eigen::Infinity>()))) {
    std::ostringstream os;
    os << "augmented matrix [M Phi_q^T; Phi_q 0] at t = " << t << " s: the system with massless "
          "coordinates has no solution (residual " << res << "; are the massless parts in equilibrium?)";
    throw NumericalError(os.str());
  }
  return x;
}
}  // namespace

std::vector<int> masslessCoordinates(const Assembler& as, const VecX& p) {
  // Only nodes of declared-massless parts (an element whose mass matrix is there but zero:
  // beam `inertia: none`). Other zero rows of M (a rigid body's attached points) are fixed by
  // constraints and keep their usual treatment.
  std::vector<char> ofMasslessPart(as.n(), 0);
  bool any = false;
  const std::vector<MatX>& masses = as.elementMasses(p);  // empty: the element has no mass matrix
  for (size_t e = 0; e < masses.size(); ++e) {
    if (masses[e].size() == 0 || !masses[e].isZero(0.0)) continue;
    any = true;
    for (int i : as.elementDofs(e))
      if (i >= 0) ofMasslessPart[i] = 1;
  }
  if (!any) return {};
  const SpMat M = as.mass(p);
  VecX rowAbs = VecX::Zero(as.n());
  for (int c = 0; c < M.outerSize(); ++c)
    for (SpMat::InnerIterator it(M, c); it; ++it) rowAbs[it.row()] += std::abs(it.value());
  std::vector<int> r;
  for (int i = 0; i < as.n(); ++i)
    if (rowAbs[i] == 0.0 && ofMasslessPart[i]) r.push_back(i);
  return r;
}

namespace {

/// The massless subproblem at (q, lambda): coordinates mc, constraint rows cr touching them,
/// its Jacobian J = [K_mm  k Phi_Cm^T; k Phi_Cm  0] and the full K = -dQ/dq + H(lambda), Phi_q.
/// The constraint rows and columns are scaled by k = max |K_mm| [N/m] so that the pivots of
/// both blocks are of one size (unscaled, J K^-1 J^T ~ 1/k looks singular to a pivot threshold).
struct MasslessBlock {
  std::vector<int> mc, cr;
  MatX K, Jq, J;
  double kappa = 1.0;
  MasslessBlock(const Assembler& as, const VecX& q, const VecX& v, const VecX& lambda, const VecX& p,
                std::vector<int> massless) : mc(std::move(massless)) {
    const int n = as.n(), m = as.m();
    SparseAccumulator acc;
    acc.begin(n, n);
    as.addForceJacobian(acc, q, v, p, 1.0, 0.0, 0, 0, 0);
    if (m) as.addHessian(acc, q, p, lambda, 1.0, 0, 0);
    K = MatX(acc.finish());
    Jq = m ? as.phiQDense(q, p) : MatX(0, n);
    for (int r = 0; r < m; ++r)
      for (int i : mc)
        if (Jq(r, i) != 0.0) {
          cr.push_back(r);
          break;
        }
    const int a = static_cast<int>(mc.size()), b = static_cast<int>(cr.size());
    J = MatX::Zero(a + b, a + b);
    for (int i = 0; i < a; ++i)
      for (int j = 0; j < a; ++j) J(i, j) = K(mc[i], mc[j]);
    const double kMax = a ? J.topLeftCorner(a, a).cwiseAbs().maxCoeff() : 0.0;
    kappa = kMax > 0.0 ? kMax : 1.0;
    for (int i = 0; i < a; ++i)
      for (int j = 0; j < b; ++j) J(i, a + j) = J(a + j, i) = kappa * Jq(cr[j], mc[i]);
  }
  /// Rows mc of x (full) and rows cr of y (constraints, scaled by kappa), stacked.
  VecX stack(const VecX& x, const VecX& y) const {
    VecX r(mc.size() + cr.size());
    for (size_t i = 0; i < mc.size(); ++i) r[i] = x[mc[i]];
    for (size_t j = 0; j < cr.size(); ++j) r[mc.size() + j] = kappa * y[cr[j]];
    return r;
  }
  /// x with its massless entries set to zero.
  VecX others(VecX x) const {
    for (int i : mc) x[i] = 0.0;
    return x;
  }
  /// Solves J z = rhs. A null vector of J with a part in q_m is a massless direction without
  /// stiffness (named); one in the multipliers only (more constraint rows than the massless
  /// coordinates need, e.g. a spring's end on a rigid body's attached point) leaves those
  /// multipliers to the acceleration solve: least-norm solution.
  VecX solve(const Assembler& as, const VecX& rhs) const {
    Eigen::FullPivLU<MatX> lu(J);
    lu.setThreshold(1e-10);
    if (lu.isInvertible()) return lu.solve(rhs);
    const MatX ker = lu.kernel();
    const int a = static_cast<int>(mc.size());
    int worst = 0;
    for (int c = 1; c < ker.cols(); ++c)
      if (ker.col(c).head(a).norm() > ker.col(worst).head(a).norm()) worst = c;
    if (ker.col(worst).head(a).norm() > 1e-8 * ker.col(worst).norm()) {
      const VecX z = ker.col(worst);
      std::vector<int> idx;
      for (size_t i = 0; i < mc.size(); ++i) idx.push_back(static_cast<int>(i));
      std::sort(idx.begin(), idx.end(), [&](int x, int y) { return std::abs(z[x]) > std::abs(z[y]); });
      std::string names;
      for (size_t k = 0; k < idx.size() && k < 4 && std::abs(z[idx[k]]) > 0.1 * std::abs(z[idx[0]]); ++k)
        names += (k ? ", " : "") + as.model().coordinateLabel(mc[idx[k]]);
      throw NumericalError("massless coordinates without stiffness: " + names +
                           " carry no mass (inertia: none) and nothing restrains them in that direction; "
                           "give them mass, stiffness (e.g. a bending stiffness) or a constraint");
    }
    return J.completeOrthogonalDecomposition().solve(rhs);
  }
};

}  // namespace

MasslessStability masslessStability(const Assembler& as, const State& s, const VecX& p,
                                    const std::vector<int>& massless) {
  MasslessStability r;
  if (massless.empty()) return r;
  const VecX lambda = s.lambda.size() == as.m() ? s.lambda : VecX(VecX::Zero(as.m()));
  const MasslessBlock b(as, s.q, s.v, lambda, p, massless);
  const int a = static_cast<int>(b.mc.size());
  MatX Kmm = b.J.topLeftCorner(a, a);
  MatX Z = MatX::Identity(a, a);
  if (!b.cr.empty()) {
    MatX C(b.cr.size(), a);
    for (size_t j = 0; j < b.cr.size(); ++j)
      for (int i = 0; i < a; ++i) C(j, i) = b.Jq(b.cr[j], b.mc[i]);
    Eigen::FullPivLU<MatX> lu(C);
    lu.setThreshold(1e-10);
    Z = lu.kernel();
    if (lu.rank() == a) return r;  // the constraints fix every massless coordinate
    Z = Z.householderQr().householderQ() * MatX::Identity(a, Z.cols());  // orthonormal basis
  }
  const MatX Kr = Z.transpose() * (0.5 * (Kmm + Kmm.transpose())) * Z;
  const Eigen::SelfAdjointEigenSolver<MatX> es(Kr);
  r.minEigenvalue = es.eigenvalues()[0];
  r.maxEigenvalue = es.eigenvalues()[Kr.rows() - 1];
  const VecX soft = Z * es.eigenvectors().col(0);
  Eigen::Index i = 0;
  soft.cwiseAbs().maxCoeff(&i);
  r.coordinate = as.model().coordinateLabel(b.mc[i]);
  return r;
}

void equilibrateMassless(const Assembler& as, State& s, const VecX& p) {
  const std::vector<int> mc = masslessCoordinates(as, p);
  if (mc.empty()) return;
  const int n = as.n(), m = as.m();
  if (s.lambda.size() != m) s.lambda = VecX::Zero(m);
  if (s.v.size() != n) s.v = VecX::Zero(n);
  {  // a damping force on a massless coordinate would make it a first-order ODE, not algebraic
    SparseAccumulator acc;
    acc.begin(n, n);
    as.addForceJacobian(acc, s.q, s.v, p, 0.0, 1.0, 0, 0, 0);
    const MatX C = MatX(acc.finish());
    for (int i : mc)
      if (C.row(i).lpNorm<Eigen::Infinity>() != 0.0)
        throw InputError("coordinate " + as.model().coordinateLabel(i) + " is massless (inertia: none) "
                         "but carries a damping force (e.g. a spring_damper with damping): not supported; "
                         "give the node mass or remove the damping");
  }
  double err = 0.0;
  for (int it = 0; it < 50; ++it) {
    const MasslessBlock b(as, s.q, s.v, s.lambda, p, mc);
    VecX F = -as.force(s.q, s.v, p);
    VecX G = VecX::Zero(m);
    if (m) {
      F += as.phiQTransposeTimes(s.q, p, s.lambda);
      G = as.phi(s.q, p);
    }
    const VecX r = b.stack(F, G);
    const VecX dz = b.solve(as, VecX(-r));
    for (size_t i = 0; i < b.mc.size(); ++i) s.q[b.mc[i]] += dz[i];
    for (size_t j = 0; j < b.cr.size(); ++j) s.lambda[b.cr[j]] += b.kappa * dz[b.mc.size() + j];
    err = dz.head(b.mc.size()).lpNorm<Eigen::Infinity>();
    if (err <= 1e-12 * (1.0 + s.q.lpNorm<Eigen::Infinity>())) {
      // Quasi-static velocities: d/dt of F = 0 and Phi_C = 0 with the other velocities given.
      const MasslessBlock c(as, s.q, s.v, s.lambda, p, mc);
      const VecX vo = c.others(s.v);
      const VecX dv = c.solve(as, VecX(-c.stack(c.K * vo, m ? VecX(c.Jq * vo) : VecX())));
      for (size_t i = 0; i < c.mc.size(); ++i) s.v[c.mc[i]] = dv[i];
      return;
    }
  }
  std::ostringstream os;
  os << "the massless coordinates could not be brought to equilibrium at t = " << s.t
     << " s: last Newton update " << err << " m after 50 iterations";
  throw NumericalError(os.str());
}

void masslessSensitivity(const Assembler& as, const State& x, const VecX& p, int k, State& d) {
  const std::vector<int> mc = masslessCoordinates(as, p);
  if (mc.empty()) return;
  const int m = as.m();
  const MasslessBlock b(as, x.q, x.v, x.lambda, p, mc);
  // d/dp_k of F = Phi_q^T lambda - Q and Phi_C at fixed massless unknowns.
  const VecX qo = b.others(d.q);
  VecX phiP, phiQPTl;  // Phi_p, Phi_qp^T lambda
  as.constraintParamTerms(x.q, p, k, x.lambda, phiP, phiQPTl);
  const VecX dF = b.K * qo - as.forceParamDerivative(x.q, x.v, p, k) + phiQPTl;
  const VecX dG = m ? VecX(b.Jq * qo + phiP) : VecX();
  const VecX z = b.solve(as, VecX(-b.stack(dF, dG)));
  for (size_t i = 0; i < mc.size(); ++i) d.q[mc[i]] = z[i];
  const VecX vo = b.others(d.v);
  const VecX w = b.solve(as, VecX(-b.stack(b.K * vo, m ? VecX(b.Jq * vo) : VecX())));
  for (size_t i = 0; i < mc.size(); ++i) d.v[mc[i]] = w[i];
}

void solveAccelerations(const Assembler& as, State& s, const VecX& p) {
  const int n = as.n(), m = as.m();
  VecX rhs(n + m);
  as.setTime(s.t);
  rhs.head(n) = as.force(s.q, s.v, p);
  // d2 Phi/dt2 = Phi_q a + (v^T H_i v)_i + Phi_tt + 2 Phi_qt v = 0
  if (m) rhs.tail(m) = -(as.hessianQuadratic(s.q, p, s.v) + as.accelerationTimeTerms(s.q, s.v, p));
  const VecX x = solveAugmented(as, s.q, p, s.t, rhs);
  s.a = x.head(n);
  s.lambda = x.tail(m);
}

namespace {

/// The right-hand side of [M Phi_q^T; Phi_q 0] (a_p, lambda_p) = rhs for parameter k, with the
/// force Jacobians Kq = dQ/dq, Kv = dQ/dv at x.
VecX accelerationSensitivityRhs(const Assembler& as, const State& x, const VecX& p, int k, const State& d,
                                const SpMat& Kq, const SpMat& Kv) {
  const int n = as.n(), m = as.m();
  VecX rhs(n + m);
  rhs.head(n) = -(as.massParamDerivativeTimes(p, k, x.a) + as.hessianTimes(x.q, p, x.lambda, d.q) +
                  as.phiQParamDerivativeTransposeTimes(x.q, p, k, x.lambda) -
                  Kq * d.q - Kv * d.v - as.forceParamDerivative(x.q, x.v, p, k));
  if (m)
    rhs.tail(m) = -(as.hessianRowsTimes(x.q, p, x.a, d.q) + as.phiQParamDerivativeTimes(x.q, p, k, x.a) +
                    2.0 * as.hessianRowsTimes(x.q, p, x.v, d.v) +
                    // d/dp of the drivers' g = Phi_tt + 2 Phi_qt v: g_q q_p + 2 Phi_qt v_p + g_p
                    as.accelerationTimeTermsQTimes(x.q, x.v, p, d.q) + 2.0 * as.phiQTTimes(x.q, p, d.v) +
                    as.accelerationTimeTermsParamDerivative(x.q, x.v, p, k));
  return rhs;
}

/// dQ/dq and dQ/dv at x (the assembler at x.t).
std::pair<SpMat, SpMat> forceJacobians(const Assembler& as, const State& x, const VecX& p) {
  const int n = as.n();
  SparseAccumulator kq, kv;
  kq.begin(n, n);
  as.addForceJacobian(kq, x.q, x.v, p, -1.0, 0.0, 0, 0, 0);
  kv.begin(n, n);
  as.addForceJacobian(kv, x.q, x.v, p, 0.0, -1.0, 0, 0, 0);
  return {kq.finish(), kv.finish()};
}

}  // namespace

void solveAccelerationSensitivity(const Assembler& as, const State& x, const VecX& p, int k,
                                  State& d) {
  const int n = as.n(), m = as.m();
  as.setTime(x.t);
  const auto [Kq, Kv] = forceJacobians(as, x, p);
  const VecX sol = solveAugmented(as, x.q, p, x.t, accelerationSensitivityRhs(as, x, p, k, d, Kq, Kv));
  d.a = sol.head(n);
  d.lambda = sol.tail(m);
}

void solveAccelerationSensitivities(const Assembler& as, const State& x, const VecX& p, std::vector<State>& ds,
                                    int first) {
  if (ds.empty()) return;
  const int n = as.n(), m = as.m();
  as.setTime(x.t);
  const auto [Kq, Kv] = forceJacobians(as, x, p);
  MatX sol(n + m, Eigen::Index(ds.size()));
  for (size_t k = 0; k < ds.size(); ++k)
    sol.col(Eigen::Index(k)) = accelerationSensitivityRhs(as, x, p, first + int(k), ds[k], Kq, Kv);
  bool factored = true;
  try {
    factorAugmented(as, x.q, p, x.t).solve(sol);
  } catch (const NumericalError&) {
    if (masslessCoordinates(as, p).empty()) throw;
    factored = false;
  }
  for (size_t k = 0; k < ds.size(); ++k) {
    // With massless coordinates the matrix is singular: column by column as solveAugmented.
    const VecX c = factored ? VecX(sol.col(Eigen::Index(k)))
                            : solveAugmented(as, x.q, p, x.t, VecX(sol.col(Eigen::Index(k))));
    ds[k].a = c.head(n);
    ds[k].lambda = c.tail(m);
  }
}

}  // namespace flexsens
