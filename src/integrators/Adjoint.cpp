#include "integrators/Adjoint.hpp"

#include <chrono>
#include <cmath>
#include <sstream>

#include "core/Interrupt.hpp"
#include "core/MemoryBudget.hpp"
#include "core/SparseLU.hpp"
#include "integrators/FixedStepper.hpp"
#include "integrators/Scheme.hpp"
#include "integrators/StepEnd.hpp"
#include "integrators/StepEquations.hpp"
#include "integrators/TimeGrid.hpp"

namespace flexsens {

namespace {

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// The scheme's linear maps between steps as scalars (each is a multiple of the identity):
///   abar = av v_n + aa a_n + aw w_n,  vbar = bv v_n + ba a_n + bw w_n   (Scheme::history)
///   w_{n+1} = c1 a_{n+1} + c2 a_n + c3 w_n                              (Scheme::nextPseudo)
/// read off the scheme's own functions on unit one-coordinate states.
struct SchemeMaps {
  double av = 0, aa = 0, aw = 0, bv = 0, ba = 0, bw = 0, c1 = 0, c2 = 0, c3 = 0;
  explicit SchemeMaps(const Scheme& sc) {
    auto unit = [](double v, double a, double w) {
      State s;
      s.q = VecX::Zero(1);
      s.v = VecX::Constant(1, v);
      s.a = VecX::Constant(1, a);
      s.pseudoAcc = VecX::Constant(1, w);
      return s;
    };
    VecX abar, vbar;
    auto hist = [&](double v, double a, double w, double& ca, double& cb) {
      sc.history(unit(v, a, w), abar, vbar);
      ca = abar[0];
      cb = vbar[0];
    };
    hist(1, 0, 0, av, bv);
    hist(0, 1, 0, aa, ba);
    hist(0, 0, 1, aw, bw);
    auto next = [&](double aNext, double a, double w) {
      const VecX r = sc.nextPseudo(unit(0, a, w), VecX::Constant(1, aNext));
      return r.size() ? r[0] : 0.0;
    };
    c1 = next(1, 0, 0);
    c2 = next(0, 1, 0);
    c3 = next(0, 0, 1);
  }
};

/// The adjoint of the carried state (q, v, a, w), one column per objective.
struct Adjoints {
  MatX q, v, a, w;
  Adjoints(Eigen::Index n, Eigen::Index cols)
      : q(MatX::Zero(n, cols)), v(MatX::Zero(n, cols)), a(MatX::Zero(n, cols)), w(MatX::Zero(n, cols)) {}
};

/// One step of the sweep: from the adjoints of y_{n+1} to those of y_n, adding -W^T R_p.
class AdjointStep {
 public:
  AdjointStep(const Assembler& as, const VecX& p, const IntegratorSettings& set)
      : as_(as), p_(p), sc_(set), maps_(sc_), eq_(as, p_, sc_, residuals_) {}

  void apply(const State& old, const State& next, long step, Adjoints& mu, MatX& gradient);
  long factorizations() const { return lu_.factorizations(); }

 private:
  MatX solveTransposed(const SpMat& A, const MatX& rhs) const;
  void addParameterTerms(const State& next, const VecX& qf, const VecX& vf, const VecX& lt, const MatX& W,
                         MatX& gradient);

  const Assembler& as_;
  const VecX& p_;
  const Scheme sc_;
  const SchemeMaps maps_;
  long residuals_ = 0;
  StepEquations eq_;
  SparseAccumulator acc_, kv_;
  SparseLU lu_;
  VecX forceP_, reactionP_, phiMid_, phiP_, phiQPTl_, inertiaP_;
};

/// A^T X = rhs with A's LU, refined twice against A^T (KLU's transposed solve is plain).
MatX AdjointStep::solveTransposed(const SpMat& A, const MatX& rhs) const {
  MatX X(rhs.rows(), rhs.cols());
  const SpMat At = A.transpose();
  for (Eigen::Index i = 0; i < rhs.cols(); ++i) {
    VecX x = lu_.solveTransposed(VecX(rhs.col(i)));
    for (int r = 0; r < 2; ++r) x += lu_.solveTransposed(VecX(rhs.col(i) - At * x));
    X.col(i) = x;
  }
  return X;
}

/// gradient(k, i) += W_i . X0_k, X0_k = -dr/dp_k at fixed x_{n+1} and y_n (the forward
/// sensitivity's right-hand side without history: integrators/StepSensitivity.cpp).
void AdjointStep::addParameterTerms(const State& next, const VecX& qf, const VecX& vf, const VecX& lt, const MatX& W,
                                    MatX& gradient) {
  const Eigen::Index n = as_.n(), m = as_.m();
  const double t = eq_.time(), sigma = eq_.sigma();
  for (Eigen::Index k = 0; k < gradient.rows(); ++k) {
    as_.setTime(sc_.forceTime(t));
    as_.forceParamDerivative(qf, vf, p_, int(k), forceP_);
    if (sc_.fw != 1.0) as_.constraintParamTerms(qf, p_, int(k), lt, phiMid_, reactionP_);
    as_.setTime(t);
    as_.constraintParamTerms(next.q, p_, int(k), lt, phiP_, phiQPTl_);
    if (sc_.fw != 1.0) phiQPTl_ = reactionP_;
    as_.massParamDerivativeTimes(p_, int(k), next.a, inertiaP_);
    const VecX top = -(sigma * (inertiaP_ - forceP_) + phiQPTl_);
    for (Eigen::Index i = 0; i < W.cols(); ++i)
      gradient(k, i) += W.col(i).head(n).dot(top) - (m ? W.col(i).tail(m).dot(phiP_) : 0.0);
  }
}

void AdjointStep::apply(const State& old, const State& next, long step, Adjoints& mu, MatX& gradient) {
  const Eigen::Index n = as_.n(), m = as_.m(), cols = mu.q.cols();
  const double t = next.t, sigma = eq_.sigma(), fw = sc_.fw;
  eq_.begin(old, t, step);
  const VecX lt = sigma * next.lambda;
  const SpMat A = eq_.matrix(acc_, next.q, lt);  // the Newton matrix at the converged point
  lu_.factor(A, [t]() { return "adjoint step matrix at t = " + std::to_string(t) + " s"; });
  // Adjoint of q_{n+1} through v_{n+1} = cv q + vh, a_{n+1} = ca q + ah, w_{n+1} = c1 a_{n+1} + ...
  const MatX aEff = mu.a + maps_.c1 * mu.w;
  MatX rhs = MatX::Zero(n + m, cols);
  rhs.topRows(n) = mu.q + sc_.cv * mu.v + sc_.ca * aEff;
  const MatX W = solveTransposed(A, rhs);
  const VecX qf = eq_.forcePositions(next.q);  // copies: the next calls reuse the buffers
  const VecX vf = eq_.forceVelocities(next.v);
  addParameterTerms(next, qf, vf, lt, W, gradient);
  // R_y^T: the residual's first block changes by sigma (M ah - dQ) + (1 - fw) H dq_n at fixed x.
  const MatX U = -W.topRows(n);
  as_.setTime(sc_.forceTime(t));
  kv_.begin(n, n);
  as_.addForceJacobian(kv_, qf, vf, p_, 0.0, -1.0, 0, 0, 0);
  const SpMat dQdv = kv_.finish();
  const MatX dQdvTU = dQdv.transpose() * U;
  const MatX lAh = aEff + sigma * (eq_.mass() * U);  // M symmetric
  const MatX lVh = mu.v - sigma * fw * dQdvTU;
  MatX extraQ = MatX::Zero(n, cols), extraV = MatX::Zero(n, cols);
  if (fw != 1.0) {  // midpoint: the forces and the reaction see q_n and v_n too
    kv_.begin(n, n);
    as_.addForceJacobian(kv_, qf, vf, p_, -1.0, 0.0, 0, 0, 0);
    const SpMat dQdq = kv_.finish();
    extraQ = -sigma * (1.0 - fw) * (dQdq.transpose() * U);
    for (Eigen::Index i = 0; i < cols; ++i)
      extraQ.col(i) += (1.0 - fw) * as_.hessianTimes(qf, p_, lt, VecX(U.col(i)));
    extraV = -sigma * (1.0 - fw) * dQdvTU;
  }
  const SchemeMaps& s = maps_;
  const MatX wNext = mu.w;
  mu.q = -sc_.ca * lAh - sc_.cv * lVh + extraQ;
  mu.v = s.av * lAh + s.bv * lVh + extraV;
  mu.a = s.aa * lAh + s.ba * lVh + s.c2 * wNext;
  mu.w = s.aw * lAh + s.bw * lVh + s.c3 * wNext;
}

}  // namespace

bool hasAdjoint(const std::string& integrator) {
  return integrator == "trapezoidal" || integrator == "bdf1" || integrator == "generalized_alpha" ||
         integrator == "midpoint";
}

long checkpointInterval(long steps, double stateBytes, long requested) {
  if (requested > 0) return std::min(requested, std::max(steps, 1L));
  if (double(steps + 1) * stateBytes <= 0.25 * memoryBudget()) return std::max(steps, 1L);
  const long k = long(std::ceil(std::sqrt(double(steps + 1))));
  std::ostringstream what;
  what << "the adjoint's checkpoints (" << steps / k + 1 << " states) and one recomputed segment (" << k
       << " states) of " << steps << " steps";
  requireMemory(double(steps / k + 1 + k) * stateBytes, what.str(), "use fewer steps (a larger dt)");
  return k;
}

DiscreteAdjoint::DiscreteAdjoint(const Assembler& as, const VecX& p, const StateWithSens& start,
                                 const IntegratorSettings& set, long checkpointEvery)
    : as_(as), p_(p), start_(start), set_(set) {
  if (!hasAdjoint(set.type))
    throw InputError("integrator " + set.type + " has no discrete adjoint; the methods that have one: " +
                     kAdjointIntegrators + " (or use --method forward)");
  if (set.projections)
    throw InputError("the adjoint does not differentiate the velocity and acceleration projections "
                     "(integrator.projections: true); switch them off or use --method forward");
  steps_ = fixedStepCount(set.tEnd - start.x.t, set.dt);
  const double n = as.n(), m = as.m();
  stateBytes_ = doubles((set.type == "generalized_alpha" ? 5.0 : 4.0) * n + m);
  st_.checkpointEvery = checkpointInterval(steps_, stateBytes_, checkpointEvery);
}

void DiscreteAdjoint::addPeak(size_t held) {
  st_.peakStates = std::max(st_.peakStates, long(held));
  st_.peakStateBytes = double(st_.peakStates) * stateBytes_;
}

IntegratorStats DiscreteAdjoint::forward(Observer& obs) {
  const auto t0 = std::chrono::steady_clock::now();
  const long k = st_.checkpointEvery;
  FixedStepper stepper(as_, p_, StateWithSens{start_.x, {}}, set_);
  beginRun(obs, stepper.current());
  checkpoints_.assign(1, stepper.current().x);
  tail_.assign(1, stepper.current().x);
  while (!stepper.done()) {
    stepper.step();
    endStep(obs, stepper.current(), stepper.statistics(), stepper.frameDue());
    const long n = stepper.stepIndex();
    if (n % k == 0 && n < steps_) {  // a checkpoint starts the next segment
      checkpoints_.push_back(stepper.current().x);
      tail_.clear();
    }
    tail_.push_back(stepper.current().x);
    addPeak(checkpoints_.size() + tail_.size());
  }
  st_.checkpoints = long(checkpoints_.size());
  st_.forwardSeconds = secondsSince(t0);
  return stepper.statistics();
}

std::vector<State> DiscreteAdjoint::recompute(long c, long len) {
  FixedStepper stepper(as_, p_, StateWithSens{checkpoints_[size_t(c / st_.checkpointEvery)], {}}, set_, c,
                       start_.x.t);
  std::vector<State> seg{stepper.current().x};
  for (long j = 0; j < len; ++j) {
    stepper.step();
    seg.push_back(stepper.current().x);
  }
  st_.recomputedSteps += len;
  return seg;
}

MatX DiscreteAdjoint::backward(int objectives, const Source& source) {
  const auto t0 = std::chrono::steady_clock::now();
  const Eigen::Index n = as_.n(), np = p_.size();
  const long k = st_.checkpointEvery;
  AdjointStep step(as_, p_, set_);
  Adjoints mu(n, objectives);
  MatX gradient = MatX::Zero(np, objectives);
  for (long seg = long(checkpoints_.size()) - 1; seg >= 0; --seg) {
    const long c = seg * k, len = std::min(k, steps_ - c);
    std::vector<State> states = seg + 1 == long(checkpoints_.size()) ? std::move(tail_) : recompute(c, len);
    addPeak(checkpoints_.size() + states.size());
    for (long j = len; j >= 1; --j) {  // step c + j: states[j - 1] -> states[j]
      source(c + j, states[size_t(j)], mu.q, mu.v);
      step.apply(states[size_t(j - 1)], states[size_t(j)], c + j, mu, gradient);
      st_.backwardSteps++;
      if (const int sig = interruptSignal()) throw Interrupted(sig, states[size_t(j - 1)].t);
    }
    if (seg == 0) source(0, states[0], mu.q, mu.v);
  }
  // The start: w_0 = a_0 (generalized-alpha), then the initial sensitivities.
  mu.a += mu.w;
  startAdjoints_ = {std::move(mu.q), std::move(mu.v), std::move(mu.a)};
  for (size_t kk = 0; kk < start_.dp.size(); ++kk) gradient.row(Eigen::Index(kk)) += startAdjoints_.termsOf(start_.dp[kk]);
  st_.backwardFactorizations = step.factorizations();
  st_.backwardSeconds = secondsSince(t0);
  return gradient;
}

}  // namespace flexsens
