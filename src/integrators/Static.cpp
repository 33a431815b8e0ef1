#include "integrators/Static.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "core/SparseLU.hpp"

namespace flexsens {

namespace {
double infNorm(const VecX& x) { return x.size() ? x.lpNorm<Eigen::Infinity>() : 0.0; }

/// The static Newton matrix R_x = [-dQ/dq + sum lambda_i Hess(Phi_i), Phi_q^T; Phi_q, 0].
SpMat staticMatrix(SparseAccumulator& acc, const Assembler& as, const VecX& q, const VecX& lambda, const VecX& p) {
  const int n = as.n(), m = as.m();
  acc.begin(n + m, n + m);
  as.addForceJacobian(acc, q, VecX::Zero(n), p, 1.0, 0.0, 0, 0, 0);
  if (m) {
    as.addHessian(acc, q, p, lambda, 1.0, 0, 0);
    as.addPhiQ(acc, q, p, 1.0, 0, n, true);
    as.addPhiQ(acc, q, p, 1.0, n, 0, false);
  }
  return acc.finish();
}
}  // namespace

std::function<VecX(double)> linearLoadPath(const VecX& pUnloaded, const VecX& pLoaded) {
  if (pUnloaded.size() != pLoaded.size())
    throw std::invalid_argument("linearLoadPath: parameter vectors of different sizes");
  return [p0 = pUnloaded, dp = VecX(pLoaded - pUnloaded)](double s) -> VecX { return p0 + s * dp; };
}

VecX solveStatic(const Assembler& as, const VecX& p, VecX q0, const StaticSettings& s,
                 StaticReport* report) {
  const int n = as.n(), m = as.m();
  if (q0.size() != n) {
    std::ostringstream os;
    os << "solveStatic: initial positions have " << q0.size() << " entries, the model has " << n
       << " coordinates";
    throw std::invalid_argument(os.str());
  }
  if (s.steps < 1 || s.maxIterations < 1 || !(s.tol > 0.0))
    throw std::invalid_argument("solveStatic: need steps >= 1, maxIterations >= 1 and tol > 0");
  const int steps = (s.paramsAt || s.stepLoadFactor) ? s.steps : 1;
  // The load factor goes back to 1 however this call ends.
  struct LoadFactorReset {
    const Assembler& as;
    ~LoadFactorReset() { as.setLoadFactor(1.0); }
  } reset{as};
  if (s.paramsAt) {
    const VecX p1 = s.paramsAt(1.0);
    if (p1.size() != p.size() || (p1 - p).lpNorm<Eigen::Infinity>() >
                                     1e-12 * std::max(1.0, p.lpNorm<Eigen::Infinity>()))
      throw std::invalid_argument("solveStatic: paramsAt(1) differs from the parameters p");
  }

  StaticReport rep;
  as.setTime(s.time);  // staticSensitivities then differentiates at the same time
  VecX q = std::move(q0), lambda = VecX::Zero(m);
  const VecX v = VecX::Zero(n);
  SparseAccumulator acc;
  SparseLU lu;
  VecX r(n + m);

  // Residual [Phi_q^T lambda - Q; Phi] at (q, lambda, pk).
  auto residual = [&](const VecX& pk) {
    r.head(n) = -as.force(q, v, pk);
    if (m) {
      r.head(n) += as.phiQTransposeTimes(q, pk, lambda);
      r.tail(m) = as.phi(q, pk);
    }
  };

  for (int k = 1; k <= steps; ++k) {
    const double lf = static_cast<double>(k) / steps;
    const VecX pk = (k == steps || !s.paramsAt) ? p : s.paramsAt(lf);
    if (s.stepLoadFactor) as.setLoadFactor(lf);
    bool converged = false;
    int it = 0;
    double dqNorm = 0.0;
    for (it = 1; it <= s.maxIterations; ++it) {
      residual(pk);
      const SpMat J = staticMatrix(acc, as, q, lambda, pk);
      std::ostringstream what;
      what << "static Newton matrix [-dQ/dq + H(lambda), Phi_q^T; Phi_q, 0] at load step " << k
           << "/" << steps << " (load factor " << lf << "), iteration " << it
           << " (an unrestrained rigid motion, a buckling point, or redundant constraints)";
      try {
        lu.factor(J, what.str());
      } catch (const NumericalError& e) {
        std::ostringstream os;
        os << "static equilibrium: " << e.what() << "; residual |Q - Phi_q^T lambda|_inf = "
           << infNorm(r.head(n)) << " N";
        if (m) os << ", |Phi|_inf = " << infNorm(r.tail(m));
        os << "; if a load step overshoots, try more load steps (e.g. " << 2 * steps << ")";
        throw NumericalError(os.str());
      }
      const VecX dx = lu.solve(VecX(-r));
      if (!dx.allFinite()) break;
      q += dx.head(n);
      if (m) lambda += dx.tail(m);
      dqNorm = infNorm(dx.head(n));
      const double dlNorm = m ? infNorm(dx.tail(m)) : 0.0;
      if (dqNorm <= s.tol * (1.0 + infNorm(q)) && dlNorm <= s.tol * (1.0 + infNorm(lambda))) {
        converged = true;
        break;
      }
    }
    if (!converged || !q.allFinite()) {
      residual(pk);
      std::ostringstream os;
      os << "static equilibrium: Newton did not converge at load step " << k << "/" << steps
         << " (load factor " << lf << ") after " << std::min(it, s.maxIterations)
         << " iterations: residual |Q - Phi_q^T lambda|_inf = " << infNorm(r.head(n)) << " N";
      if (m) os << ", |Phi|_inf = " << infNorm(r.tail(m));
      os << ", last update |dq|_inf = " << dqNorm
         << " m; try more load steps (e.g. " << 2 * steps << ") or more iterations";
      throw NumericalError(os.str());
    }
    if (s.onStep) s.onStep(k, lf, q, lambda);
    rep.iterationsPerStep.push_back(it);
    rep.iterations += it;
    ++rep.steps;
  }
  residual(p);
  rep.residualNorm = infNorm(r.head(n));
  rep.constraintNorm = m ? infNorm(r.tail(m)) : 0.0;
  rep.lambda = lambda;
  if (report) *report = std::move(rep);
  return q;
}

StaticSensitivity staticSensitivities(const Assembler& as, const VecX& q, const VecX& lambda, const VecX& p) {
  const int n = as.n(), m = as.m(), np = static_cast<int>(p.size());
  const VecX v = VecX::Zero(n);
  SparseAccumulator acc;
  const SpMat J = staticMatrix(acc, as, q, lambda, p);
  SparseLU lu;
  lu.factor(J, "static sensitivity matrix [-dQ/dq + H(lambda), Phi_q^T; Phi_q, 0] at the equilibrium");
  StaticSensitivity out{MatX(n, np), MatX(m, np)};
  for (int k = 0; k < np; ++k) {
    VecX phiP, phiQPTl;  // Phi_p, Phi_qp^T lambda
    as.constraintParamTerms(q, p, k, lambda, phiP, phiQPTl);
    VecX rp(n + m);
    rp.head(n) = phiQPTl - as.forceParamDerivative(q, v, p, k);
    rp.tail(m) = phiP;
    VecX x = lu.solve(VecX(-rp));
    x += lu.solve(VecX(-rp - J * x));  // one step of iterative refinement
    out.qp.col(k) = x.head(n);
    if (m) out.lambdap.col(k) = x.tail(m);
  }
  return out;
}

}  // namespace flexsens
