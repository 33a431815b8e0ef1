// Per-run state of the DAE and its parameter sensitivities.
#pragma once

#include <vector>

#include "core/Types.hpp"

namespace flexsens {

/// Positions q [m], velocities v [m/s], accelerations a [m/s^2], multipliers lambda.
struct State {
  double t = 0.0;
  VecX q, v, a, lambda;
  /// Generalized-alpha's acceleration-like history variable [m/s^2]; empty elsewhere (and at
  /// the start, where it equals a).
  VecX pseudoAcc;
};

/// State together with d(state)/dp_k for each design parameter k (same layout).
struct StateWithSens {
  State x;
  std::vector<State> dp;  ///< one per parameter; .t unused
};

/// Counters every integrator reports (summary.json, benchmarks).
struct IntegratorStats {
  long steps = 0;
  long newtonIterations = 0;
  long factorizations = 0;      ///< every numeric LU factorization of the step matrices
  /// Fixed step, modified Newton: applications of the kept LU in the sensitivity solves
  /// (preconditioned GMRES), and the factorizations of the exact matrix they fell back to.
  long sensitivityIterations = 0;
  long sensitivityFactorizations = 0;
  /// Fixed step: steps whose sensitivity solve used Newton's LU as is, because Newton had
  /// factorized it at the converged point to round-off (no assembly, no iteration).
  long sensitivityReusedLu = 0;
  long residualEvaluations = 0;
  long jacobianEvaluations = 0;
  long errorTestFailures = 0;
  long convergenceFailures = 0;  ///< IDAS: nonlinear failures; fixed step: modified-Newton steps redone with full Newton
  long acceleratedIterations = 0;  ///< fixed step, modified Newton: iterations with an Anderson-accelerated step
  double maxConstraintViolation = 0.0;  ///< max over frames of |Phi|_inf
  double luFill = 0.0;                  ///< largest nnz(L + U) / nnz(A) of the step matrices
  long choleskyFactorizations = 0;      ///< of the factorizations, those by Cholesky (core/SparseLU)
  long ldltFactorizations = 0;          ///< ... and those by MUMPS' LDL^T (core/SparseLU)
  double factorizationSeconds = 0.0;    ///< wall time in numeric factorizations [s]
};

/// Receives output frames; integrators call it at the requested frame times.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void frame(const StateWithSens& s) = 0;
  /// Called once per step with the current time (progress reporting); cheap.
  virtual void progress(double t) { (void)t; }
  /// Called with the initial state and then once per accepted step (every step, not only at
  /// frames; IDAS: every internal step) with the state there, sensitivities left out: the
  /// energy audit integrates the work of dampers, loads and drivers over the steps.
  virtual void stepped(const State& x) { (void)x; }
  /// Called once per step with the counters so far, so that a failed or interrupted run
  /// still reports how far it got.
  virtual void reached(const IntegratorStats& st) { (void)st; }
};

/// Passes everything on to the next observer: the run's chain (health -> energy audit ->
/// writer); a link overrides what it inspects and still passes it on.
class ForwardingObserver : public Observer {
 public:
  explicit ForwardingObserver(Observer& next) : next_(next) {}
  void frame(const StateWithSens& s) override { next_.frame(s); }
  void progress(double t) override { next_.progress(t); }
  void stepped(const State& x) override { next_.stepped(x); }
  void reached(const IntegratorStats& st) override { next_.reached(st); }

 protected:
  Observer& next_;
};

}  // namespace flexsens
