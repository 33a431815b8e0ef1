#include "integrators/FixedStep.hpp"

#include "integrators/FixedStepper.hpp"
#include "integrators/StepEnd.hpp"

namespace flexsens {

IntegratorStats integrateFixedStep(const Assembler& as, const VecX& p, StateWithSens start,
                                   const IntegratorSettings& set, Observer& obs) {
  FixedStepper stepper(as, p, std::move(start), set);
  beginRun(obs, stepper.current());
  stepper.advance(set.tEnd, obs);
  return stepper.statistics();
}

}  // namespace flexsens
