#include "integrators/FixedStep.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <sstream>

#include "core/PreconditionedSolve.hpp"
#include "core/SparseLU.hpp"
#include "integrators/AndersonMixing.hpp"
#include "integrators/InitialState.hpp"
#include "integrators/MotionProjection.hpp"
#include "integrators/StepEnd.hpp"
#include "integrators/TimeGrid.hpp"

namespace flexsens {

namespace {

/// Scheme coefficients: a = ca (q - qn) + abar, v = cv (q - qn) + vbar.
/// Newmark family with generalized-alpha averaging of the accelerations (Chung-Hulbert,
/// in Arnold-Bruls' index-3 form: equilibrium and constraints exactly at t_{n+1}):
///   q_{n+1} = q_n + h v_n + h^2 (1/2 - beta) w_n + h^2 beta w_{n+1}
///   v_{n+1} = v_n + h (1 - gamma) w_n + h gamma w_{n+1}
///   (1 - am) w_{n+1} + am w_n = (1 - af) a_{n+1} + af a_n,  w = pseudo-acceleration.
/// Trapezoidal = (am, af, beta, gamma) = (0, 0, 1/4, 1/2), so w = a. BDF-1 is separate.
/// Implicit midpoint rule: q_{n+1} = q_n + h (v_n + v_{n+1}) / 2, M (v_{n+1} - v_n) / h =
/// Q(q_{n+1/2}, v_{n+1/2}, t_{n+1/2}) - Phi_q(q_{n+1/2}, t_{n+1/2})^T lambda with
/// q_{n+1/2} = (q_n + q_{n+1}) / 2: a symplectic Runge-Kutta method, so with no constraint it
/// conserves linear and angular momentum exactly (internal forces of a frame-indifferent
/// energy have no net force or moment at any configuration) and every quadratic invariant;
/// energy is bounded, not drifting. Constraints hold at t_{n+1} (index 3), Phi(q_{n+1}) = 0, as
/// in the other schemes; the reaction acts where the forces do. With the reaction at q_{n+1}
/// instead, the step's force is off by (h/2) (sum lambda_i Hess Phi_i) v = O(h), one sign
/// every step: first order (seed-000 double pendulum, joint angle over 2 s against IDAS:
/// 1.6e-3, 8.2e-4, 4.1e-4 rad at dt 2, 1, 0.5 ms). At the midpoint the step is symmetric
/// (swap n and n+1, h -> -h: the same equations, given Phi(q_n) = 0), hence of even order: 2.
/// lambda is then the mid-step multiplier; the loads read t_{n+1/2} for the same reason.
struct Scheme {
  double ca = 0, cv = 0;
  bool bdf1 = false, trapezoidal = false, midpoint = false;
  double am = 0, af = 0, beta = 0.25, gamma = 0.5, h = 0;
  /// Forces are evaluated at (fw q_{n+1} + (1 - fw) q_n, fw v_{n+1} + (1 - fw) v_n).
  double fw = 1.0;
  Scheme(const IntegratorSettings& set) : h(set.dt) {
    bdf1 = set.type == "bdf1";
    trapezoidal = set.type == "trapezoidal";
    midpoint = set.type == "midpoint";
    if (bdf1) {
      ca = 1.0 / (h * h);
      cv = 1.0 / h;
      return;
    }
    if (midpoint) {  // a = (v_{n+1} - v_n) / h with v_{n+1} = 2 (q_{n+1} - q_n) / h - v_n
      ca = 2.0 / (h * h);
      cv = 2.0 / h;
      fw = 0.5;
      return;
    }
    if (set.type == "generalized_alpha") {
      const double r = set.rhoInf;  // second order for every r in [0, 1]
      am = (2.0 * r - 1.0) / (r + 1.0);
      af = r / (r + 1.0);
      gamma = 0.5 + af - am;
      beta = 0.25 * (gamma + 0.5) * (gamma + 0.5);
    }
    ca = (1.0 - am) / ((1.0 - af) * beta * h * h);
    cv = gamma / (beta * h);
  }
  /// w_0 = a_0, the consistent initial accelerations (Chung-Hulbert's and Arnold-Bruls' start).
  /// A mode with omega h >> 1 released out of equilibrium then overshoots in the first step:
  /// v_1 -> (1 - rho_inf)^2 / 4 h a_0 instead of at most omega x_0, then decays (its energy by
  /// rho_inf^2 per step asymptotically; test GeneralizedAlpha.FirstStepOvershootOfAStiffModeFollowsTheRecurrence).
  static const VecX& pseudo(const State& n) { return n.pseudoAcc.size() ? n.pseudoAcc : n.a; }
  /// History terms (abar, vbar) from the previous step's q, v, a, w (or their
  /// sensitivities: the map is linear, and q_n enters through -ca q_n, -cv q_n).
  void history(const State& n, VecX& abar, VecX& vbar) const {
    if (midpoint) {
      abar = -2.0 / h * n.v;
      vbar = -n.v;
      return;
    }
    if (bdf1) {
      abar = -n.v / h;
      vbar = VecX::Zero(n.v.size());
      return;
    }
    if (trapezoidal) {  // the general formulas below with w = a, in the original arithmetic
      abar = -4.0 / h * n.v - n.a;
      vbar = -n.v;
      return;
    }
    const VecX& w = pseudo(n);
    const VecX jump = n.v / (beta * h) + (0.5 - beta) / beta * w;  // -(w_{n+1} at q = q_n)
    abar = (-(1.0 - am) * jump + am * w - af * n.a) / (1.0 - af);
    vbar = n.v + h * (1.0 - gamma) * w - gamma * h * jump;
  }
  /// w_{n+1} from a_{n+1} (also for sensitivities); empty for BDF-1.
  VecX nextPseudo(const State& n, const VecX& aNext) const {
    if (bdf1 || trapezoidal || midpoint) return VecX();  // trapezoidal: w = a
    return ((1.0 - af) * aNext + af * n.a - am * pseudo(n)) / (1.0 - am);
  }
  /// Where the forces are evaluated: fw x_{n+1} + (1 - fw) x_n (x = q or v); `next` itself
  /// unless fw < 1 (then written into buf), so the other schemes copy nothing per residual.
  const VecX& forcePoint(const VecX& next, const VecX& old, VecX& buf) const {
    if (fw == 1.0) return next;
    buf = fw * next + (1.0 - fw) * old;
    return buf;
  }
  /// The time [s] of the force point of the step ending at t.
  double forceTime(double t) const { return t - (1.0 - fw) * h; }
};

/// The residual's constraint parts: phi = Phi(q_{n+1}, t_{n+1}), and the reaction
/// phiQTl = Phi_q^T l at the force point (qf, tf) (q_{n+1}, t_{n+1} but for the midpoint rule).
/// Leaves the assembler at time t.
void constraintResidual(const Assembler& as, const Scheme& sc, const VecX& q, const VecX& qf, double t,
                        const VecX& p, const VecX& l, VecX& phi, VecX& phiQTl, VecX& scratch) {
  as.setTime(t);
  if (sc.fw == 1.0) {
    as.constraintTerms(q, p, l, phi, phiQTl);
    return;
  }
  as.setTime(sc.forceTime(t));
  as.constraintTerms(qf, p, l, scratch, phiQTl);
  as.setTime(t);
  phi = as.phi(q, p);
}

/// Modified Newton refreshes its matrix when an update shrinks by less than this factor.
/// (Satellite SAT1, 2 s, BDF-1: 0.1 / 0.3 / 0.5 / 0.9 gave 318 / 287 / 268 / 302 factorizations.)
constexpr double kRefreshRate = 0.5;
/// Modified Newton's Anderson acceleration keeps this many differences (AndersonMixing.hpp).
/// Satellite, 10 s, BDF-1, no parameter: depth 0 / 3 / 5 / 8 gave 1.81 / 1.62 / 1.49 / 1.44
/// factorizations per step (0.526 / 0.514 / 0.491 / 0.495 s).
constexpr int kAndersonDepth = 8;
/// ... used in a step when the step before contracted slower than this somewhere (where the
/// chord already contracts fast the fit only costs: flexible five-bar, modified Newton, 20000
/// steps, 0.20 s accelerated everywhere, 0.185 s so, 0.176 s without; satellite 1.44 / 1.45
/// factorizations per step either way).
constexpr double kAndersonAbove = 0.2;
/// Sensitivity solves with the kept LU: normwise backward error |b - A x| / (|A| |x| + |b|)
/// (inf-norms) to reach, and the applications of the LU allowed before A is factorized. With
/// Anderson acceleration modified Newton keeps an older LU, and 12 applications let SAT1's
/// sensitivity solve fall back to factoring 192 times in 500 steps; 20 / 30: 3 / 0.
constexpr double kSensitivityBackwardError = 1e-13;
/// Iterates whose (q, sigma lambda) differ by at most this much relative (inf-norm, per block)
/// give the same Newton matrix to round-off (see the sensitivity solve).
constexpr double kSameMatrix = 1e-13;
constexpr int kSensitivitySolves = 30;
/// A failure message names the growth of the accelerations when the last step's |a|_inf
/// exceeds this multiple of the largest over the first kEarlySteps steps.
constexpr double kAccelerationGrowth = 100.0;
constexpr long kEarlySteps = 50;

/// |a - b|_inf <= tol (1 + |a|_inf); false when the sizes differ.
bool sameTo(const VecX& a, const VecX& b, double tol) {
  return a.size() == b.size() && (a - b).lpNorm<Eigen::Infinity>() <= tol * (1.0 + a.lpNorm<Eigen::Infinity>());
}

/// The Newton matrix at q_{n+1} = q (time t), with the forces and the reaction at their
/// scheme point (qf, vf) at sc.forceTime(t) (dqf/dq = fw). Leaves the assembler at time t.
SpMat newtonMatrix(const Assembler& as, SparseAccumulator& acc, const VecX& q, const VecX& qf, const VecX& vf,
                   const VecX& lt, const VecX& p, const Scheme& sc, double t) {
  const int n = as.n(), m = as.m();
  const double sigma = 1.0 / sc.ca;
  acc.begin(n + m, n + m);
  as.setTime(sc.forceTime(t));
  as.addMassAndForceJacobian(acc, qf, vf, p, 1.0, sigma * sc.fw, sigma * sc.fw * sc.cv, 0, 0);
  as.addHessian(acc, qf, p, lt, sc.fw, 0, 0);
  as.addPhiQ(acc, qf, p, 1.0, 0, n, true);
  as.setTime(t);
  as.addPhiQ(acc, q, p, 1.0, n, 0, false);
  return acc.finish();
}

}  // namespace

IntegratorStats integrateFixedStep(const Assembler& as, const VecX& p, StateWithSens cur,
                                   const IntegratorSettings& set, Observer& obs) {
  const int n = as.n(), m = as.m();
  const double h = set.dt;
  const Scheme sc(set);
  const std::vector<int> massless = masslessCoordinates(as, p);
  if (sc.midpoint && !massless.empty())  // their equilibrium at the midpoint oscillates
    throw InputError("integrator midpoint: the model has massless parts (inertia: none), whose equilibrium "
                     "the midpoint rule would hold at the mid-step, leaving the end state to oscillate; use "
                     "trapezoidal, bdf1, generalized_alpha or idas");
  const double sigma = 1.0 / sc.ca;
  const long nsteps = fixedStepCount(set.tEnd - cur.x.t, h);
  const long every = frameEvery(set);
  const SpMat M = as.mass(p);
  // Velocity and acceleration projections (trapezoidal rule, generalized-alpha), on request.
  std::unique_ptr<MotionProjection> projection;
  if (set.projections) projection = std::make_unique<MotionProjection>(as, p, massless);
  IntegratorStats st;
  SparseAccumulator acc, kv;
  SparseLU lu;  // modified Newton: kept across iterations and steps
  long gmresSolves = 0, gmresColumns = 0;  // sensitivity solves by GMRES: LU applications, columns
  double factoredCa = 0.0;  // the scheme coefficient of the matrix in lu (h changed: refresh)
  const bool modified = set.newton == "modified";  // else full Newton
  // Growth of the accelerations, for the failure message: the trapezoidal rule (generalized-
  // alpha at rho_inf 1) carries a_n+1 = 4 (q_n+1 - q_n) / h^2 - 4 v_n / h - a_n undamped, and
  // along the constraint directions nothing else holds it; with nonlinear constraints that
  // part grows (massless satellite, dt 1e-3 s: |a|_inf 3e3 at step 100, 1e6 at step 900)
  // until Newton fails. Massless coordinates are left out: their a is that recurrence alone.
  std::vector<char> counted(size_t(n), 1);
  for (int i : massless) counted[size_t(i)] = 0;
  auto largestAcceleration = [&](const VecX& a, int& where) {
    double r = 0.0;
    for (int i = 0; i < n; ++i)
      if (counted[size_t(i)] && std::abs(a[i]) > r) r = std::abs(a[i]), where = i;
    return r;
  };
  double aEarly = 0.0;  // largest |a|_inf over the first kEarlySteps steps
  // A step starts with the matrix of an earlier step unless that failed lately: after a
  // failure the next `skipReuse` steps start with a fresh matrix, twice as many each time.
  int skipReuse = 0, backoff = 1;
  // Newton starts from q_n instead of the predictor once a step needed that (see below).
  bool startAtOld = false;
  AndersonMixing anderson(modified ? kAndersonDepth : 0, n + m, n);  // modified Newton's acceleration
  VecX xk(n + m);                                     // its iterate (q, lambda)
  bool slowChord = false;  // the last step's chord contracted slower than kAndersonAbove
  std::vector<State> dnext;  // the next step's sensitivities
  MatX X, hist;              // their right-hand sides and history terms, kept across steps
  VecX phiBuf, phiQTlBuf;    // the residual's constraint terms (and their p-derivatives)
  VecX phiMidBuf, reactionP; // midpoint: Phi at the force point (unused), the reaction's p-derivative
  VecX forceTerm, inertiaTerm;  // the sensitivity right-hand sides' force and inertia parts
  VecX luQ, luL;             // the iterate (q, sigma lambda) lu's matrix was assembled at ...
  long luStep = 0;           // ... in this step
  VecX dabar, dvbar;
  // The step's history terms and the residual's parts, kept across steps and iterations (no
  // heap traffic: with the kernels' temporaries, malloc and free were ~16% of the n = 8
  // flexible five-bar's run).
  VecX abar, vbar, aBuf, vBuf, forceBuf;

  beginRun(obs, cur);
  as.setTime(cur.x.t);
  st.maxConstraintViolation = m ? as.phi(cur.x.q, p).lpNorm<Eigen::Infinity>() : 0.0;
  const double t0 = cur.x.t;
  for (long step = 1; step <= nsteps; ++step) {
    const State& old = cur.x;
    // Not accumulated: frame times stay exact multiples; the last one is t_end itself.
    const double t = step == nsteps ? set.tEnd : t0 + step * h;
    // Index 3: equilibrium, loads and the drivers' Phi(q, t) all at t_{n+1} (the sensitivity
    // solve below differentiates the same equations, at the same time).
    as.setTime(t);
    sc.history(old, abar, vbar);
    // Predictor: Taylor expansion of the previous step for the trapezoidal rule. BDF-1 and
    // generalized-alpha are the schemes for stiff models and start from q_n + h v_n: stiff
    // light parts (the satellite's prestressed springs, node masses ~1e-3 kg, accelerations
    // ~1e6 m/s^2) would put h^2 a_n / 2 metres away, where the Newton matrix is singular.
    // Last resort (below): Newton from the other start, q_n itself, when an unresolved fast
    // mode (ANCF springs' slopes released from a prestressed shape) left a velocity that throws
    // q_n + h v_n out of Newton's reach. A start that rescued a step becomes the first one tried
    // (startAtOld); a model the predictor serves never sees the other.
    const VecX qTaylor = old.q + h * old.v + (sc.trapezoidal ? 0.5 * h * h : 0.0) * old.a;
    VecX qPredicted = startAtOld ? old.q : qTaylor;
    VecX qfBuf, vfBuf;  // the midpoint's force state
    auto residual = [&](const VecX& qq, const VecX& ll) {
      aBuf = sc.ca * (qq - old.q) + abar;
      vBuf = sc.cv * (qq - old.q) + vbar;
      const VecX& qf = sc.forcePoint(qq, old.q, qfBuf);
      as.setTime(sc.forceTime(t));
      as.force(qf, sc.forcePoint(vBuf, old.v, vfBuf), p, forceBuf);
      constraintResidual(as, sc, qq, qf, t, p, ll, phiBuf, phiQTlBuf, phiMidBuf);
      VecX r(n + m);
      r.head(n).noalias() = M * aBuf;
      r.head(n) = sigma * (r.head(n) - forceBuf) + phiQTlBuf;
      r.tail(m) = phiBuf;
      st.residualEvaluations++;
      return r;
    };
    VecX q, lt;
    double lastUpdate = 0.0, lastResidual = 0.0;
    auto factorAt = [&](const VecX& qq, const VecX& ll, const char* how) {
      vBuf = sc.cv * (qq - old.q) + vbar;
      lu.factor(newtonMatrix(as, acc, qq, sc.forcePoint(qq, old.q, qfBuf), sc.forcePoint(vBuf, old.v, vfBuf), ll, p, sc, t),
                [&] {
                  std::ostringstream what;
                  what << "Newton matrix at t = " << t << " s (step " << step << ", h = " << h << " s" << how << ")";
                  return what.str();
                });
      st.jacobianEvaluations++;
      factoredCa = sc.ca;
      luQ = qq;
      luL = ll;
      luStep = step;
    };
    // Newton from the predictor. With `backtrack`, an update that increases |r|_2 is halved
    // (down to 1/64): the fallback when plain Newton fails, so every step plain Newton
    // solves keeps exactly its path and result.
    auto newton = [&](bool backtrack) {
      q = qPredicted;
      lt = sigma * old.lambda;
      VecX r = residual(q, lt);
      lastResidual = r.lpNorm<Eigen::Infinity>();
      for (int it = 0; it < set.maxNewtonIterations; ++it) {
        factorAt(q, lt, backtrack ? ", with backtracking" : "");
        const VecX dx = lu.solve(VecX(-r));
        st.newtonIterations++;
        lastUpdate = dx.head(n).lpNorm<Eigen::Infinity>();
        double s = 1.0;
        VecX qt = q + dx.head(n), lnew = lt + dx.tail(m);
        if (lastUpdate <= set.newtonTol * (1.0 + qt.lpNorm<Eigen::Infinity>())) {
          q = qt;
          lt = lnew;
          return true;
        }
        VecX rt = residual(qt, lnew);
        while (backtrack && s > 1.0 / 64 && !(rt.allFinite() && rt.norm() <= r.norm())) {
          s *= 0.5;
          qt = q + s * dx.head(n);
          lnew = lt + s * dx.tail(m);
          rt = residual(qt, lnew);
        }
        q = qt;
        lt = lnew;
        r = rt;
        lastResidual = r.lpNorm<Eigen::Infinity>();
        lastUpdate *= s;
      }
      return false;
    };
    // Modified Newton: the factorization kept from earlier iterations or steps, refreshed at
    // the current iterate when the contraction rate theta = |dq_k| / |dq_k-1| (same matrix)
    // exceeds kRefreshRate (that update is dropped), when theta predicts more iterations than
    // the budget left, or when h changed. A matrix of an earlier step that leads away restarts
    // the step from the predictor with a fresh one. The same convergence test as full Newton,
    // made stricter by theta / (1 - theta) (the error left after a linearly converging update)
    // should theta exceed 1/2. False: full Newton redoes the step. In a step after one whose
    // chord contracted slower than kAndersonAbove, the chord steps are Anderson-accelerated.
    bool staleFailed = false;  // the matrix of an earlier step led away: the step restarted
    auto modifiedNewton = [&]() {
      anderson.reset();  // its history belongs to this step's residual and this matrix
      double slowest = 0.0;
      q = qPredicted;
      lt = sigma * old.lambda;
      VecX r = residual(q, lt);
      lastResidual = r.lpNorm<Eigen::Infinity>();
      double previous = 0.0;  // |dq| of the last update with the current matrix; 0: none yet
      bool atCurrent = false;  // the matrix was factorized at the current iterate
      bool earlier = true;     // ... at an iterate of an earlier step
      auto refresh = [&]() {
        factorAt(q, lt, "");
        previous = 0.0;
        atCurrent = true;
        earlier = false;
        anderson.reset();
      };
      if (!lu.factorized() || factoredCa != sc.ca || skipReuse > 0) refresh();
      for (int it = 0; it < set.maxNewtonIterations; ++it) {
        // One plain solve: the matrix is in general an earlier iterate's, so refining the solve
        // against it buys nothing the next residual does not correct (satellite, 10 s: 11% of
        // the run).
        const VecX dx = lu.solve(VecX(-r), false);
        st.newtonIterations++;
        const double update = dx.head(n).lpNorm<Eigen::Infinity>();
        const double theta = previous > 0.0 ? update / previous : 0.0;
        slowest = std::max(slowest, theta);
        // Diverging or contracting slowly: drop the update (a slow one can lead away, as
        // on the satellite's light spring nodes) and refresh at the current iterate.
        if (!dx.allFinite() || theta > kRefreshRate) {
          if (atCurrent) return false;
          if (earlier) {  // the first update, unchecked, may have been the bad one: start over
            q = qPredicted;
            lt = sigma * old.lambda;
            r = residual(q, lt);
            staleFailed = true;
          }
          refresh();
          continue;
        }
        if (slowChord) {  // Anderson acceleration of the chord step (AndersonMixing.hpp)
          st.acceleratedIterations++;
          xk << q, lt;
          const VecX stepped = anderson.step(xk, dx);
          q += stepped.head(n);
          lt += stepped.tail(m);
        } else {
          q += dx.head(n);
          lt += dx.tail(m);
        }
        atCurrent = false;
        lastUpdate = update;
        const double tol = set.newtonTol * (1.0 + q.lpNorm<Eigen::Infinity>());
        if (update * std::max(1.0, theta / (1.0 - theta)) <= tol) {
          slowChord = slowest > kAndersonAbove;
          return true;
        }
        r = residual(q, lt);
        lastResidual = r.lpNorm<Eigen::Infinity>();
        previous = update;
        // Iterations still needed at this rate: theta^k |dq| <= tol.
        const double needed = theta > 0.0 ? std::log(tol / update) / std::log(theta) : 0.0;
        if (it + 1 + needed > set.maxNewtonIterations) refresh();
      }
      return false;
    };
    bool converged = false;
    if (modified) {
      const bool startedStale = skipReuse == 0;
      try {
        converged = modifiedNewton();
      } catch (const NumericalError&) {  // singular refreshed matrix: full Newton decides below
      }
      if (!converged) st.convergenceFailures++;
      if (skipReuse > 0) {
        --skipReuse;
      } else if (startedStale && (staleFailed || !converged)) {
        skipReuse = backoff;
        backoff = std::min(2 * backoff, 32);
      } else {
        backoff = 1;
      }
    }
    if (!converged) {
      try {
        converged = newton(false);
      } catch (const NumericalError&) {  // singular Newton matrix on the way: retry below
      }
    }
    if (!converged) {
      try {
        converged = newton(true);
      } catch (const NumericalError& e) {  // e.g. an element turned inside out: say when
        std::ostringstream os;
        os << set.type << " step " << step << " at t = " << t << " s (h = " << h << " s): " << e.what();
        throw NumericalError(os.str());
      }
    }
    if (!converged && qTaylor != old.q) {
      qPredicted = startAtOld ? qTaylor : VecX(old.q);
      for (bool backtrack : {false, true}) {
        try {
          converged = converged || newton(backtrack);
        } catch (const NumericalError&) {  // reported as not converged below
        }
      }
      if (converged) startAtOld = !startAtOld;
    }
    if (!converged) {
      std::ostringstream os;
      os << set.type << " step " << step << " at t = " << t << " s (h = " << h
         << " s): Newton did not converge in " << set.maxNewtonIterations
         << " iterations, also with backtracking and from both q_n + h v_n and q_n (last update |dq|_inf = " << lastUpdate
         << " m, residual " << lastResidual << "); try a smaller --dt"
         << (set.type == "generalized_alpha" ? ", a smaller rho_inf (more damping)" : "")
         << " or a looser newton_tol";
      int where = -1;
      const double aLast = largestAcceleration(old.a, where);
      if (aEarly > 0.0 && aLast > kAccelerationGrowth * aEarly) {
        os << "; the accelerations grew from |a|_inf = " << aEarly << " (first " << kEarlySteps << " steps) to "
           << aLast << " at the last step (in " << as.model().coordinateLabel(where) << "): ";
        if (sc.trapezoidal || (set.type == "generalized_alpha" && set.rhoInf >= 1.0))
          os << "this scheme leaves the accelerations along the constraint directions undamped and nonlinear "
                "constraints make them grow; project them (integrator.projections: true, --projections on) or "
                "use generalized_alpha with rho_inf < 1, which damps them";
        else
          os << "an unresolved mode or the constraint directions gained energy; try more damping (generalized_alpha "
                "with a smaller rho_inf) or a smaller dt";
      }
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

    dnext.resize(cur.dp.size());  // the storage of two steps ago, reused (no heap traffic)
    if (!cur.dp.empty()) {
      // Exact derivative of the discrete step: A(q_{n+1}) dx/dp = -dr/dp at fixed q_{n+1}, with
      // the Newton matrix at the converged point; one right-hand side per parameter.
      const VecX& qf = sc.forcePoint(q, old.q, qfBuf);
      const VecX& vf = sc.forcePoint(next.v, old.v, vfBuf);
      // The LU Newton kept is of the matrix at the converged point when this step factorized
      // it at an iterate within round-off of that point (full Newton's last update: 1e-14 to
      // 1e-16 relative on the flexible five-bar refined, n >= 20; 1e-10 to 1e-15 on the
      // satellite; ~1e-11 at the five-bar's n = 8, which stops after 2 iterations): the matrix
      // assembled there would be the same to its last digits. Then the right-hand sides are
      // solved with it (refined against the matrix it factorized) and the assembly is skipped:
      // it was 0.15 of a one-parameter five-bar run (refine 16). With the last iterate's
      // matrix at newton_tol instead the sensitivities moved by 5e-7 relative: not exact.
      const bool luAtSolution = luStep == step && factoredCa == sc.ca && lu.factorized() &&
                                sameTo(q, luQ, kSameMatrix) && sameTo(lt, luL, kSameMatrix);
      if (luAtSolution) {
        st.sensitivityReusedLu++;
      } else {
        newtonMatrix(as, acc, q, qf, vf, lt, p, sc, t);
        st.jacobianEvaluations++;
      }
      const SpMat& A = acc.matrix();  // its values are read only when assembled here
      as.setTime(sc.forceTime(t));  // the force derivatives below: at the force point
      kv.begin(n, n);
      as.addForceJacobian(kv, qf, vf, p, 0.0, -1.0, 0, 0, 0);
      const SpMat dQdv = kv.finish();
      SpMat dQdq;  // midpoint: the forces see q_n too
      if (sc.fw != 1.0) {
        kv.begin(n, n);
        as.addForceJacobian(kv, qf, vf, p, -1.0, 0.0, 0, 0, 0);
        dQdq = kv.finish();
      }
      const Eigen::Index np = Eigen::Index(cur.dp.size());
      X.resize(n + m, np);  // right-hand sides -> solutions
      hist.resize(2 * n, np);  // (a, v) at fixed q_{n+1}
      for (Eigen::Index k = 0; k < np; ++k) {
        const State& dold = cur.dp[size_t(k)];
        sc.history(dold, dabar, dvbar);
        auto ah = hist.col(k).head(n);  // d a / dp at fixed q_{n+1}
        auto vh = hist.col(k).tail(n);  // d v / dp at fixed q_{n+1}
        ah = -sc.ca * dold.q + dabar;
        vh = -sc.cv * dold.q + dvbar;
        // d(qf, vf)/dp at fixed q_{n+1}: ((1 - fw) dq_n, fw vh + (1 - fw) dv_n).
        // Into kept vectors (no heap traffic per step and parameter): Q_p + dQ/d(q, v) terms.
        as.setTime(sc.forceTime(t));
        as.forceParamDerivative(qf, vf, p, int(k), forceTerm);
        if (sc.fw != 1.0)
          forceTerm += (1.0 - sc.fw) * (dQdq * dold.q) + dQdv * VecX(sc.fw * vh + (1.0 - sc.fw) * dold.v);
        else
          forceTerm.noalias() += dQdv * vh;
        if (sc.fw != 1.0) {  // the reaction Phi_q(qf)^T sigma lambda: Phi_qp^T sigma lambda + (1 - fw) H dq_n
          as.constraintParamTerms(qf, p, int(k), lt, phiMidBuf, reactionP);
          reactionP += (1.0 - sc.fw) * as.hessianTimes(qf, p, lt, dold.q);
        }
        as.setTime(t);
        as.constraintParamTerms(q, p, int(k), lt, phiBuf, phiQTlBuf);  // Phi_p, Phi_qp^T sigma lambda
        if (sc.fw != 1.0) phiQTlBuf = reactionP;
        as.massParamDerivativeTimes(p, int(k), next.a, inertiaTerm);    // M_p a, then + M ah
        inertiaTerm.noalias() += M * ah;
        X.col(k).head(n) = -(sigma * (inertiaTerm - forceTerm) + phiQTlBuf);
        X.col(k).tail(m) = -phiBuf;
      }
      // Named only when factorized (formatting t every step cost 3% of a small model's run).
      auto what = [t]() { return "sensitivity matrix at t = " + std::to_string(t) + " s"; };
      // Solved by GMRES preconditioned with the LU Newton kept (full Newton: of the last
      // iterate, next to the converged point), without a factorization; with several
      // parameters, by factoring A instead when that costs fewer flops (counts, not clocks:
      // the same choice on every machine). GMRES: per parameter s iterations (s: the
      // preconditioner solves per parameter so far, 3 before any), each an LU solve, a product
      // with A and ~10 vector passes, plus Gram-Schmidt's 2 (n + m) s^2. Factoring: twice KLU's
      // flop count (its refactorization's overhead), then up to two refined solves per
      // parameter. Ten parameters, BDF-1: GMRES took 0.075 / 2.90 s, factoring 0.059 / 2.67 s
      // of the flexible five-bar's / the 3000-segment chain's runs; one parameter: a wash.
      const double perSolve = lu.solveFlops() + 2.0 * double(A.nonZeros()) + 10.0 * double(n + m);
      const double s = gmresColumns > 0 ? double(gmresSolves) / double(gmresColumns) : 3.0;
      const double iterate = double(np) * (s * perSolve + 2.0 * double(n + m) * s * s);
      const double factor = 2.0 * lu.factorFlops() + double(np) * 2.0 * perSolve;
      bool exact = luAtSolution || (np > 1 && iterate > factor && lu.factorFlops() > 0.0);
      if (exact && !luAtSolution) {
        lu.factor(A, what);
        st.sensitivityFactorizations++;
      }
      Eigen::Index iterated = 0;  // the first columns, solved by GMRES
      if (!exact) {
        const double normA = infNorm(A);
        for (; iterated < np; ++iterated) {
          VecX x;
          const PreconditionedSolveResult res = preconditionedSolve(
              A, normA, lu, VecX(X.col(iterated)), x, kSensitivityBackwardError, kSensitivitySolves);
          st.sensitivityIterations += res.preconditionerSolves;
          gmresSolves += res.preconditionerSolves;
          ++gmresColumns;
          if (!res.converged) {  // this column and the rest with A factorized
            lu.factor(A, what);
            st.sensitivityFactorizations++;
            exact = true;
            break;
          }
          X.col(iterated) = x;
        }
      }
      if (exact) {
        // Refined against A: the Newton matrix of natural-coordinate rigid bodies can be
        // ill-conditioned (thin bars: tiny second moments about their axis), and unlike the
        // state, whose Newton iteration corrects its own solves, the sensitivity is a single
        // solve per step (the 3D double pendulum was off by 2e-6 relative unrefined).
        MatX rest = X.rightCols(np - iterated);
        lu.solve(rest);
        X.rightCols(np - iterated) = rest;
      }
    }
    // The step's equations, which the sensitivity right-hand sides above differentiate, hold
    // with the scheme's a and v; the projections change them only now.
    if (projection) projection->project(next, step);
    next.pseudoAcc = sc.nextPseudo(old, next.a);
    for (size_t k = 0; k < dnext.size(); ++k) {
      State& d = dnext[k];
      d.q = X.col(Eigen::Index(k)).head(n);
      d.lambda = X.col(Eigen::Index(k)).tail(m) / sigma;
      d.v = sc.cv * d.q + hist.col(Eigen::Index(k)).tail(n);
      d.a = sc.ca * d.q + hist.col(Eigen::Index(k)).head(n);
      if (projection) projection->sensitivity(next, int(k), d);
      d.pseudoAcc = sc.nextPseudo(cur.dp[k], d.a);
    }
    if (step <= kEarlySteps) {
      int where = -1;
      aEarly = std::max(aEarly, largestAcceleration(next.a, where));
    }
    cur.x = std::move(next);
    std::swap(cur.dp, dnext);
    st.steps++;
    if (m) st.maxConstraintViolation =
        std::max(st.maxConstraintViolation, as.phi(cur.x.q, p).lpNorm<Eigen::Infinity>());
    st.factorizations = lu.factorizations();
    st.luFill = lu.maxFill();
    st.factorizationSeconds = lu.factorSeconds();
    endStep(obs, cur, st, step % every == 0 || step == nsteps);
  }
  return st;
}

}  // namespace flexsens
