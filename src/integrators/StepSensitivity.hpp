// The sensitivities of a fixed step: the exact derivative of the discrete step,
//   A(x_{n+1}) dx_{n+1}/dp = -dr/dp  at fixed x_{n+1},
// with A the Newton matrix at the converged point (integrators/StepEquations.hpp) and one
// right-hand side per parameter (Q_p, M_p a, Phi_p, Phi_qp^T l and the history's dependence on
// the previous step's sensitivities). Solved with Newton's LU as is when Newton factorized at
// the converged point to round-off, else by GMRES preconditioned with Newton's kept LU
// (core/PreconditionedSolve.hpp), or with A factorized when that costs fewer flops or GMRES
// stalls.
#pragma once

#include <vector>

#include "core/SparseAccumulator.hpp"
#include "integrators/MotionProjection.hpp"
#include "integrators/NewtonSolver.hpp"
#include "integrators/StepEquations.hpp"

namespace flexsens {

class SensitivitySolver {
 public:
  explicit SensitivitySolver(IntegratorStats& stats) : st_(stats) {}

  /// Right-hand sides and solutions for the step just solved: eq begun at the step, next its
  /// end state (the scheme's a and v, before any projection), dold the previous sensitivities.
  void solve(StepEquations& eq, NewtonSolver& newton, const State& next, const std::vector<State>& dold);
  /// The next step's sensitivities from the solutions, after the projections changed next.
  void finish(const StepEquations& eq, const State& next, const MotionProjection* projection,
              const std::vector<State>& dold, std::vector<State>& dnext) const;

  /// The last step's solutions dx_{n+1}/dp, one column (q, sigma lambda) per parameter (the
  /// right-hand sides are overwritten by them), until the next step.
  const MatX& solutions() const { return X_; }

 private:
  /// -dr/dp at fixed x_{n+1}, one column per parameter, into X_ (and the history terms, hist_).
  void rightHandSides(StepEquations& eq, const VecX& qf, const VecX& vf, const VecX& lt, const State& next,
                      const std::vector<State>& dold);
  /// Solves A X = X_ in place: GMRES on Newton's LU, or A factorized (`exact`).
  void solveColumns(const SpMat& A, SparseLU& lu, bool luAtSolution, double t);

  IntegratorStats& st_;
  SparseAccumulator kv_;
  long gmresSolves_ = 0, gmresColumns_ = 0;  // sensitivity solves by GMRES: LU applications, columns
  MatX X_, hist_;  // right-hand sides -> solutions; (a, v) at fixed q_{n+1}, kept across steps
  VecX phiBuf_, phiQTlBuf_;       // Phi_p, Phi_qp^T sigma lambda
  VecX phiMidBuf_, reactionP_;    // midpoint: Phi at the force point (unused), the reaction's p-derivative
  VecX forceTerm_, inertiaTerm_;  // the right-hand sides' force and inertia parts
  VecX dabar_, dvbar_;
};

}  // namespace flexsens
