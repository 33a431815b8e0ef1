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
  long factorizations = 0;
  long residualEvaluations = 0;
  long jacobianEvaluations = 0;
  long errorTestFailures = 0;
  long convergenceFailures = 0;
  double maxConstraintViolation = 0.0;  ///< max over frames of |Phi|_inf
};

/// Receives output frames; integrators call it at the requested frame times.
class Observer {
 public:
  virtual ~Observer() = default;
  virtual void frame(const StateWithSens& s) = 0;
  /// Called once per step with the current time (progress reporting); cheap.
  virtual void progress(double t) { (void)t; }
  /// Called once per step with the counters so far, so that a failed or interrupted run
  /// still reports how far it got.
  virtual void reached(const IntegratorStats& st) { (void)st; }
};

}  // namespace flexsens
