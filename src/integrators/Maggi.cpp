#include "integrators/Maggi.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <sstream>

#include "integrators/InitialState.hpp"
#include "integrators/StepEnd.hpp"
#include "integrators/TimeGrid.hpp"

namespace flexsens {

namespace {

/// Dependent (pivot) and independent coordinate indices, each ascending.
struct Partition {
  std::vector<int> dep, indep;
};

/// The ODE state y = (q, v_i) and its sensitivities y_p = (q_p, v_i,p), one per parameter.
/// The same layout holds a derivative dy/dt (q' = v, v_i' = a_i; q_p' = v_p, v_i,p' = a_p,i).
struct Y {
  VecX q, vi;
  std::vector<VecX> qp, vip;
};

/// y + c dy
Y axpy(const Y& y, double c, const Y& dy) {
  Y r;
  r.q = y.q + c * dy.q;
  r.vi = y.vi + c * dy.vi;
  r.qp.resize(y.qp.size());
  r.vip.resize(y.vip.size());
  for (size_t k = 0; k < y.qp.size(); ++k) {
    r.qp[k] = y.qp[k] + c * dy.qp[k];
    r.vip[k] = y.vip[k] + c * dy.vip[k];
  }
  return r;
}

/// Classic RK4 update y + h/6 (k1 + 2 k2 + 2 k3 + k4), sensitivities alike.
Y rk4Combine(const Y& y, double h, const Y& k1, const Y& k2, const Y& k3, const Y& k4) {
  Y r;
  const double c = h / 6.0;
  r.q = y.q + c * (k1.q + 2.0 * k2.q + 2.0 * k3.q + k4.q);
  r.vi = y.vi + c * (k1.vi + 2.0 * k2.vi + 2.0 * k3.vi + k4.vi);
  r.qp.resize(y.qp.size());
  r.vip.resize(y.vip.size());
  for (size_t k = 0; k < y.qp.size(); ++k) {
    r.qp[k] = y.qp[k] + c * (k1.qp[k] + 2.0 * k2.qp[k] + 2.0 * k3.qp[k] + k4.qp[k]);
    r.vip[k] = y.vip[k] + c * (k1.vip[k] + 2.0 * k2.vip[k] + 2.0 * k3.vip[k] + k4.vip[k]);
  }
  return r;
}

VecX gather(const VecX& x, const std::vector<int>& idx) {
  VecX r(idx.size());
  for (size_t i = 0; i < idx.size(); ++i) r[i] = x[idx[i]];
  return r;
}

MatX gatherColumns(const MatX& A, const std::vector<int>& idx) {
  MatX r(A.rows(), idx.size());
  for (size_t i = 0; i < idx.size(); ++i) r.col(i) = A.col(idx[i]);
  return r;
}

/// Suggestion appended to every failure: the scheme is explicit.
std::string advice(const Assembler& as, const VecX& p, const VecX& q, const VecX& v, double h) {
  std::ostringstream os;
  os << "the Maggi/RK4 integrator is explicit: a stiff (flexible) model needs dt below ~2.8/omega_max";
  // Estimate omega_max [rad/s] from the unconstrained stiffness -dQ/dq and M at the last finite
  // state (an upper estimate: the constraints only remove modes). Dense: only small models.
  const int n = as.n();
  if (n <= 400 && q.allFinite() && v.allFinite()) {
    SparseAccumulator kq;
    kq.begin(n, n);
    as.addForceJacobian(kq, q, v, p, 1.0, 0.0, 0, 0, 0);  // adds -dQ/dq = K
    const MatX K = MatX(kq.finish());
    const MatX M = MatX(as.mass(p));
    Eigen::FullPivLU<MatX> mlu(M);
    if (mlu.isInvertible() && K.allFinite()) {
      const Eigen::VectorXcd ev = Eigen::EigenSolver<MatX>(mlu.solve(K), false).eigenvalues();
      double w2 = 0.0;
      for (int i = 0; i < ev.size(); ++i) w2 = std::max(w2, std::abs(ev[i]));
      if (w2 > 0 && std::isfinite(w2)) {
        const double w = std::sqrt(w2);
        os << " (here omega_max ~ " << w << " rad/s: dt below ~" << 2.8 / w << " s, dt = " << h
           << " s)";
      }
    }
  }
  os << "; use --integrator trapezoidal or a smaller --dt";
  return os.str();
}

/// How well a partition holds at a state: the reciprocal 1-norm condition estimate of
/// Phi_q,d, and the largest |entry| of B = Phi_q,d^-1 Phi_q,i (the map dq_d = -B dq_i).
struct BlockHealth {
  double rcond = 1.0, coupling = 0.0;
};

/// f(y) and its linearization for the sensitivities, under a fixed partition.
class Rhs {
 public:
  Rhs(const Assembler& as, const VecX& p, const IntegratorSettings& set, IntegratorStats& st)
      : as_(as), p_(p), set_(set), st_(st) {}

  void setPartition(const Partition& P) { P_ = P; }
  const Partition& partition() const { return P_; }

  /// Evaluates at y (time t [s], inside step `step`): the full state with sensitivities into s,
  /// y' into dy, and returns how well the partition holds there.
  BlockHealth eval(const Y& y, double t, long step, StateWithSens& s, Y& dy) const {
    const int n = as_.n(), m = as_.m();
    st_.residualEvaluations++;
    if (!y.q.allFinite() || !y.vi.allFinite()) fail(t, step, "positions or independent velocities");
    as_.setTime(t);  // drivers and time-dependent loads at the stage time
    State& x = s.x;
    x.t = t;
    x.q = y.q;
    x.v.resize(n);
    for (size_t i = 0; i < P_.indep.size(); ++i) x.v[P_.indep[i]] = y.vi[i];
    BlockHealth health;
    double& rcond = health.rcond;
    Eigen::PartialPivLU<MatX> lu;
    MatX Ji;
    if (m) {
      const MatX J = as_.phiQDense(y.q, p_);
      const MatX Jd = gatherColumns(J, P_.dep);
      Ji = gatherColumns(J, P_.indep);
      lu.compute(Jd);
      st_.factorizations++;
      rcond = lu.rcond();
      if (!(rcond > kSingular)) {
        std::ostringstream os;
        os << "maggi_rk4 step " << step << " at t = " << t
           << " s: the dependent block Phi_q,d of the constraint Jacobian is singular (reciprocal "
              "condition estimate "
           << rcond << "): the mechanism is at a singular configuration, or the solution has "
              "gone unstable; "
           << advice(as_, p_, ref_.q, ref_.v, set_.dt);
        throw NumericalError(os.str());
      }
      // dq_d = -B dq_i on the constraint surface: |B|max is how far the dependent coordinates
      // amplify the independent ones (unbounded as Phi_q,d turns singular, also when it is
      // 1 x 1, whose rcond is 1 up to the singularity itself).
      if (Ji.size()) health.coupling = lu.solve(Ji).lpNorm<Eigen::Infinity>();
      // Phi_q v + Phi_t = 0 for the dependent velocities [m/s].
      const VecX vd = -lu.solve(VecX(Ji * y.vi + as_.phiT(y.q, p_)));
      for (size_t i = 0; i < P_.dep.size(); ++i) x.v[P_.dep[i]] = vd[i];
    }
    solveAccelerations(as_, x, p_);  // a [m/s^2], lambda from the index-1 system
    st_.factorizations++;
    dy.q = x.v;
    dy.vi = gather(x.a, P_.indep);
    if (!x.v.allFinite() || !x.a.allFinite() || !x.lambda.allFinite())
      fail(t, step, "velocities, accelerations or multipliers");

    const size_t np = y.qp.size();
    s.dp.assign(np, State());
    dy.qp.resize(np);
    dy.vip.resize(np);
    for (size_t k = 0; k < np; ++k) {
      const int kk = static_cast<int>(k);
      State& d = s.dp[k];
      d.t = t;
      d.q = y.qp[k];
      d.v.resize(n);
      for (size_t i = 0; i < P_.indep.size(); ++i) d.v[P_.indep[i]] = y.vip[k][i];
      if (m) {
        // d/dp of Phi_q v + Phi_t = 0: Phi_q v_p = -((Phi_q v + Phi_t)_q q_p + Phi_qp v + Phi_tp).
        const VecX r = velocitySensitivityRhs(as_, y.q, x.v, p_, kk, d.q);
        const VecX vd = lu.solve(VecX(r - Ji * y.vip[k]));
        for (size_t i = 0; i < P_.dep.size(); ++i) d.v[P_.dep[i]] = vd[i];
      }
      solveAccelerationSensitivity(as_, x, p_, kk, d);  // a_p, lambda_p
      st_.factorizations++;
      dy.qp[k] = d.v;
      dy.vip[k] = gather(d.a, P_.indep);
      if (!d.q.allFinite() || !d.v.allFinite() || !d.a.allFinite() || !d.lambda.allFinite())
        fail(t, step, "sensitivities of parameter " + std::to_string(k));
    }
    return health;
  }

  [[noreturn]] void fail(double t, long step, const std::string& what) const {
    std::ostringstream os;
    os << "maggi_rk4 step " << step << " at t = " << t << " s (dt = " << set_.dt
       << " s): the " << what << " are not finite; "
       << advice(as_, p_, ref_.q, ref_.v, set_.dt);
    throw NumericalError(os.str());
  }

  /// The state at which messages estimate omega_max (the start: a blown-up state would
  /// give a meaningless stiffness).
  void setReference(const State& s) { ref_ = s; }
  const State& reference() const { return ref_; }

  static constexpr double kSingular = 1e-13;  ///< rcond below which Phi_q,d counts as singular

 private:
  const Assembler& as_;
  const VecX& p_;
  const IntegratorSettings& set_;
  IntegratorStats& st_;
  Partition P_;
  State ref_;
};

/// Gaussian elimination with full pivoting of Phi_q (m x n): the m pivot columns are the
/// dependent coordinates, the rest the f = n - m independent ones.
///
/// Ties are broken deterministically: any candidate within kPivotTie (relative) of the largest
/// remaining entry counts as largest, and the lowest coordinate index wins. Symmetric
/// mechanisms (the five-bar) have exact ties in Phi_q; plain full pivoting would then pick
/// the partition by round-off, and a parameter perturbation of 1e-5 could flip it, so the
/// discrete solution would not be a smooth function of p (finite differences of the scheme
/// would disagree with its exact derivative). A pivot 1% below the largest costs nothing in
/// conditioning.
Partition choosePartition(const Assembler& as, const VecX& q, const VecX& p, double t, long step,
                          IntegratorStats& st) {
  constexpr double kPivotTie = 1e-2;
  constexpr double kRankTol = 1e-12;  // pivot below this times max|Phi_q|: rank deficient
  const int n = as.n(), m = as.m();
  Partition P;
  if (m == 0) {
    for (int j = 0; j < n; ++j) P.indep.push_back(j);
    return P;
  }
  MatX A = as.phiQDense(q, p);
  if (!A.allFinite()) {
    std::ostringstream os;
    os << "maggi_rk4 step " << step << " at t = " << t << " s: the constraint Jacobian is not finite";
    throw NumericalError(os.str());
  }
  st.factorizations++;
  const double scale = A.lpNorm<Eigen::Infinity>();
  std::vector<bool> isDep(n, false);
  for (int k = 0; k < m; ++k) {
    // Largest remaining entry (rows k.., columns not yet pivots).
    double big = 0.0;
    for (int j = 0; j < n; ++j)
      if (!isDep[j]) big = std::max(big, A.col(j).tail(m - k).lpNorm<Eigen::Infinity>());
    if (!(big > kRankTol * scale)) {
      std::ostringstream os;
      os << "maggi_rk4 step " << step << " at t = " << t << " s: the constraint Jacobian Phi_q has rank "
         << k << " < m = " << m
         << " (redundant constraints or a singular configuration): no set of dependent coordinates "
            "exists; check the constraints, or use --integrator idas";
      throw NumericalError(os.str());
    }
    int pr = -1, pc = -1;
    for (int j = 0; j < n && pc < 0; ++j) {
      if (isDep[j]) continue;
      for (int i = k; i < m; ++i)
        if (std::abs(A(i, j)) >= (1.0 - kPivotTie) * big) {
          pr = i;
          pc = j;
          break;
        }
    }
    A.row(k).swap(A.row(pr));
    isDep[pc] = true;
    for (int i = k + 1; i < m; ++i) A.row(i) -= (A(i, pc) / A(k, pc)) * A.row(k);
  }
  for (int j = 0; j < n; ++j) (isDep[j] ? P.dep : P.indep).push_back(j);
  return P;
}

/// ODE state of a full state (with sensitivities) under partition P.
Y toY(const StateWithSens& s, const Partition& P) {
  Y y;
  y.q = s.x.q;
  y.vi = gather(s.x.v, P.indep);
  for (const State& d : s.dp) {
    y.qp.push_back(d.q);
    y.vip.push_back(gather(d.v, P.indep));
  }
  return y;
}

}  // namespace

IntegratorStats integrateMaggi(const Assembler& as, const VecX& p, StateWithSens start,
                               const IntegratorSettings& set, Observer& obs) {
  return integrateMaggi(as, p, std::move(start), set, obs, MaggiOptions{}, nullptr);
}

IntegratorStats integrateMaggi(const Assembler& as, const VecX& p, StateWithSens start,
                               const IntegratorSettings& set, Observer& obs,
                               const MaggiOptions& opt, MaggiReport* report) {
  const int m = as.m();
  const double h = set.dt;
  if (!(h > 0)) throw InputError("integrator maggi_rk4: needs a positive fixed step dt");
  if (!masslessCoordinates(as, p).empty())  // an explicit ODE needs a nonsingular reduced mass
    throw InputError("integrator maggi_rk4: the model has massless parts (inertia: none), whose "
                     "equilibrium equations an explicit scheme cannot solve; use idas, bdf1, "
                     "trapezoidal or generalized_alpha");
  const double t0 = start.x.t;
  const long nsteps = fixedStepCount(set.tEnd - t0, h);
  const long every = frameEvery(set);
  const double maxDrift =
      opt.maxConstraintDrift > 0
          ? opt.maxConstraintDrift
          : 1e-2 * std::pow(std::max(1.0, start.x.q.lpNorm<Eigen::Infinity>()), 2);
  IntegratorStats st;
  Rhs f(as, p, set, st);

  auto repartition = [&](const VecX& q, double t, long step) {
    f.setPartition(choosePartition(as, q, p, t, step, st));
    if (report) {
      report->partitionTimes.push_back(t);
      report->independent.push_back(f.partition().indep);
    }
  };
  repartition(start.x.q, t0, 0);
  f.setReference(start.x);
  Y y = toY(start, f.partition());
  StateWithSens cur;  // full state at y, also the first stage derivative of the next step
  Y k1, k2, k3, k4;
  BlockHealth block = f.eval(y, t0, 0, cur, k1);
  double condAtPartition = 1.0 / block.rcond, couplingAtPartition = block.coupling;
  double errorSum = 0.0, errorMax = 0.0, errorMaxTime = t0;  // the local error estimates below
  st.maxConstraintViolation = m ? as.phi(cur.x.q, p).lpNorm<Eigen::Infinity>() : 0.0;
  beginRun(obs, cur);

  StateWithSens stage;
  for (long step = 1; step <= nsteps; ++step) {
    const double t = t0 + (step - 1) * h;  // step start; not accumulated: frames stay exact
    const double cond = 1.0 / block.rcond;
    if (m && (cond > opt.maxCondition || cond > opt.maxConditionGrowth * condAtPartition ||
              block.coupling > opt.maxCouplingGrowth * std::max(1.0, couplingAtPartition))) {
      // Phi_q,d has degraded: choose the dependent set anew at q_n. The full velocities
      // satisfy Phi_q v = 0, so the new v_i = v[indep] reproduce them (and their derivatives).
      const std::vector<int> old = f.partition().indep;
      f.setPartition(choosePartition(as, cur.x.q, p, t, step, st));
      if (f.partition().indep != old) {
        if (report) {
          report->partitionTimes.push_back(t);
          report->independent.push_back(f.partition().indep);
        }
        y = toY(cur, f.partition());
        block = f.eval(y, t, step, cur, k1);
      }
      // Measure further growth from here (also when full pivoting kept the same set: it is
      // still the best one, and re-testing it every step would only cost factorizations).
      condAtPartition = 1.0 / block.rcond;
      couplingAtPartition = block.coupling;
    }
    f.eval(axpy(y, 0.5 * h, k1), t + 0.5 * h, step, stage, k2);
    f.eval(axpy(y, 0.5 * h, k2), t + 0.5 * h, step, stage, k3);
    f.eval(axpy(y, h, k3), t + h, step, stage, k4);
    y = rk4Combine(y, h, k1, k2, k3, k4);
    const double tn = step == nsteps ? set.tEnd : t0 + step * h;
    block = f.eval(y, tn, step, cur, k1);
    st.steps++;
    // Embedded third-order solution y + h/6 (k1 + 2 k2 + 2 k3 + f(y_{n+1})) (its order
    // conditions hold with c = (0, 1/2, 1/2, 1, 1)): y_{n+1} minus it is h/6 (k4 - f(y_{n+1})),
    // the step's local error estimate (of the third-order solution: an upper estimate of
    // RK4's), free since f(y_{n+1}) is the next step's first stage. Positions only.
    const double local = h / 6.0 * (k4.q - k1.q).lpNorm<Eigen::Infinity>();
    errorSum += local;
    if (!(local <= errorMax)) errorMax = local, errorMaxTime = tn;
    if (report) {
      report->errorEstimate = errorSum;
      report->maxStepErrorEstimate = errorMax;
      report->maxStepErrorTime = errorMaxTime;
    }
    if (m) {
      const double drift = as.phi(cur.x.q, p).lpNorm<Eigen::Infinity>();
      st.maxConstraintViolation = std::max(st.maxConstraintViolation, drift);
      if (!(drift <= maxDrift)) {
        std::ostringstream os;
        os << "maggi_rk4 step " << step << " at t = " << tn << " s (dt = " << h
           << " s): the constraint drift |Phi|_inf = " << drift << " exceeds " << maxDrift
           << " (the positions are integrated without projection; a drift this large means "
              "the solution is unstable or inaccurate); "
           << advice(as, p, f.reference().q, f.reference().v, h);
        throw NumericalError(os.str());
      }
    }
    endStep(obs, cur, st, step % every == 0 || step == nsteps);
  }
  return st;
}

}  // namespace flexsens
