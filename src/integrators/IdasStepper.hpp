// SUNDIALS IDAS (variable-order BDF) on the GGL form (integrators/GglSystem.hpp), driven one
// internal step at a time: lambda and mu are algebraic (IDASetId) and kept out of the error
// test (IDASetSuppressAlg); the iteration matrix dF/dy + cj dF/dy' is assembled sparse and
// factorized by core/SparseLU; the sensitivity residual is analytic (resS, staggered corrector)
// unless the scene asks for IDAS' difference quotients (dq).
//
// The pieces, in the order a run meets them: setup (SUNDIALS objects, which variables are
// algebraic, tolerances, the linear solver), the residual/Jacobian callbacks (thin wrappers over
// GglSystem), the sensitivity configuration (analytic or dq, corrector, normwise tolerances),
// then step() as often as the caller wants, and stateAt() for frames between steps.
#pragma once

#include <memory>

#include "core/Assembler.hpp"
#include "integrators/Settings.hpp"
#include "integrators/State.hpp"

#include <sundials/sundials_context.h>

namespace flexsens {

/// Steps IDAS may take between two frames before the run stops as too much work.
constexpr long kMaxIdasStepsPerFrame = 1000000;
/// IDAS' flag IDA_TOO_MUCH_WORK, for callers that count steps themselves (throwIfFailed).
constexpr int kIdasTooMuchWork = -1;

class IdasStepper {
 public:
  /// Sets IDAS up at `start` (consistent y, y' and sensitivities, as the PIM gives them).
  /// Throws InputError for an all-massless model, NumericalError when SUNDIALS refuses.
  IdasStepper(const Assembler& as, const VecX& p, const StateWithSens& start, const IntegratorSettings& set);
  ~IdasStepper();
  IdasStepper(const IdasStepper&) = delete;
  IdasStepper& operator=(const IdasStepper&) = delete;

  /// Time of the last step's end [s].
  double time() const;
  /// One internal step towards the frame at tout (a stop time set only for a step that will
  /// reach it, see the source); `updateTolerances` renews the normwise sensitivity tolerances
  /// from the sensitivities reached first. Returns IDASolve's flag (< 0: failed; throwIfFailed).
  int step(double tout, bool updateTolerances);
  /// Throws the NumericalError for a failed flag of `function`, naming the time and the hint.
  void throwIfFailed(int flag, const char* function) const;
  /// The state at the last step's end (no sensitivities): the energy audit's step sequence.
  State current() const;
  /// The state and sensitivities at tq from the last step's interpolating polynomial (exact at
  /// its end, valid back to its start); keeps the largest |Phi| of the frames.
  StateWithSens stateAt(double tq);
  /// The counters so far (read from IDAS).
  const IntegratorStats& statistics();
  /// Before the first step: keep IDAS' adjoint data (IDAAdjInit, Hermite interpolation, a
  /// checkpoint every `stepsPerCheckpoint` steps) and step with IDASolveF, so that backward
  /// problems (integrators/IdasAdjoint.hpp) can be solved on `memory()` after the run.
  void enableAdjoint(long stepsPerCheckpoint);
  /// Checkpoints IDASolveF has written so far.
  long checkpoints() const;
  /// IDAS' memory and the SUNDIALS context (for the backward problems).
  void* memory() const;
  SUNContext context() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace flexsens
