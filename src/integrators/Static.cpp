#include "integrators/Static.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <sstream>
#include <stdexcept>

#include "core/SparseLU.hpp"

namespace flexsens {

void FactorizationCounters::add(const FactorizationCounters& o) {
  factorizations += o.factorizations;
  seconds += o.seconds;
  maxFill = std::max(maxFill, o.maxFill);
}

namespace {
double infNorm(const VecX& x) { return x.size() ? x.lpNorm<Eigen::Infinity>() : 0.0; }

FactorizationCounters countersOf(const SparseLU& lu) {
  FactorizationCounters c;
  c.factorizations = lu.factorizations();
  c.seconds = lu.factorSeconds();
  c.maxFill = lu.maxFill();
  return c;
}

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

VecX solveLinearStatic(const Assembler& as, const VecX& p, const VecX& q0, double time, StaticReport* report) {
  const int n = as.n(), m = as.m();
  if (q0.size() != n) throw std::invalid_argument("solveLinearStatic: rest positions of the wrong size");
  as.setLoadFactor(1.0);
  as.setTime(time);
  SparseAccumulator acc;
  const SpMat J = staticMatrix(acc, as, q0, VecX::Zero(m), p);
  SparseLU lu;
  lu.factor(J, "linear static matrix [K, Phi_q^T; Phi_q, 0] at the rest state (an unrestrained rigid motion, "
               "a mechanism, or redundant constraints: add supports)");
  VecX r(n + m);  // the static residual at (q0, lambda = 0)
  r.head(n) = -as.force(q0, VecX::Zero(n), p);
  if (m) r.tail(m) = as.phi(q0, p);
  VecX x = lu.solve(VecX(-r));
  x += lu.solve(VecX(-r - J * x));  // one step of iterative refinement
  if (!x.allFinite())
    throw NumericalError("linear static: the solution is not finite (a singular stiffness at the rest state)");
  StaticReport rep;
  rep.steps = 1;
  rep.iterations = 1;
  rep.iterationsPerStep = {1};
  const VecX res = J * x + r;
  rep.residualNorm = infNorm(res.head(n));
  rep.constraintNorm = m ? infNorm(res.tail(m)) : 0.0;
  rep.lambda = x.tail(m);
  rep.factor = countersOf(lu);
  if (report) *report = std::move(rep);
  return q0 + x.head(n);
}

namespace {
/// Q_qp u: the derivative along u of the analytic Q_p at q0, by a fourth-order central
/// difference (Richardson of two central differences) with the step h |u|_inf = 1e-3 (1 +
/// |q0|_inf) / 8 ... h / 2; zero without a displacement.
VecX forceParamDerivativeAlong(const Assembler& as, const VecX& q0, const VecX& u, const VecX& p, int k) {
  const VecX v = VecX::Zero(q0.size());
  const double un = infNorm(u);
  if (un == 0.0) return VecX::Zero(q0.size());
  const double h = 1e-3 * (1.0 + infNorm(q0)) / (8.0 * un);
  auto central = [&](double e) {
    return VecX((as.forceParamDerivative(q0 + e * u, v, p, k) - as.forceParamDerivative(q0 - e * u, v, p, k)) / (2.0 * e));
  };
  return (4.0 * central(0.5 * h) - central(h)) / 3.0;
}
}  // namespace

StaticSensitivity linearStaticSensitivities(const Assembler& as, const VecX& q0, const VecX& q, const VecX& lambda,
                                            const VecX& p) {
  const int n = as.n(), m = as.m(), np = static_cast<int>(p.size());
  const VecX v = VecX::Zero(n), u = q - q0;
  SparseAccumulator acc;
  const SpMat J = staticMatrix(acc, as, q0, VecX::Zero(m), p);
  SparseLU lu;
  lu.factor(J, "linear static matrix [K, Phi_q^T; Phi_q, 0] at the rest state");
  StaticSensitivity out{MatX(n, np), MatX(m, np)};
  for (int k = 0; k < np; ++k) {
    VecX phiP, phiQPTl;  // Phi_p, Phi_qp^T lambda at q0
    as.constraintParamTerms(q0, p, k, lambda, phiP, phiQPTl);
    VecX rp(n + m);  // d/dp of J [u; lambda] + r at fixed (u, lambda)
    rp.head(n) = phiQPTl - as.forceParamDerivative(q0, v, p, k) - forceParamDerivativeAlong(as, q0, u, p, k);
    if (m) rp.tail(m) = phiP + as.phiQParamDerivativeTimes(q0, p, k, u);
    VecX x = lu.solve(VecX(-rp));
    x += lu.solve(VecX(-rp - J * x));
    out.qp.col(k) = x.head(n);
    if (m) out.lambdap.col(k) = x.tail(m);
  }
  out.factor = countersOf(lu);
  return out;
}

std::function<VecX(double)> linearLoadPath(const VecX& pUnloaded, const VecX& pLoaded) {
  if (pUnloaded.size() != pLoaded.size())
    throw std::invalid_argument("linearLoadPath: parameter vectors of different sizes");
  return [p0 = pUnloaded, dp = VecX(pLoaded - pUnloaded)](double s) -> VecX { return p0 + s * dp; };
}

namespace {

/// One Newton update measured against the convergence test (the quantities and their bounds).
struct UpdateCheck {
  double dq = 0.0, dqBound = 0.0;  ///< |dq|_inf and tol (1 + |q|_inf) [m]
  double dl = 0.0, dlBound = 0.0;  ///< |dlambda|_inf and its bound (force units, [N])
  double forceScale = 0.0;         ///< the scale dlBound is relative to [N]
  bool passed() const { return dq <= dqBound && dl <= dlBound; }
};

/// Newton on one load step of the static equations, plain or with a backtracking line search.
class StaticNewton {
 public:
  StaticNewton(const Assembler& as, const StaticSettings& s) : as_(as), s_(s), n_(as.n()), m_(as.m()), r_(n_ + m_) {}

  /// Newton from (q, lambda) at parameters pk; true when converged, (q, lambda) the last iterate.
  bool solve(VecX& q, VecX& lambda, const VecX& pk, bool lineSearch, const std::string& where);
  int iterations() const { return iterations_; }
  const UpdateCheck& last() const { return check_; }
  const SparseLU& lu() const { return lu_; }
  /// [Phi_q^T lambda - Q; Phi] at (q, lambda, pk), with the force scale max(|Q|, |Phi_q^T lambda|).
  const VecX& residual(const VecX& q, const VecX& lambda, const VecX& pk);
  double forceNorm() const { return infNorm(r_.head(n_)); }
  double constraintNorm() const { return m_ ? infNorm(r_.tail(m_)) : 0.0; }

 private:
  void factor(const VecX& q, const VecX& lambda, const VecX& pk, const std::string& where);
  /// The convergence test of the update dx at the iterate it leads to. Positions as the
  /// dynamic Newton: |dq|_inf <= tol (1 + |q|_inf). Multipliers relative to the load and
  /// reaction scales: |dlambda|_inf <= tol (1 + max(|Q|_inf, |Phi_q^T lambda|_inf, k (1 + |q|_inf))),
  /// k the largest diagonal stiffness: the force the positions' tolerance stands for, so a
  /// model whose internal forces are large beside its loads (round-off ~ eps k |q|) converges.
  UpdateCheck measure(const VecX& dx, const VecX& q, const VecX& lambda) const;

  const Assembler& as_;
  const StaticSettings& s_;
  const int n_, m_;
  SparseAccumulator acc_;
  SparseLU lu_;
  VecX r_;
  double forceScale_ = 0.0, stiffness_ = 0.0;
  int iterations_ = 0;
  UpdateCheck check_;
};

const VecX& StaticNewton::residual(const VecX& q, const VecX& lambda, const VecX& pk) {
  const VecX Q = as_.force(q, VecX::Zero(n_), pk);
  r_.head(n_) = -Q;
  forceScale_ = infNorm(Q);
  if (m_) {
    const VecX reaction = as_.phiQTransposeTimes(q, pk, lambda);
    r_.head(n_) += reaction;
    r_.tail(m_) = as_.phi(q, pk);
    forceScale_ = std::max(forceScale_, infNorm(reaction));
  }
  return r_;
}

void StaticNewton::factor(const VecX& q, const VecX& lambda, const VecX& pk, const std::string& where) {
  const SpMat J = staticMatrix(acc_, as_, q, lambda, pk);
  stiffness_ = n_ ? J.diagonal().head(n_).cwiseAbs().maxCoeff() : 0.0;
  try {
    lu_.factor(J, [&] {
      return "static Newton matrix [-dQ/dq + H(lambda), Phi_q^T; Phi_q, 0] at " + where +
             " (an unrestrained rigid motion, a buckling point, or redundant constraints)";
    });
  } catch (const NumericalError& e) {
    std::ostringstream os;
    os << "static equilibrium: " << e.what() << "; residual |Q - Phi_q^T lambda|_inf = " << forceNorm() << " N";
    if (m_) os << ", |Phi|_inf = " << constraintNorm();
    os << "; if a load step overshoots, try more load steps (static.load_steps)";
    throw NumericalError(os.str());
  }
}

UpdateCheck StaticNewton::measure(const VecX& dx, const VecX& q, const VecX& lambda) const {
  UpdateCheck c;
  c.dq = infNorm(dx.head(n_));
  c.dqBound = s_.tol * (1.0 + infNorm(q));
  c.dl = m_ ? infNorm(dx.tail(m_)) : 0.0;
  c.forceScale = std::max({forceScale_, infNorm(lambda), stiffness_ * (1.0 + infNorm(q))});
  c.dlBound = s_.tol * (1.0 + c.forceScale);
  return c;
}

// Full Newton. With the line search an update that does not decrease |r|_2 is halved down to
// 1/64 of it (the convergence test is on the full update first, so round-off noise in |r|
// near the solution does not shrink the last steps).
bool StaticNewton::solve(VecX& q, VecX& lambda, const VecX& pk, bool lineSearch, const std::string& where) {
  iterations_ = 0;
  residual(q, lambda, pk);
  for (int it = 1; it <= s_.maxIterations; ++it) {
    iterations_ = it;
    factor(q, lambda, pk, where + ", iteration " + std::to_string(it) + (lineSearch ? " with line search" : ""));
    const VecX dx = lu_.solve(VecX(-r_));
    if (!dx.allFinite()) return false;
    const double r0 = r_.norm();
    VecX qt = q + dx.head(n_), lt = lambda + dx.tail(m_);
    check_ = measure(dx, qt, lt);
    if (check_.passed()) {
      q = std::move(qt);
      lambda = std::move(lt);
      residual(q, lambda, pk);
      return true;
    }
    residual(qt, lt, pk);
    for (double step = 0.5; lineSearch && step >= 1.0 / 64 && !(r_.allFinite() && r_.norm() < r0); step *= 0.5) {
      qt = q + step * dx.head(n_);
      lt = lambda + step * dx.tail(m_);
      residual(qt, lt, pk);
    }
    q = std::move(qt);
    lambda = std::move(lt);
    if (!q.allFinite() || !r_.allFinite()) return false;
  }
  return false;
}

/// The failure of a load step: the failing quantity with its bound, where, and what may help.
std::string stepFailure(StaticNewton& newton, const StaticSettings& s, const std::string& where, int steps,
                        int iterations) {
  const UpdateCheck& c = newton.last();
  std::ostringstream os;
  os << "static equilibrium: Newton did not converge at " << where << " in " << iterations
     << " iterations (plain, then with a backtracking line search): ";
  if (!(c.dq <= c.dqBound))
    os << "the positions' update |dq|_inf = " << c.dq << " m exceeds its bound " << c.dqBound
       << " m (newton_tol " << s.tol << " x (1 + |q|_inf))";
  else
    os << "the multipliers' update |dlambda|_inf = " << c.dl << " exceeds its bound " << c.dlBound
       << " (newton_tol " << s.tol << " x (1 + the force scale " << c.forceScale << " N))";
  os << "; residual |Q - Phi_q^T lambda|_inf = " << newton.forceNorm() << " N";
  if (newton.constraintNorm() > 0.0) os << ", |Phi|_inf = " << newton.constraintNorm();
  const bool roundOff = newton.forceNorm() <= 1e-6 * (1.0 + c.forceScale) && c.dq <= 1e3 * c.dqBound;
  if (roundOff)
    os << "; the residual is at round-off: a looser integrator.newton_tol (e.g. " << 100 * s.tol << ") accepts it";
  else
    os << "; try more load steps (static.load_steps, e.g. " << 2 * steps
       << ") or more iterations (integrator.max_newton_iterations, now " << s.maxIterations << ")";
  return os.str();
}

}  // namespace

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
  StaticNewton newton(as, s);
  for (int k = 1; k <= steps; ++k) {
    const double lf = static_cast<double>(k) / steps;
    const VecX pk = (k == steps || !s.paramsAt) ? p : s.paramsAt(lf);
    if (s.stepLoadFactor) as.setLoadFactor(lf);
    std::ostringstream where;
    where << "load step " << k << "/" << steps << " (load factor " << lf << ")";
    // Plain Newton first (its path is the classic one); when it stalls, diverges or meets a
    // singular matrix, again from the last equilibrium with the line search.
    VecX qk = q, lk = lambda;
    bool converged = false;
    int used = 0;
    try {
      converged = newton.solve(qk, lk, pk, false, where.str());
    } catch (const NumericalError&) {
    }
    used += newton.iterations();
    if (!converged) {
      qk = q;
      lk = lambda;
      converged = newton.solve(qk, lk, pk, true, where.str());
      used += newton.iterations();
      if (!converged) throw NumericalError(stepFailure(newton, s, where.str(), steps, used));
    }
    q = std::move(qk);
    lambda = std::move(lk);
    if (s.onStep) s.onStep(k, lf, q, lambda);
    rep.iterationsPerStep.push_back(used);
    rep.iterations += used;
    ++rep.steps;
  }
  newton.residual(q, lambda, p);
  rep.residualNorm = newton.forceNorm();
  rep.constraintNorm = newton.constraintNorm();
  rep.lambda = lambda;
  rep.factor = countersOf(newton.lu());
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
  out.factor = countersOf(lu);
  return out;
}

}  // namespace flexsens
