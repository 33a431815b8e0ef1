#include "integrators/FixedStepper.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "integrators/InitialState.hpp"
#include "integrators/StepEnd.hpp"
#include "integrators/TimeGrid.hpp"

namespace flexsens {

namespace {

/// A failure message names the growth of the accelerations when the last step's |a|_inf
/// exceeds this multiple of the largest over the first kEarlySteps steps.
constexpr double kAccelerationGrowth = 100.0;
constexpr long kEarlySteps = 50;

/// The massless coordinates; InputError for the midpoint rule with any (their equilibrium at
/// the midpoint oscillates).
std::vector<int> masslessFor(const Assembler& as, const VecX& p, const Scheme& sc) {
  std::vector<int> massless = masslessCoordinates(as, p);
  if (sc.midpoint && !massless.empty())
    throw InputError("integrator midpoint: the model has massless parts (inertia: none), whose equilibrium "
                     "the midpoint rule would hold at the mid-step, leaving the end state to oscillate; use "
                     "trapezoidal, bdf1, generalized_alpha or idas");
  return massless;
}

}  // namespace

FixedStepper::FixedStepper(const Assembler& as, const VecX& p, StateWithSens start, const IntegratorSettings& set)
    : FixedStepper(as, p, std::move(start), set, 0, -1.0) {}

FixedStepper::FixedStepper(const Assembler& as, const VecX& p, StateWithSens start, const IntegratorSettings& set,
                           long firstStep, double runStart)
    : as_(as), p_(p), set_(set), sc_(set_), massless_(masslessFor(as, p_, sc_)),
      nsteps_(fixedStepCount(set_.tEnd - (firstStep ? runStart : start.x.t), set_.dt)), every_(frameEvery(set_)),
      t0_(firstStep ? runStart : start.x.t), eq_(as, p_, sc_, st_.residualEvaluations),
      newton_(set_, as.n(), as.m(), st_), sens_(st_), step_(firstStep), cur_(std::move(start)) {
  // Velocity and acceleration projections (trapezoidal rule, generalized-alpha), on request.
  if (set_.projections) projection_ = std::make_unique<MotionProjection>(as_, p_, massless_);
  // Growth of the accelerations, for the failure message: the trapezoidal rule (generalized-
  // alpha at rho_inf 1) carries a_n+1 = 4 (q_n+1 - q_n) / h^2 - 4 v_n / h - a_n undamped, and
  // along the constraint directions nothing else holds it; with nonlinear constraints that
  // part grows (massless satellite, dt 1e-3 s: |a|_inf 3e3 at step 100, 1e6 at step 900)
  // until Newton fails. Massless coordinates are left out: their a is that recurrence alone.
  counted_.assign(size_t(as_.n()), 1);
  for (int i : massless_) counted_[size_t(i)] = 0;
  as_.setTime(cur_.x.t);
  st_.maxConstraintViolation = as_.m() ? as_.phi(cur_.x.q, p_).lpNorm<Eigen::Infinity>() : 0.0;
}

double FixedStepper::largestAcceleration(const VecX& a, int& where) const {
  double r = 0.0;
  for (int i = 0; i < as_.n(); ++i)
    if (counted_[size_t(i)] && std::abs(a[i]) > r) r = std::abs(a[i]), where = i;
  return r;
}

void FixedStepper::advance(double t, Observer& obs) {
  while (!done() && cur_.x.t < t) {
    step();
    endStep(obs, cur_, st_, frameDue());
  }
}

void FixedStepper::step() {
  // The state before the step moves to prev_ (the storage of two steps ago comes back, to be
  // overwritten by the new state: no heap traffic), where the step's equations refer to it.
  std::swap(prev_, cur_.x);
  ++step_;
  try {
    takeStep();
  } catch (...) {  // current() stays the state reached
    std::swap(prev_, cur_.x);
    --step_;
    throw;
  }
}

void FixedStepper::takeStep() {
  const double h = set_.dt;
  const State& old = prev_;
  // Not accumulated: frame times stay exact multiples; the last one is t_end itself.
  const double t = step_ == nsteps_ ? set_.tEnd : t0_ + step_ * h;
  // Index 3: equilibrium, loads and the drivers' Phi(q, t) all at t_{n+1} (the sensitivity
  // solve differentiates the same equations, at the same time).
  eq_.begin(old, t, step_);
  // The predictor (NewtonSolver::solve says why this one, and what it falls back to).
  const VecX qTaylor = old.q + h * old.v + (sc_.trapezoidal ? 0.5 * h * h : 0.0) * old.a;
  if (!newton_.solve(eq_, qTaylor)) failNotConverged(old, t);
  State next = eq_.solution(newton_.q(), newton_.l());
  if (!next.q.allFinite() || !next.v.allFinite() || !next.lambda.allFinite()) {
    std::ostringstream os;
    os << set_.type << " step " << step_ << " at t = " << t << " s: the solution is not finite; "
       << "try a smaller --dt";
    throw NumericalError(os.str());
  }
  dnext_.resize(cur_.dp.size());  // the storage of two steps ago, reused (no heap traffic)
  if (!cur_.dp.empty()) sens_.solve(eq_, newton_, next, cur_.dp);
  // The step's equations, which the sensitivity right-hand sides differentiate, hold with the
  // scheme's a and v; the projections change them only now.
  if (projection_) projection_->project(next, step_);
  next.pseudoAcc = sc_.nextPseudo(old, next.a);
  sens_.finish(eq_, next, projection_.get(), cur_.dp, dnext_);
  finishStep(std::move(next));
}

void FixedStepper::finishStep(State&& next) {
  if (step_ <= kEarlySteps) {
    int where = -1;
    aEarly_ = std::max(aEarly_, largestAcceleration(next.a, where));
  }
  cur_.x = std::move(next);
  std::swap(cur_.dp, dnext_);
  st_.steps++;
  if (as_.m()) st_.maxConstraintViolation =
      std::max(st_.maxConstraintViolation, as_.phi(cur_.x.q, p_).lpNorm<Eigen::Infinity>());
  st_.factorizations = newton_.lu().factorizations();
  st_.luFill = newton_.lu().maxFill();
  st_.choleskyFactorizations = newton_.lu().choleskyFactorizations();
  st_.ldltFactorizations = newton_.lu().ldltFactorizations();
  st_.factorizationSeconds = newton_.lu().factorSeconds();
}

void FixedStepper::failNotConverged(const State& old, double t) const {
  std::ostringstream os;
  os << set_.type << " step " << step_ << " at t = " << t << " s (h = " << set_.dt
     << " s): Newton did not converge in " << set_.maxNewtonIterations
     << " iterations, also with backtracking and from both q_n + h v_n and q_n (last update |dq|_inf = "
     << newton_.lastUpdate() << " m, residual " << newton_.lastResidual() << "); try a smaller --dt"
     << (set_.type == "generalized_alpha" ? ", a smaller rho_inf (more damping)" : "") << " or a looser newton_tol";
  int where = -1;
  const double aLast = largestAcceleration(old.a, where);
  if (aEarly_ > 0.0 && aLast > kAccelerationGrowth * aEarly_) {
    os << "; the accelerations grew from |a|_inf = " << aEarly_ << " (first " << kEarlySteps << " steps) to "
       << aLast << " at the last step (in " << as_.model().coordinateLabel(where) << "): ";
    if (sc_.trapezoidal || (set_.type == "generalized_alpha" && set_.rhoInf >= 1.0))
      os << "this scheme leaves the accelerations along the constraint directions undamped and nonlinear "
            "constraints make them grow; project them (integrator.projections: true, --projections on) or "
            "use generalized_alpha with rho_inf < 1, which damps them";
    else
      os << "an unresolved mode or the constraint directions gained energy; try more damping (generalized_alpha "
            "with a smaller rho_inf) or a smaller dt";
  }
  throw NumericalError(os.str());
}

const SpMat& FixedStepper::jacobianAtSolution() {
  as_.setTime(eq_.time());
  eq_.matrix(replayAcc_, newton_.q(), newton_.l());
  return replayAcc_.matrix();
}

}  // namespace flexsens
