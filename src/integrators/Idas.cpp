#include "integrators/Idas.hpp"

#include <algorithm>

#include "core/Interrupt.hpp"
#include "integrators/IdasStepper.hpp"
#include "integrators/StepEnd.hpp"
#include "integrators/TimeGrid.hpp"

namespace flexsens {

namespace {

/// Steps until the frame at tout is reached (the frame itself is interpolated by the caller).
/// One step per call, so that a signal is seen after the step it arrived in; IDAS' own step
/// limit (IDASetMaxNumSteps) counts per call, so one step per call needs our own.
void stepToFrame(IdasStepper& stepper, double tout, bool firstFrame, double tEnd, Observer& obs,
                 const IdasStepHook& afterStep) {
  for (long stepsThisFrame = 0; stepper.time() < tout; ++stepsThisFrame) {
    if (stepsThisFrame >= kMaxIdasStepsPerFrame) {
      obs.reached(stepper.statistics());
      stepper.throwIfFailed(kIdasTooMuchWork, "IDASolve");
    }
    const double tBefore = stepper.time();
    const int flag = stepper.step(tout, stepsThisFrame > 0 || !firstFrame);
    if (flag < 0) {  // the failed run's summary reports the work done up to here
      obs.reached(stepper.statistics());
      stepper.throwIfFailed(flag, "IDASolve");
    }
    const double t = stepper.time();
    if (afterStep) afterStep(stepper, tBefore);
    if (t < tout && interruptSignal()) {
      StateWithSens out = stepper.stateAt(t);
      endStep(obs, out, stepper.statistics(), false);  // writes the state reached and throws Interrupted
    }
    obs.stepped(stepper.current());
    obs.progress(std::min(t, tEnd));
  }
}

}  // namespace

IntegratorStats integrateIdas(const Assembler& as, const VecX& p, const StateWithSens& start,
                              const IntegratorSettings& set, Observer& obs) {
  IdasStepper stepper(as, p, start, set);
  return integrateIdas(stepper, start, set, obs, {});
}

IntegratorStats integrateIdas(IdasStepper& stepper, const StateWithSens& start, const IntegratorSettings& set,
                              Observer& obs, const IdasStepHook& afterStep) {
  beginRun(obs, start);
  const long nframes = outputCount(set.tEnd - start.x.t, set.frameInterval);
  for (long f = 1; f <= nframes; ++f) {
    const double tout = (f == nframes) ? set.tEnd : start.x.t + f * set.frameInterval;
    stepToFrame(stepper, tout, f == 1, set.tEnd, obs, afterStep);
    StateWithSens out = stepper.stateAt(tout);
    endStep(obs, out, stepper.statistics(), true);
  }
  return stepper.statistics();
}

}  // namespace flexsens
