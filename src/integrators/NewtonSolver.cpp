#include "integrators/NewtonSolver.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace flexsens {

namespace {

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

/// |a - b|_inf <= tol (1 + |a|_inf); false when the sizes differ.
bool sameTo(const VecX& a, const VecX& b, double tol) {
  return a.size() == b.size() && (a - b).lpNorm<Eigen::Infinity>() <= tol * (1.0 + a.lpNorm<Eigen::Infinity>());
}

}  // namespace

NewtonSolver::NewtonSolver(const IntegratorSettings& set, int n, int m, IntegratorStats& stats)
    : set_(set), n_(n), m_(m), st_(stats), modified_(set.newton == "modified"),
      anderson_(modified_ ? kAndersonDepth : 0, n + m, n), xk_(n + m) {}

bool NewtonSolver::factorizedNear(const VecX& q, const VecX& l, long step, double ca, double tol) const {
  return luStep_ == step && factoredCa_ == ca && lu_.factorized() && sameTo(q, luQ_, tol) && sameTo(l, luL_, tol);
}

void NewtonSolver::factorAt(StepEquations& eq, const VecX& qq, const VecX& ll, const char* how) {
  const double t = eq.time();
  const long step = eq.step();
  const double h = eq.scheme().h;
  lu_.factor(eq.matrix(acc_, qq, ll), [&] {
    std::ostringstream what;
    what << "Newton matrix at t = " << t << " s (step " << step << ", h = " << h << " s" << how << ")";
    return what.str();
  });
  st_.jacobianEvaluations++;
  factoredCa_ = eq.scheme().ca;
  luQ_ = qq;
  luL_ = ll;
  luStep_ = step;
}

/// The iterate at the start: the predictor and sigma lambda_n, with its residual.
void NewtonSolver::startAt(StepEquations& eq, VecX& r) {
  q_ = qPredicted_;
  lt_ = eq.sigma() * eq.old().lambda;
  r = eq.residual(q_, lt_);
}

// Newton from the predictor. With `backtrack`, an update that increases |r|_2 is halved
// (down to 1/64): the fallback when plain Newton fails, so every step plain Newton
// solves keeps exactly its path and result.
bool NewtonSolver::fullNewton(StepEquations& eq, bool backtrack) {
  VecX r;
  startAt(eq, r);
  lastResidual_ = r.lpNorm<Eigen::Infinity>();
  for (int it = 0; it < set_.maxNewtonIterations; ++it) {
    factorAt(eq, q_, lt_, backtrack ? ", with backtracking" : "");
    const VecX dx = lu_.solve(VecX(-r));
    st_.newtonIterations++;
    lastUpdate_ = dx.head(n_).lpNorm<Eigen::Infinity>();
    double s = 1.0;
    VecX qt = q_ + dx.head(n_), lnew = lt_ + dx.tail(m_);
    if (lastUpdate_ <= set_.newtonTol * (1.0 + qt.lpNorm<Eigen::Infinity>())) {
      q_ = qt;
      lt_ = lnew;
      return true;
    }
    VecX rt = eq.residual(qt, lnew);
    while (backtrack && s > 1.0 / 64 && !(rt.allFinite() && rt.norm() <= r.norm())) {
      s *= 0.5;
      qt = q_ + s * dx.head(n_);
      lnew = lt_ + s * dx.tail(m_);
      rt = eq.residual(qt, lnew);
    }
    q_ = qt;
    lt_ = lnew;
    r = rt;
    lastResidual_ = r.lpNorm<Eigen::Infinity>();
    lastUpdate_ *= s;
  }
  return false;
}

// Modified Newton: the factorization kept from earlier iterations or steps, refreshed at
// the current iterate when the contraction rate theta = |dq_k| / |dq_k-1| (same matrix)
// exceeds kRefreshRate (that update is dropped), when theta predicts more iterations than
// the budget left, or when h changed. The same convergence test as full Newton, made stricter
// by theta / (1 - theta) (the error left after a linearly converging update) should theta
// exceed 1/2. False: full Newton redoes the step. In a step after one whose chord contracted
// slower than kAndersonAbove, the chord steps are Anderson-accelerated.
bool NewtonSolver::modifiedNewton(StepEquations& eq) {
  anderson_.reset();  // its history belongs to this step's residual and this matrix
  double slowest = 0.0;
  VecX r;
  startAt(eq, r);
  lastResidual_ = r.lpNorm<Eigen::Infinity>();
  Chord chord;
  auto refresh = [&](bool atStart) {
    factorAt(eq, q_, lt_, "");
    chord = Chord{};
    chord.fresh = true;
    chord.stale = false;
    chord.atStart = atStart;
    anderson_.reset();
  };
  if (!lu_.factorized() || factoredCa_ != eq.scheme().ca || skipReuse_ > 0) refresh(true);
  for (int it = 0; it < set_.maxNewtonIterations; ++it) {
    // One plain solve: the matrix is in general an earlier iterate's, so refining the solve
    // against it buys nothing the next residual does not correct (satellite, 10 s: 11% of
    // the run).
    const VecX dx = lu_.solve(VecX(-r), false);
    st_.newtonIterations++;
    const double update = dx.head(n_).lpNorm<Eigen::Infinity>();
    const double theta = chord.previous > 0.0 ? update / chord.previous : 0.0;
    slowest = std::max(slowest, theta);
    if (theta > 0.0 && theta <= kRefreshRate) chord.confirmed = true;
    if (chord.previous == 0.0) chord.first = update;
    // Diverging or contracting slowly: drop the update (a slow one can lead away, as
    // on the satellite's light spring nodes) and refresh.
    if (!dx.allFinite() || theta > kRefreshRate) {
      if (chord.fresh) {
        return false;
      }
      const bool restart = rejectedChord(chord);
      if (restart) startAt(eq, r);
      refresh(restart);
      continue;
    }
    if (slowChord_) {  // Anderson acceleration of the chord step (AndersonMixing.hpp)
      st_.acceleratedIterations++;
      xk_ << q_, lt_;
      const VecX stepped = anderson_.step(xk_, dx);
      q_ += stepped.head(n_);
      lt_ += stepped.tail(m_);
    } else {
      q_ += dx.head(n_);
      lt_ += dx.tail(m_);
    }
    chord.fresh = false;
    lastUpdate_ = update;
    const double tol = set_.newtonTol * (1.0 + q_.lpNorm<Eigen::Infinity>());
    if (update * std::max(1.0, theta / (1.0 - theta)) <= tol) {
      slowChord_ = slowest > kAndersonAbove;
      lastCorrection_ = (q_ - qPredicted_).lpNorm<Eigen::Infinity>();
      return true;
    }
    r = eq.residual(q_, lt_);
    lastResidual_ = r.lpNorm<Eigen::Infinity>();
    chord.previous = update;
    // Iterations still needed at this rate: theta^k |dq| <= tol.
    const double needed = theta > 0.0 ? std::log(tol / update) / std::log(theta) : 0.0;
    if (it + 1 + needed > set_.maxNewtonIterations) refresh(false);
  }
  return false;
}

// A chord dropped after its first update or later: restart the step from the start point
// (true) or refresh at the current iterate (false). A matrix of an earlier step may have led
// away with its first update (the satellite's light spring nodes, thrown metres off by a
// matrix of stiffer days): unless a contracting update confirmed it, or it is no larger than
// twice the last step's whole correction from its predictor, the step restarts with a fresh
// matrix at the start point. (The thin shell panel at n = 24495: a first update of the
// predictor's size takes out its membrane error, after which the matrix at that iterate
// converges at once and any other contracts at 0.55-0.8; restarts doubled the factorizations.)
bool NewtonSolver::rejectedChord(const Chord& chord) {
  if (!chord.stale || chord.confirmed || chord.first <= 2.0 * lastCorrection_) return false;
  staleFailed_ = true;
  return true;
}

bool NewtonSolver::modifiedWithBackoff(StepEquations& eq) {
  bool converged = false;
  staleFailed_ = false;
  const bool startedStale = skipReuse_ == 0;
  try {
    converged = modifiedNewton(eq);
  } catch (const NumericalError&) {  // singular refreshed matrix: full Newton decides below
  }
  if (!converged) st_.convergenceFailures++;
  if (skipReuse_ > 0) {
    --skipReuse_;
  } else if (startedStale && (staleFailed_ || !converged)) {
    skipReuse_ = backoff_;
    backoff_ = std::min(2 * backoff_, 32);
  } else {
    backoff_ = 1;
  }
  return converged;
}

bool NewtonSolver::fallbacks(StepEquations& eq, const VecX& qTaylor, bool converged) {
  if (!converged) {
    try {
      converged = fullNewton(eq, false);
    } catch (const NumericalError&) {  // singular Newton matrix on the way: retry below
    }
  }
  if (!converged) {
    try {
      converged = fullNewton(eq, true);
    } catch (const NumericalError& e) {  // e.g. an element turned inside out: say when
      std::ostringstream os;
      os << set_.type << " step " << eq.step() << " at t = " << eq.time() << " s (h = " << eq.scheme().h
         << " s): " << e.what();
      throw NumericalError(os.str());
    }
  }
  const VecX& qOld = eq.old().q;
  if (!converged && qTaylor != qOld) {
    qPredicted_ = startAtOld_ ? qTaylor : VecX(qOld);
    for (bool backtrack : {false, true}) {
      try {
        converged = converged || fullNewton(eq, backtrack);
      } catch (const NumericalError&) {  // reported as not converged below
      }
    }
    if (converged) startAtOld_ = !startAtOld_;
  }
  return converged;
}

// Predictor (the caller's qTaylor): a Taylor expansion of the previous step for the
// trapezoidal rule; BDF-1 and generalized-alpha are the schemes for stiff models and start
// from q_n + h v_n: stiff light parts (the satellite's prestressed springs, node masses ~1e-3
// kg, accelerations ~1e6 m/s^2) would put h^2 a_n / 2 metres away, where the Newton matrix is
// singular. Last resort: Newton from the other start, q_n itself, when an unresolved fast mode
// (ANCF springs' slopes released from a prestressed shape) left a velocity that throws
// q_n + h v_n out of Newton's reach. A start that rescued a step becomes the first one tried
// (startAtOld); a model the predictor serves never sees the other.
bool NewtonSolver::solve(StepEquations& eq, const VecX& qTaylor) {
  qPredicted_ = startAtOld_ ? eq.old().q : qTaylor;
  lastUpdate_ = lastResidual_ = 0.0;
  const bool converged = modified_ && modifiedWithBackoff(eq);
  return fallbacks(eq, qTaylor, converged);
}

}  // namespace flexsens
