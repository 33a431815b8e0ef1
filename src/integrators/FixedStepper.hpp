// A fixed-step run as an object: the trapezoidal rule, BDF-1, generalized-alpha or the implicit
// midpoint rule (integrators/Scheme.hpp) on the index-3 form, a step at a time. Each step
// composes the pieces: the step's equations (StepEquations), Newton (NewtonSolver), the
// sensitivity solve (SensitivitySolver), the velocity and acceleration projections
// (MotionProjection, on request) and the step-end bookkeeping. advance(t, obs) is the loop,
// with the observers called at every step's end; a caller that drives the run itself (an
// interactive session, an adjoint recording the steps) calls step() and reads the pieces.
#pragma once

#include <memory>
#include <vector>

#include "core/Assembler.hpp"
#include "integrators/MotionProjection.hpp"
#include "integrators/NewtonSolver.hpp"
#include "integrators/Scheme.hpp"
#include "integrators/Settings.hpp"
#include "integrators/State.hpp"
#include "integrators/StepEquations.hpp"
#include "integrators/StepSensitivity.hpp"

namespace flexsens {

class FixedStepper {
 public:
  /// Checks the settings against the model (InputError: the midpoint rule with massless
  /// parts, t_end not a whole number of steps) and starts at `start`.
  FixedStepper(const Assembler& as, const VecX& p, StateWithSens start, const IntegratorSettings& set);
  /// Resumes a run that began at runStart [s]: `start` is its state after firstStep steps (an
  /// adjoint recomputing from a checkpoint takes the run's own step times, t0 + n dt).
  FixedStepper(const Assembler& as, const VecX& p, StateWithSens start, const IntegratorSettings& set,
               long firstStep, double runStart);
  FixedStepper(const FixedStepper&) = delete;
  FixedStepper& operator=(const FixedStepper&) = delete;

  /// Steps until time t (or t_end), the observers told at each step's end (endStep: a frame
  /// when due, the interrupt check).
  void advance(double t, Observer& obs);
  /// One step; NumericalError naming the step, the time and what to change when Newton fails
  /// (current() is then still the state reached).
  void step();

  bool done() const { return step_ >= nsteps_; }
  /// A frame is due at the end of the step just taken (every k steps and at t_end).
  bool frameDue() const { return step_ % every_ == 0 || step_ == nsteps_; }
  long stepIndex() const { return step_; }
  const StateWithSens& current() const { return cur_; }
  const IntegratorStats& statistics() const { return st_; }

  // ---- the last step's pieces, for an adjoint that replays the steps backwards
  /// Its equations (the previous state, the history terms, the time) ...
  StepEquations& equations() { return eq_; }
  /// ... its solution (q_{n+1}, sigma lambda_{n+1}) ...
  const VecX& solutionQ() const { return newton_.q(); }
  const VecX& solutionL() const { return newton_.l(); }
  /// ... the Newton matrix dr/dx there (assembled on request, into storage of its own) ...
  const SpMat& jacobianAtSolution();
  /// ... and the sensitivities' solutions dx/dp (empty without parameters).
  const MatX& sensitivitySolutions() const { return sens_.solutions(); }

 private:
  [[noreturn]] void failNotConverged(const State& old, double t) const;
  /// The largest |a_i| over the coordinates that have mass, and where.
  double largestAcceleration(const VecX& a, int& where) const;
  void takeStep();
  void finishStep(State&& next);

  const Assembler& as_;
  const VecX p_;
  const IntegratorSettings set_;
  const Scheme sc_;
  const std::vector<int> massless_;
  const long nsteps_, every_;
  const double t0_;
  IntegratorStats st_;
  StepEquations eq_;
  NewtonSolver newton_;
  SensitivitySolver sens_;
  std::unique_ptr<MotionProjection> projection_;  // velocity and acceleration projections
  std::vector<char> counted_;  // coordinates whose accelerations the failure message watches
  double aEarly_ = 0.0;        // largest |a|_inf over the first kEarlySteps steps
  long step_ = 0;
  StateWithSens cur_;
  State prev_;                 // the state before the last step (its equations refer to it)
  std::vector<State> dnext_;   // the next step's sensitivities
  SparseAccumulator replayAcc_;
};

}  // namespace flexsens
