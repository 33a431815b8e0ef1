#include "app/EnergyAudit.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "output/ResultWriter.hpp"

namespace flexsens {

void EnergyAudit::frame(const StateWithSens& s) {
  next_.frame(s);  // the writer first: a non-finite state is its error to report
  const Energy e = meter_.at(s.x.q, s.x.v);
  if (!started_) {
    started_ = true;
    e0_ = e.total();
    vMin_ = vMax_ = e.potential;
  }
  tMax_ = std::max(tMax_, e.kinetic);
  vMin_ = std::min(vMin_, e.potential);
  vMax_ = std::max(vMax_, e.potential);
  eLast_ = e.total();
  tLast_ = s.x.t;
  if (eLast_ - e0_ > maxRise_) {
    maxRise_ = eLast_ - e0_;
    tRise_ = s.x.t;
  }
}

// The motion's own energy: the largest kinetic energy or swing of the potential. A model at
// rest has neither; then the floor 1e-9 |V| keeps round-off in V from counting as a rise.
double EnergyAudit::scale() const {
  const double floor = 1e-9 * std::max({std::abs(e0_), std::abs(vMin_), std::abs(vMax_)}) + 1e-300;
  return std::max({tMax_, vMax_ - vMin_, floor});
}

bool EnergyAudit::suspect() const {
  return notJudged_.empty() && tolerance_ > 0 && maxRise_ > tolerance_ * scale();
}

std::string EnergyAudit::reason() const {
  if (!suspect()) return "";
  std::ostringstream os;
  os << "energy audit: the total mechanical energy rose by " << maxRise_ << " J (largest at t = " << tRise_
     << " s), " << maxRise_ / scale() << " times the run's energy scale " << scale()
     << " J, above the tolerance " << tolerance_ << " (integrator.energy_tolerance); a passive model cannot gain "
     << "energy: the motion is wrong (e.g. a branch switch at a singular configuration, or a step too large for "
     << "the fastest mode). Try a smaller dt, generalized_alpha with rho_inf < 1, or IDAS";
  return os.str();
}

std::string EnergyAudit::json() const {
  std::ostringstream os;
  os << "{\"initial_J\": " << jsonNumber(e0_) << ", \"final_J\": " << jsonNumber(eLast_)
     << ", \"max_rise_J\": " << jsonNumber(maxRise_) << ", \"max_rise_t\": " << jsonNumber(tRise_)
     << ", \"scale_J\": " << jsonNumber(scale()) << ", \"tolerance\": " << jsonNumber(tolerance_)
     << ", \"suspect\": " << (suspect() ? "true" : "false") << ", \"judged\": " << (notJudged_.empty() ? "true" : "false");
  if (!notJudged_.empty()) os << ", \"not_judged\": " << jsonString(notJudged_);
  os << "}";
  return os.str();
}

}  // namespace flexsens
