// What every integrator does at the start (the first frame) and at the end of a step: report
// the state, progress and counters, write the frame when one is due, and stop on
// SIGINT/SIGTERM with a last frame at the time reached.
#pragma once

#include "core/Interrupt.hpp"
#include "integrators/State.hpp"

namespace flexsens {

/// The first frame and the first state of the audit's step sequence.
inline void beginRun(Observer& obs, const StateWithSens& start) {
  obs.frame(start);
  obs.stepped(start.x);
}

inline void endStep(Observer& obs, const StateWithSens& cur, const IntegratorStats& st, bool frameDue) {
  obs.stepped(cur.x);
  obs.progress(cur.x.t);
  obs.reached(st);
  if (frameDue) obs.frame(cur);
  if (const int sig = interruptSignal()) {
    if (!frameDue) obs.frame(cur);  // the outputs end where the integration stopped
    throw Interrupted(sig, cur.x.t);
  }
}

}  // namespace flexsens
