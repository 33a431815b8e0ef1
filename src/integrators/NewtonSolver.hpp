// The Newton solver of a fixed step (integrators/StepEquations.hpp): full Newton (a
// factorization per iteration) or modified Newton (the factorization kept across iterations and
// steps while the iteration contracts fast, Anderson-accelerated after a slow step), with the
// fallbacks a step takes before it fails: full Newton, full Newton with backtracking, and both
// again from the other start (q_n instead of the predictor). Counts into the run's statistics.
// Keeps its LU and the iterate it was factorized at, for the sensitivity solve (the matrix at
// the converged point, to round-off, when Newton's last factorization was there).
#pragma once

#include "core/SparseAccumulator.hpp"
#include "core/SparseLU.hpp"
#include "integrators/AndersonMixing.hpp"
#include "integrators/Settings.hpp"
#include "integrators/StepEquations.hpp"

namespace flexsens {

class NewtonSolver {
 public:
  NewtonSolver(const IntegratorSettings& set, int n, int m, IntegratorStats& stats);

  /// Solves the step's equations (begun) from the predictor qTaylor (or q_n, once a step needed
  /// that start). True when converged: q(), l() hold the solution. A NumericalError of the
  /// last fallback (an element turned inside out) is rethrown naming the step.
  bool solve(StepEquations& eq, const VecX& qTaylor);

  const VecX& q() const { return q_; }
  const VecX& l() const { return lt_; }  ///< sigma lambda
  /// The last update's |dq|_inf [m] and residual |r|_inf, for failure messages.
  double lastUpdate() const { return lastUpdate_; }
  double lastResidual() const { return lastResidual_; }

  /// The kept LU (modified Newton: across steps) and the accumulator its matrix was assembled in.
  SparseLU& lu() { return lu_; }
  SparseAccumulator& accumulator() { return acc_; }
  /// True when this step's last factorization was of the matrix at (q, l) to within `tol`
  /// relative (inf-norm, per block) with the scheme coefficient ca.
  bool factorizedNear(const VecX& q, const VecX& l, long step, double ca, double tol) const;

 private:
  /// The chord of one matrix within a step.
  struct Chord {
    double previous = 0.0;   ///< |dq| of its last update; 0: none yet
    double first = 0.0;      ///< |dq| of its first update
    bool fresh = false;      ///< factorized at the current iterate (no update since)
    bool atStart = false;    ///< factorized at the step's start point
    bool stale = true;       ///< factorized in an earlier step
    bool confirmed = false;  ///< an update followed by a contracting one
  };
  bool rejectedChord(const Chord& chord);
  bool fullNewton(StepEquations& eq, bool backtrack);
  bool modifiedNewton(StepEquations& eq);
  /// Modified Newton with the reuse back-off around it (true: converged).
  bool modifiedWithBackoff(StepEquations& eq);
  /// Full Newton, plain then with backtracking, and then from the other start.
  bool fallbacks(StepEquations& eq, const VecX& qTaylor, bool converged);
  void factorAt(StepEquations& eq, const VecX& q, const VecX& l, const char* how);
  void startAt(StepEquations& eq, VecX& r);

  const IntegratorSettings& set_;
  const int n_, m_;
  IntegratorStats& st_;
  const bool modified_;  // else full Newton
  SparseAccumulator acc_;
  SparseLU lu_;              // modified Newton: kept across iterations and steps
  double factoredCa_ = 0.0;  // the scheme coefficient of the matrix in lu (h changed: refresh)
  VecX luQ_, luL_;           // the iterate (q, sigma lambda) lu's matrix was assembled at ...
  long luStep_ = 0;          // ... in this step
  // A step starts with the matrix of an earlier step unless that failed lately: after a
  // failure the next `skipReuse` steps start with a fresh matrix, twice as many each time.
  int skipReuse_ = 0, backoff_ = 1;
  // Newton starts from q_n instead of the predictor once a step needed that (see solve).
  bool startAtOld_ = false;
  AndersonMixing anderson_;  // modified Newton's acceleration
  VecX xk_;                  // its iterate (q, lambda)
  bool slowChord_ = false;   // the last step's chord contracted slower than kAndersonAbove
  bool staleFailed_ = false; // the matrix of an earlier step led away: the step restarted
  double lastCorrection_ = 0.0;  // |q_n+1 - predictor|_inf of the last modified Newton step [m]
  VecX qPredicted_, q_, lt_;
  double lastUpdate_ = 0.0, lastResidual_ = 0.0;
};

}  // namespace flexsens
