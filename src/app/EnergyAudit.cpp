#include "app/EnergyAudit.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "output/ResultWriter.hpp"

namespace flexsens {

void EnergyAudit::stepped(const State& x) {
  next_.stepped(x);
  const Energy e = meter_.at(x.q, x.v);
  const double P = meter_.externalPower(x);
  if (!started_) {
    started_ = true;
    e0_ = e.total();
    vMin_ = vMax_ = e.potential;
    t0_ = x.t;
    qScale_ = x.q.size() ? x.q.lpNorm<Eigen::Infinity>() : 0.0;
  } else {
    ++steps_;
    work_ += 0.5 * (x.t - tLast_) * (P + pLast_);  // NaN from here on when P is unknown
    work_ += dampingWork(x);
  }
  pLast_ = P;
  tLast_ = x.t;
  qLast_ = x.q;
  eLast_ = e.total();
  tMax_ = std::max(tMax_, e.kinetic);
  vMin_ = std::min(vMin_, e.potential);
  vMax_ = std::max(vMax_, e.potential);
  wMax_ = std::max(wMax_, std::abs(work_));
  const double balance = eLast_ - e0_ - work_;
  if (balance > maxRise_) maxRise_ = balance, tRise_ = x.t;
  if (-balance > maxLoss_) maxLoss_ = -balance, tLoss_ = x.t;
}

// The dampers' work over the step from (tLast_, qLast_) to x [J]: dq . F_d(q_mid, dq / h), with
// the mean velocity dq / h of the step. A damper's force is linear in v at given q and opposes
// it, so this is <= 0, and it is what a step does to a stiff damped mode it leaves unresolved
// (v_n+1 ~ -v_n, dq ~ 0): nothing.
double EnergyAudit::dampingWork(const State& x) const {
  const double h = x.t - tLast_;
  if (!meter_.damped() || h == 0.0) return 0.0;  // IDAS can report a step back to a frame: h < 0
  State mid;
  mid.t = 0.5 * (x.t + tLast_);
  mid.q = 0.5 * (x.q + qLast_);
  mid.v = (x.q - qLast_) / h;
  return (x.q - qLast_).dot(meter_.dampingForce(mid));
}

// The largest rise or loss of the balance as a fraction of the scale (-1 when not judged).
double EnergyAudit::worstFraction() const {
  const double s = judged() ? scale() : 0.0;
  return s > 0.0 ? std::max(maxRise_, maxLoss_) / s : -1.0;
}

// The motion's own energy: the largest kinetic energy, swing of the potential or work done on
// it, with two floors below which the balance is noise, not a verdict:
// - 1e-9 |V| keeps round-off in V from counting (a model at rest has no motion energy);
// - the resolution floor 1/2 tr(M) (r L / h)^2: the kinetic energy of the model moving at the
//   velocity its position resolution gives, r = 1e-10 (the Newton tolerance, relative to the
//   largest coordinate L, at least 1 m) over the mean step h. The balance error of a motion
//   resolved to dq is ~ M v dv (dv = dq / h), so it is judged relative to T only where
//   v >> dv: the first 3 steps of a spin-up (T = 9e-20 J, displacements of 1e-11 m, far below
//   the 1e-9 m the Newton iteration resolves) are below it.
double EnergyAudit::resolutionFloor() const {
  if (steps_ == 0 || !(tLast_ > t0_)) return 0.0;
  const double h = (tLast_ - t0_) / steps_;
  const double dv = kPositionResolution * std::max(qScale_, 1.0) / h;
  return 0.5 * meter_.massTrace() * dv * dv;
}

double EnergyAudit::scale() const {
  const double floor = 1e-9 * std::max({std::abs(e0_), std::abs(vMin_), std::abs(vMax_)}) + 1e-300;
  return std::max({tMax_, vMax_ - vMin_, wMax_, floor, resolutionFloor()});
}

std::string EnergyAudit::reason() const {
  if (!judged()) return "";
  std::ostringstream os;
  if (riseTol_ > 0 && maxRise_ > riseTol_ * scale()) {
    os << "energy audit: the energy balance E - E0 - W (W: work of dampers, loads and drivers) rose by " << maxRise_
       << " J (largest at t = " << tRise_ << " s), " << maxRise_ / scale() << " times the run's energy scale "
       << scale() << " J, above the tolerance " << riseTol_ << " (integrator.energy_tolerance); a motion cannot "
       << "gain energy nothing supplied: it is wrong (e.g. a branch switch at a singular configuration, or a step "
       << "too large for the fastest mode). Try a smaller dt, generalized_alpha with rho_inf < 1, or IDAS";
  } else if (lossTol_ > 0 && maxLoss_ > lossTol_ * scale()) {
    os << "energy audit: the integrator dissipated " << maxLoss_ << " J that no damper or load took out (largest "
       << "at t = " << tLoss_ << " s), " << maxLoss_ / scale() << " times the run's energy scale " << scale()
       << " J, above the tolerance " << lossTol_ << " (integrator.energy_loss_tolerance): numerical damping "
       << "changes the motion. Try a smaller dt, the trapezoidal rule or generalized_alpha with rho_inf nearer 1, "
       << "or IDAS";
  }
  return os.str();
}

std::string EnergyAudit::json() const {
  std::ostringstream os;
  os << "{\"initial_J\": " << jsonNumber(e0_) << ", \"final_J\": " << jsonNumber(eLast_)
     << ", \"work_J\": " << jsonNumber(work_) << ", \"balance_J\": " << jsonNumber(eLast_ - e0_ - work_)
     << ", \"max_rise_J\": " << jsonNumber(maxRise_) << ", \"max_rise_t\": " << jsonNumber(tRise_)
     << ", \"max_loss_J\": " << jsonNumber(maxLoss_) << ", \"max_loss_t\": " << jsonNumber(tLoss_)
     << ", \"scale_J\": " << jsonNumber(scale()) << ", \"resolution_floor_J\": " << jsonNumber(resolutionFloor()) << ", \"tolerance\": " << jsonNumber(riseTol_)
     << ", \"loss_tolerance\": " << jsonNumber(lossTol_) << ", \"suspect\": " << (suspect() ? "true" : "false")
     << ", \"judged\": " << (judged() ? "true" : "false");
  if (!judged())
    os << ", \"not_judged\": " << jsonString(started_ ? "the drivers' multipliers were not available" : "no state reached");
  os << "}";
  return os.str();
}

}  // namespace flexsens
