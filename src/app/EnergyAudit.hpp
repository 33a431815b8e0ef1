// The energy audit of a run: passes every frame on to the next observer and follows the total
// mechanical energy E = T + V. The models flexsens integrates are passive (dampers only take
// energy out; constraints are scleronomic and do no work; loads are dead, with a potential), so
// E may fall (damping, or an integrator's numerical dissipation) but not rise. A rise above
// `tolerance` times the energy scale (the largest kinetic energy or potential swing of the run)
// marks the run `suspect`: the N-four-bar that flips its crank every frame past a singular
// configuration gains energy by orders of magnitude while |Phi| stays at round-off.
// A model with drivers (rheonomic constraints) or loads that do external work (varying in
// time, torques) is not passive: the audit then records the energy but does not judge
// (never `suspect`), and its json says why (`"judged": false, "not_judged": ...`).
#pragma once

#include <string>

#include "integrators/State.hpp"
#include "output/Energy.hpp"

namespace flexsens {

class EnergyAudit : public Observer {
 public:
  /// `meter` is the run's (the writer's energy columns use the same one).
  EnergyAudit(const EnergyMeter& meter, Observer& next, double tolerance)
      : meter_(meter), next_(next), tolerance_(tolerance) {}
  void frame(const StateWithSens& s) override;
  void progress(double t) override { next_.progress(t); }
  void reached(const IntegratorStats& st) override { next_.reached(st); }

  /// The run is not passive (drivers, external work): record, do not judge. `why` in words.
  void notJudged(std::string why) { notJudged_ = std::move(why); }
  bool suspect() const;
  /// Plain words: the largest rise, when and against which scale; empty when not suspect.
  std::string reason() const;
  /// summary.json's "energy" object.
  std::string json() const;

 private:
  double scale() const;
  const EnergyMeter& meter_;
  Observer& next_;
  double tolerance_;
  std::string notJudged_;
  bool started_ = false;
  double e0_ = 0, eLast_ = 0, maxRise_ = 0, tRise_ = 0, tLast_ = 0;
  double tMax_ = 0, vMin_ = 0, vMax_ = 0;  ///< largest kinetic energy, potential range [J]
};

}  // namespace flexsens
