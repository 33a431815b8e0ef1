// SUNDIALS IDAS (variable-order BDF) on the stabilized index-2 (GGL) form
//   q' - v + Phi_q^T mu = 0,  M v' + Phi_q^T lambda - Q = 0,  Phi = 0,  Phi_q v = 0
// with y = (q, v, lambda, mu); lambda and mu are algebraic (IDASetId) and kept out of the
// error test (IDASetSuppressAlg). Jacobian dF/dy + cj dF/dy' assembled sparse for KLU; the
// sensitivity residual is analytic (resS), staggered corrector.
#pragma once

#include <functional>

#include "core/Assembler.hpp"
#include "integrators/GglSystem.hpp"
#include "integrators/Settings.hpp"
#include "integrators/State.hpp"

namespace flexsens {

/// Integrates from `start` to set.tEnd, a frame at every multiple of set.frameInterval (and at
/// t_end), one IdasStepper step at a time (integrators/IdasStepper.hpp).
IntegratorStats integrateIdas(const Assembler& as, const VecX& p, const StateWithSens& start,
                              const IntegratorSettings& set, Observer& obs);

class IdasStepper;
/// Called after every internal step with the stepper and the step's start time [s] (the step
/// ends at stepper.time(); stepper.stateAt is valid in between).
using IdasStepHook = std::function<void(IdasStepper& stepper, double stepStart)>;
/// The same with a stepper set up by the caller (integrators/IdasStepper.hpp), `afterStep`
/// seeing each step.
IntegratorStats integrateIdas(IdasStepper& stepper, const StateWithSens& start, const IntegratorSettings& set,
                              Observer& obs, const IdasStepHook& afterStep);

}  // namespace flexsens
