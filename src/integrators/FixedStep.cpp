#include "integrators/FixedStep.hpp"

#include <cmath>
#include <sstream>

#include "core/SparseLU.hpp"

namespace flexsens {

namespace {

/// Scheme coefficients: a = ca (q - qn) + abar, v = cv (q - qn) + vbar.
struct Scheme {
  double ca, cv;
  bool trapezoidal;
  explicit Scheme(const std::string& type, double h)
      : ca(type == "trapezoidal" ? 4.0 / (h * h) : 1.0 / (h * h)),
        cv(type == "trapezoidal" ? 2.0 / h : 1.0 / h),
        trapezoidal(type == "trapezoidal") {}
  /// History terms (abar, vbar) from the previous step's q, v, a (or their sensitivities:
  /// the map is linear, and q_n enters through -ca q_n, -cv q_n).
  void history(const State& n, double h, VecX& abar, VecX& vbar) const {
    if (trapezoidal) {
      abar = -4.0 / h * n.v - n.a;
      vbar = -n.v;
    } else {
      abar = -n.v / h;
      vbar = VecX::Zero(n.v.size());
    }
  }
};

SpMat newtonMatrix(const Assembler& as, SparseAccumulator& acc, const VecX& q, const VecX& v,
                   const VecX& lt, const VecX& p, const Scheme& sc) {
  const int n = as.n(), m = as.m();
  const double sigma = 1.0 / sc.ca;
  acc.begin(n + m, n + m);
  as.addMass(acc, p, 1.0, 0, 0);
  as.addForceJacobian(acc, q, v, p, sigma, sigma * sc.cv, 0, 0, 0);
  as.addHessian(acc, q, p, lt, 1.0, 0, 0);
  as.addPhiQ(acc, q, p, 1.0, 0, n, true);
  as.addPhiQ(acc, q, p, 1.0, n, 0, false);
  return acc.finish();
}

}  // namespace

IntegratorStats integrateFixedStep(const Assembler& as, const VecX& p, StateWithSens cur,
                                   const IntegratorSettings& set, Observer& obs) {
  const int n = as.n(), m = as.m();
  const double h = set.dt;
  const Scheme sc(set.type, h);
  const double sigma = 1.0 / sc.ca;
  const long nsteps = std::lround((set.tEnd - cur.x.t) / h);
  const long frameEvery = std::max(1L, std::lround(set.frameInterval / h));
  const SpMat M = as.mass(p);
  IntegratorStats st;
  SparseAccumulator acc, kv;
  SparseLU lu;

  obs.frame(cur);
  st.maxConstraintViolation = m ? as.phi(cur.x.q, p).lpNorm<Eigen::Infinity>() : 0.0;
  const double t0 = cur.x.t;
  for (long step = 1; step <= nsteps; ++step) {
    const State& old = cur.x;
    const double t = t0 + step * h;  // not accumulated: frame times stay exact multiples
    VecX abar, vbar;
    sc.history(old, h, abar, vbar);
    // Predictor: Taylor expansion of the previous step. BDF-1 is the scheme for stiff models
    // and starts from q_n + h v_n: stiff light parts (the satellite's prestressed springs, node
    // masses ~1e-3 kg, accelerations ~1e6 m/s^2) would put h^2 a_n / 2 metres away, where the
    // Newton matrix is singular.
    VecX q = old.q + h * old.v + (sc.trapezoidal ? 0.5 * h * h : 0.0) * old.a;
    VecX lt = sigma * old.lambda;
    VecX a, v;
    bool converged = false;
    double lastUpdate = 0.0, lastResidual = 0.0;
    for (int it = 0; it < set.maxNewtonIterations; ++it) {
      a = sc.ca * (q - old.q) + abar;
      v = sc.cv * (q - old.q) + vbar;
      VecX r(n + m);
      r.head(n) = sigma * (M * a - as.force(q, v, p)) + as.phiQTransposeTimes(q, p, lt);
      if (m) r.tail(m) = as.phi(q, p);
      st.residualEvaluations++;
      lastResidual = r.lpNorm<Eigen::Infinity>();
      std::ostringstream what;
      what << "Newton matrix at t = " << t << " s (step " << step << ", h = " << h << " s)";
      lu.factor(newtonMatrix(as, acc, q, v, lt, p, sc), what.str());
      st.jacobianEvaluations++;
      const VecX dx = lu.solve(VecX(-r));
      q += dx.head(n);
      lt += dx.tail(m);
      st.newtonIterations++;
      lastUpdate = dx.head(n).lpNorm<Eigen::Infinity>();
      if (lastUpdate <= set.newtonTol * (1.0 + q.lpNorm<Eigen::Infinity>())) {
        converged = true;
        break;
      }
    }
    if (!converged) {
      std::ostringstream os;
      os << set.type << " step " << step << " at t = " << t << " s (h = " << h
         << " s): Newton did not converge in " << set.maxNewtonIterations
         << " iterations (last update |dq|_inf = " << lastUpdate << " m, residual "
         << lastResidual << "); try a smaller --dt or a looser newton_tol";
      throw NumericalError(os.str());
    }
    State next;
    next.t = t;
    next.q = q;
    next.a = sc.ca * (q - old.q) + abar;
    next.v = sc.cv * (q - old.q) + vbar;
    next.lambda = lt / sigma;
    if (!next.q.allFinite() || !next.v.allFinite() || !next.lambda.allFinite()) {
      std::ostringstream os;
      os << set.type << " step " << step << " at t = " << t << " s: the solution is not finite; "
         << "try a smaller --dt";
      throw NumericalError(os.str());
    }

    std::vector<State> dnext(cur.dp.size());
    if (!cur.dp.empty()) {
      // Exact derivative of the discrete step: Newton matrix at the converged point.
      const SpMat& A = newtonMatrix(as, acc, q, next.v, lt, p, sc);
      lu.factor(A, "sensitivity matrix at t = " + std::to_string(t) + " s");
      kv.begin(n, n);
      as.addForceJacobian(kv, q, next.v, p, 0.0, -1.0, 0, 0, 0);
      const SpMat& dQdv = kv.finish();
      for (size_t k = 0; k < cur.dp.size(); ++k) {
        const State& dold = cur.dp[k];
        VecX dabar, dvbar;
        sc.history(dold, h, dabar, dvbar);
        const VecX ah = -sc.ca * dold.q + dabar;  // d a / dp at fixed q_{n+1}
        const VecX vh = -sc.cv * dold.q + dvbar;  // d v / dp at fixed q_{n+1}
        VecX rp(n + m);
        rp.head(n) = sigma * (as.massParamDerivativeTimes(p, k, next.a) + M * ah -
                              as.forceParamDerivative(q, next.v, p, k) - dQdv * vh) +
                     as.phiQParamDerivativeTransposeTimes(q, p, k, lt);
        if (m) rp.tail(m) = as.phiParamDerivative(q, p, k);
        // One step of iterative refinement: the Newton matrix of natural-coordinate rigid
        // bodies can be ill-conditioned (thin bars: tiny second moments about their axis),
        // and unlike the state, whose Newton iteration corrects its own solves, the
        // sensitivity is a single solve per step: refinement keeps it the exact derivative of
        // the discrete step (the 3D double pendulum was off by 2e-6 relative without it).
        VecX x = lu.solve(VecX(-rp));
        x += lu.solve(VecX(-rp - A * x));
        State& d = dnext[k];
        d.q = x.head(n);
        d.lambda = x.tail(m) / sigma;
        d.v = sc.cv * d.q + vh;
        d.a = sc.ca * d.q + ah;
      }
    }
    cur.x = std::move(next);
    cur.dp = std::move(dnext);
    st.steps++;
    if (m) st.maxConstraintViolation =
        std::max(st.maxConstraintViolation, as.phi(cur.x.q, p).lpNorm<Eigen::Infinity>());
    obs.progress(t);
    if (step % frameEvery == 0 || step == nsteps) obs.frame(cur);
  }
  st.factorizations = lu.factorizations();
  return st;
}

}  // namespace flexsens
