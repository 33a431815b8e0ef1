// SIGINT/SIGTERM as a request to stop: the handler only records the signal; integrators
// look at it at the end of each step and stop there, so what was computed is written out.
#pragma once

#include <stdexcept>
#include <string>

namespace flexsens {

/// Installs the handlers (SA_RESETHAND: a second Ctrl-C kills at once, as users expect).
void installInterruptHandlers();
/// The signal received (SIGINT, SIGTERM), 0 when none; else the request this thread made
/// (requestThreadInterrupt).
int interruptSignal();
/// Forgets a received signal (tests).
void clearInterrupt();
/// Raises the flag as the handler would (tests).
void requestInterrupt(int signal);
/// Stops the run of the calling thread only, as a signal would (at the end of its step): the
/// Python binding's Ctrl-C and progress callback, with other threads' runs going on.
void requestThreadInterrupt(int signal);
/// Forgets the calling thread's request (before and after each of its runs).
void clearThreadInterrupt();

/// Thrown by an integrator that stopped on a signal after its last frame at time t.
struct Interrupted : std::runtime_error {
  Interrupted(int sig, double time);
  int signal;
  double t;  ///< [s] time reached, the last frame written
};

/// Thrown when SIGINT/SIGTERM arrives before any result exists (e.g. while a child process
/// meshes the scene's geometry): nothing was written.
struct InterruptedBeforeRun : std::runtime_error {
  InterruptedBeforeRun(int sig, const std::string& during);
  int signal;
};

}  // namespace flexsens
