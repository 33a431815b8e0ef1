// The energy audit of a run. At the initial state and after every step (Observer::stepped) it
// evaluates the energy balance
//   B(t) = E(t) - E(t0) - W(t),   E = T + V,   W(t) the work
// of what the potential does not hold, summed over the integrator's own steps (IDAS: its
// internal steps): loads that do external work and drivers by the trapezoidal rule of their
// power, dampers as dq . F_d(q_mid, dq / h) (dampingWork). Their power's trapezoidal sum,
// -h/2 (v_n C v_n + v_n+1 C v_n+1), counted a stiff damped mode the step leaves unresolved
// (v_n+1 ~ -v_n: the trapezoidal rule does not damp it) as dissipating: a Kelvin-Voigt shell
// at dt 0.01 s lost 3.3e-5 J against 2.2e-3 J counted, a false `suspect`. B is zero for the
// exact motion, so what it shows is the integrator's error: a gain (B > 0) is a wrong motion (the N-four-bar that flips its crank
// every frame past a singular configuration gains energy by orders of magnitude while |Phi|
// stays at round-off), a loss (B < 0) numerical dissipation (BDF-1 takes 40% of the
// N-four-bar's energy). A gain above `riseTolerance` or a loss above `lossTolerance` times the
// run's energy scale (its largest kinetic energy, potential swing or |W|, at least the
// resolution floor, see scale()) marks the run `suspect`; a tolerance of 0 switches that side off.
#pragma once

#include <string>

#include "integrators/State.hpp"
#include "output/Energy.hpp"

namespace flexsens {

class EnergyAudit : public ForwardingObserver {
 public:
  /// `meter` is the run's (the writer's energy columns use the same one).
  EnergyAudit(const EnergyMeter& meter, Observer& next, double riseTolerance, double lossTolerance)
      : ForwardingObserver(next), meter_(meter), riseTol_(riseTolerance), lossTol_(lossTolerance) {}
  void stepped(const State& x) override;

  bool suspect() const { return !reason().empty(); }
  /// Plain words: the largest gain or loss, when and against which scale; empty when not suspect.
  std::string reason() const;
  /// summary.json's "energy" object.
  std::string json() const;
  /// The largest gain or loss of the balance as a fraction of the energy scale; -1 when the
  /// run was not judged (no state, the drivers' multipliers missing, a zero scale).
  double worstFraction() const;

 private:
  double scale() const;
  double dampingWork(const State& x) const;
  double resolutionFloor() const;  ///< [J], 0 before the first step
  static constexpr double kPositionResolution = 1e-10;  ///< relative, the fixed-step Newton tolerance
  bool judged() const { return started_ && std::isfinite(work_); }
  const EnergyMeter& meter_;
  double riseTol_, lossTol_;
  bool started_ = false;
  double e0_ = 0, eLast_ = 0, work_ = 0, pLast_ = 0, tLast_ = 0;  ///< [J], [W], [s]
  double maxRise_ = 0, tRise_ = 0, maxLoss_ = 0, tLoss_ = 0;      ///< largest B > 0, -B > 0
  double tMax_ = 0, vMin_ = 0, vMax_ = 0, wMax_ = 0;  ///< largest T, V range, largest |W| [J]
  double t0_ = 0, qScale_ = 0;  ///< first time [s], largest |q| there [m]
  VecX qLast_;  ///< the last state's coordinates
  long steps_ = 0;
};

}  // namespace flexsens
