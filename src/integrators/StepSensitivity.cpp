#include "integrators/StepSensitivity.hpp"

#include <string>

#include "core/PreconditionedSolve.hpp"

namespace flexsens {

namespace {

/// Sensitivity solves with the kept LU: normwise backward error |b - A x| / (|A| |x| + |b|)
/// (inf-norms) to reach, and the applications of the LU allowed before A is factorized. With
/// Anderson acceleration modified Newton keeps an older LU, and 12 applications let SAT1's
/// sensitivity solve fall back to factoring 192 times in 500 steps; 20 / 30: 3 / 0.
constexpr double kSensitivityBackwardError = 1e-13;
constexpr int kSensitivitySolves = 30;
/// Iterates whose (q, sigma lambda) differ by at most this much relative (inf-norm, per block)
/// give the same Newton matrix to round-off (see solve()).
constexpr double kSameMatrix = 1e-13;

}  // namespace

void SensitivitySolver::solve(StepEquations& eq, NewtonSolver& newton, const State& next,
                              const std::vector<State>& dold) {
  const Assembler& as = eq.assembler();
  const VecX& q = newton.q();
  const VecX& lt = newton.l();
  const VecX& qf = eq.forcePositions(q);
  const VecX& vf = eq.forceVelocities(next.v);
  // The LU Newton kept is of the matrix at the converged point when this step factorized
  // it at an iterate within round-off of that point (full Newton's last update: 1e-14 to
  // 1e-16 relative on the flexible five-bar refined, n >= 20; 1e-10 to 1e-15 on the
  // satellite; ~1e-11 at the five-bar's n = 8, which stops after 2 iterations): the matrix
  // assembled there would be the same to its last digits. Then the right-hand sides are
  // solved with it (refined against the matrix it factorized) and the assembly is skipped:
  // it was 0.15 of a one-parameter five-bar run (refine 16). With the last iterate's
  // matrix at newton_tol instead the sensitivities moved by 5e-7 relative: not exact.
  const bool luAtSolution = newton.factorizedNear(q, lt, eq.step(), eq.scheme().ca, kSameMatrix);
  if (luAtSolution) {
    st_.sensitivityReusedLu++;
  } else {
    newtonMatrix(as, newton.accumulator(), q, qf, vf, lt, eq.parameters(), eq.scheme(), eq.time());
    st_.jacobianEvaluations++;
  }
  const SpMat& A = newton.accumulator().matrix();  // its values are read only when assembled here
  rightHandSides(eq, qf, vf, lt, next, dold);
  solveColumns(A, newton.lu(), luAtSolution, eq.time());
}

void SensitivitySolver::rightHandSides(StepEquations& eq, const VecX& qf, const VecX& vf, const VecX& lt,
                                       const State& next, const std::vector<State>& dold) {
  const Assembler& as = eq.assembler();
  const Scheme& sc = eq.scheme();
  const VecX& p = eq.parameters();
  const VecX& q = next.q;
  const int n = as.n(), m = as.m();
  const double sigma = eq.sigma();
  const double t = eq.time();
  as.setTime(sc.forceTime(t));  // the force derivatives below: at the force point
  kv_.begin(n, n);
  as.addForceJacobian(kv_, qf, vf, p, 0.0, -1.0, 0, 0, 0);
  const SpMat dQdv = kv_.finish();
  SpMat dQdq;  // midpoint: the forces see q_n too
  if (sc.fw != 1.0) {
    kv_.begin(n, n);
    as.addForceJacobian(kv_, qf, vf, p, -1.0, 0.0, 0, 0, 0);
    dQdq = kv_.finish();
  }
  const Eigen::Index np = Eigen::Index(dold.size());
  X_.resize(n + m, np);     // right-hand sides -> solutions
  hist_.resize(2 * n, np);  // (a, v) at fixed q_{n+1}
  for (Eigen::Index k = 0; k < np; ++k) {
    const State& d = dold[size_t(k)];
    sc.history(d, dabar_, dvbar_);
    auto ah = hist_.col(k).head(n);  // d a / dp at fixed q_{n+1}
    auto vh = hist_.col(k).tail(n);  // d v / dp at fixed q_{n+1}
    ah = -sc.ca * d.q + dabar_;
    vh = -sc.cv * d.q + dvbar_;
    // d(qf, vf)/dp at fixed q_{n+1}: ((1 - fw) dq_n, fw vh + (1 - fw) dv_n).
    // Into kept vectors (no heap traffic per step and parameter): Q_p + dQ/d(q, v) terms.
    as.setTime(sc.forceTime(t));
    as.forceParamDerivative(qf, vf, p, int(k), forceTerm_);
    if (sc.fw != 1.0)
      forceTerm_ += (1.0 - sc.fw) * (dQdq * d.q) + dQdv * VecX(sc.fw * vh + (1.0 - sc.fw) * d.v);
    else
      forceTerm_.noalias() += dQdv * vh;
    if (sc.fw != 1.0) {  // the reaction Phi_q(qf)^T sigma lambda: Phi_qp^T sigma lambda + (1 - fw) H dq_n
      as.constraintParamTerms(qf, p, int(k), lt, phiMidBuf_, reactionP_);
      reactionP_ += (1.0 - sc.fw) * as.hessianTimes(qf, p, lt, d.q);
    }
    as.setTime(t);
    as.constraintParamTerms(q, p, int(k), lt, phiBuf_, phiQTlBuf_);  // Phi_p, Phi_qp^T sigma lambda
    if (sc.fw != 1.0) phiQTlBuf_ = reactionP_;
    as.massParamDerivativeTimes(p, int(k), next.a, inertiaTerm_);     // M_p a, then + M ah
    inertiaTerm_.noalias() += eq.mass() * ah;
    X_.col(k).head(n) = -(sigma * (inertiaTerm_ - forceTerm_) + phiQTlBuf_);
    X_.col(k).tail(m) = -phiBuf_;
  }
}

void SensitivitySolver::solveColumns(const SpMat& A, SparseLU& lu, bool luAtSolution, double t) {
  const Eigen::Index np = X_.cols();
  const double nm = double(X_.rows());
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
  const double perSolve = lu.solveFlops() + 2.0 * double(A.nonZeros()) + 10.0 * nm;
  const double s = gmresColumns_ > 0 ? double(gmresSolves_) / double(gmresColumns_) : 3.0;
  const double iterate = double(np) * (s * perSolve + 2.0 * nm * s * s);
  const double factor = 2.0 * lu.factorFlops() + double(np) * 2.0 * perSolve;
  bool exact = luAtSolution || (np > 1 && iterate > factor && lu.factorFlops() > 0.0);
  if (exact && !luAtSolution) {
    lu.factor(A, what);
    st_.sensitivityFactorizations++;
  }
  Eigen::Index iterated = 0;  // the first columns, solved by GMRES
  if (!exact) {
    const double normA = infNorm(A);
    for (; iterated < np; ++iterated) {
      VecX x;
      const PreconditionedSolveResult res = preconditionedSolve(A, normA, lu, VecX(X_.col(iterated)), x,
                                                                kSensitivityBackwardError, kSensitivitySolves);
      st_.sensitivityIterations += res.preconditionerSolves;
      gmresSolves_ += res.preconditionerSolves;
      ++gmresColumns_;
      if (!res.converged) {  // this column and the rest with A factorized
        lu.factor(A, what);
        st_.sensitivityFactorizations++;
        exact = true;
        break;
      }
      X_.col(iterated) = x;
    }
  }
  if (exact) {
    // Refined against A: the Newton matrix of natural-coordinate rigid bodies can be
    // ill-conditioned (thin bars: tiny second moments about their axis), and unlike the
    // state, whose Newton iteration corrects its own solves, the sensitivity is a single
    // solve per step (the 3D double pendulum was off by 2e-6 relative unrefined).
    MatX rest = X_.rightCols(np - iterated);
    lu.solve(rest);
    X_.rightCols(np - iterated) = rest;
  }
}

void SensitivitySolver::finish(const StepEquations& eq, const State& next, const MotionProjection* projection,
                               const std::vector<State>& dold, std::vector<State>& dnext) const {
  const Scheme& sc = eq.scheme();
  const Eigen::Index n = Eigen::Index(next.q.size()), m = Eigen::Index(next.lambda.size());
  for (size_t k = 0; k < dnext.size(); ++k) {
    State& d = dnext[k];
    d.q = X_.col(Eigen::Index(k)).head(n);
    d.lambda = X_.col(Eigen::Index(k)).tail(m) / eq.sigma();
    d.v = sc.cv * d.q + hist_.col(Eigen::Index(k)).tail(n);
    d.a = sc.ca * d.q + hist_.col(Eigen::Index(k)).head(n);
    if (projection) projection->sensitivity(next, int(k), d);
    d.pseudoAcc = sc.nextPseudo(dold[k], d.a);
  }
}

}  // namespace flexsens
