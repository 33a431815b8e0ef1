#include "integrators/InitialState.hpp"

#include <sstream>

#include "core/SparseLU.hpp"

namespace flexsens {


VecX projectPositions(const Assembler& as, VecX q, const VecX& p, double tol) {
  if (as.m() == 0) return q;
  double err = 0.0;
  for (int it = 0; it < 50; ++it) {
    const VecX r = as.phi(q, p);
    err = r.lpNorm<Eigen::Infinity>();
    if (err <= tol) return q;
    const MatX J = as.phiQDense(q, p);
    // Least-norm step dq = -J^T (J J^T)^+ r, via complete orthogonal decomposition of J.
    q -= J.completeOrthogonalDecomposition().solve(r);
  }
  std::ostringstream os;
  os << "the initial positions could not be brought onto the constraints: |Phi|_inf = " << err
     << " after 50 Gauss-Newton iterations; check that the scene's node positions and "
        "constraint lengths are compatible";
  throw NumericalError(os.str());
}

VecX projectVelocities(const Assembler& as, const VecX& q, const VecX& v, const VecX& p) {
  if (as.m() == 0) return v;
  const MatX J = as.phiQDense(q, p);
  return v - J.completeOrthogonalDecomposition().solve(J * v);
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
}  // namespace

void solveAccelerations(const Assembler& as, State& s, const VecX& p) {
  const int n = as.n(), m = as.m();
  VecX rhs(n + m);
  rhs.head(n) = as.force(s.q, s.v, p);
  if (m) rhs.tail(m) = -as.hessianQuadratic(s.q, p, s.v);
  const VecX x = factorAugmented(as, s.q, p, s.t).solve(rhs);
  s.a = x.head(n);
  s.lambda = x.tail(m);
}

void solveAccelerationSensitivity(const Assembler& as, const State& x, const VecX& p, int k,
                                  State& d) {
  const int n = as.n(), m = as.m();
  // dQ/dq q_p + dQ/dv v_p, from the sparse force Jacobians.
  SparseAccumulator kq, kv;
  kq.begin(n, n);
  as.addForceJacobian(kq, x.q, x.v, p, -1.0, 0.0, 0, 0, 0);
  kv.begin(n, n);
  as.addForceJacobian(kv, x.q, x.v, p, 0.0, -1.0, 0, 0, 0);
  VecX rhs(n + m);
  rhs.head(n) = -(as.massParamDerivativeTimes(p, k, x.a) + as.hessianTimes(x.q, p, x.lambda, d.q) +
                  as.phiQParamDerivativeTransposeTimes(x.q, p, k, x.lambda) -
                  kq.finish() * d.q - kv.finish() * d.v - as.forceParamDerivative(x.q, x.v, p, k));
  if (m)
    rhs.tail(m) = -(as.hessianRowsTimes(x.q, p, x.a, d.q) + as.phiQParamDerivativeTimes(x.q, p, k, x.a) +
                    2.0 * as.hessianRowsTimes(x.q, p, x.v, d.v));
  const VecX sol = factorAugmented(as, x.q, p, x.t).solve(rhs);
  d.a = sol.head(n);
  d.lambda = sol.tail(m);
}

}  // namespace flexsens
