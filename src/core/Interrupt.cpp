#include "core/Interrupt.hpp"

#include <csignal>
#include <cstring>

namespace flexsens {

namespace {
volatile std::sig_atomic_t gSignal = 0;
extern "C" void onSignal(int sig) { gSignal = sig; }
thread_local int tRequest = 0;  ///< this thread's own stop request (no handler touches it)
}  // namespace

void installInterruptHandlers() {
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  // SA_RESTART: writes in progress finish instead of failing with EINTR.
  sa.sa_flags = SA_RESETHAND | SA_RESTART;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int interruptSignal() { return gSignal ? static_cast<int>(gSignal) : tRequest; }
void clearInterrupt() { gSignal = 0; }
void requestInterrupt(int signal) { gSignal = signal; }
void requestThreadInterrupt(int signal) { tRequest = signal; }
void clearThreadInterrupt() { tRequest = 0; }

Interrupted::Interrupted(int sig, double time)
    : std::runtime_error(std::string("interrupted by ") + (sig == SIGTERM ? "SIGTERM" : sig == SIGINT ? "SIGINT" : "a signal") +
                         " at t = " + std::to_string(time) + " s"),
      signal(sig), t(time) {}

InterruptedBeforeRun::InterruptedBeforeRun(int sig, const std::string& during)
    : std::runtime_error(std::string("interrupted by ") + (sig == SIGTERM ? "SIGTERM" : sig == SIGINT ? "SIGINT" : "a signal") +
                         " " + during + "; nothing written"),
      signal(sig) {}

}  // namespace flexsens
