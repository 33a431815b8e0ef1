// Mechanical energy of a state: kinetic T = 1/2 v^T M v with the constant mass matrix, and
// potential V (gravity, elastic, dead loads: the elements' potential()) [J]; and the power of
// everything else, so that dE/dt = power(): dampers, loads doing external work, drivers [W].
// Used for the energy columns of series.csv and the run's energy audit.
#pragma once

#include <cmath>
#include <vector>

#include "core/Assembler.hpp"
#include "integrators/State.hpp"

namespace flexsens {

struct Energy {
  double kinetic = 0.0;    ///< [J]
  double potential = 0.0;  ///< [J], zero where the elements put it (gravity: at the origin)
  double total() const { return kinetic + potential; }
};

class EnergyMeter {
 public:
  /// M(p) is assembled once: masses do not depend on q.
  EnergyMeter(const Assembler& as, const VecX& p) : as_(as), p_(p), M_(as.mass(p)) {
    for (Eigen::Index i = 0; i < M_.rows(); ++i) massTrace_ += M_.coeff(i, i);
  }
  /// Sum of the mass matrix's diagonal [kg] (point masses: dimension x the total mass).
  double massTrace() const { return massTrace_; }
  Energy at(const VecX& q, const VecX& v) const {
    return {0.5 * v.dot(M_ * v), as_.potentialEnergy(q, p_)};
  }
  /// dE/dp_k along each sensitivity dp[k] = (q_p, v_p) of state x [J per unit of p_k]: T's
  /// part exactly, v^T M v_p + 1/2 v^T M_p v; V's part grad V . q_p exactly (conservativeForce,
  /// once for all k) plus dV/dp_k at fixed q by a central difference in p_k: V is linear or
  /// quadratic in what the parameters bind (moduli, masses, densities, gravity, lengths), where
  /// the difference is exact to round-off (a section side enters to the 4th power: relative
  /// error ~1e-8 at step 1e-4).
  std::vector<double> sensitivities(const State& x, const std::vector<State>& dp) const {
    std::vector<double> dE;
    if (dp.empty()) return dE;
    const VecX gradV = -as_.conservativeForce(x.q, p_);
    for (size_t k = 0; k < dp.size(); ++k) {
      const int kk = static_cast<int>(k);
      const double dT = x.v.dot(M_ * dp[k].v) + 0.5 * x.v.dot(as_.massParamDerivativeTimes(p_, kk, x.v));
      VecX pp = p_, pm = p_;
      // Relative step, absolute (1e-4 of the unit) at or near p = 0: 1e-4 |p| of a subnormal
      // p (5e-324) is 0, and (V - V) / 0 was the NaN in denergy_J/d<p>.
      const double h = 1e-4 * (std::abs(p_[kk]) >= 1e-150 ? std::abs(p_[kk]) : 1.0);
      pp[kk] += h;
      pm[kk] -= h;
      const double dVdp = (as_.potentialEnergy(x.q, pp) - as_.potentialEnergy(x.q, pm)) / (2 * h);
      dE.push_back(dT + gradV.dot(dp[k].q) + dVdp);
    }
    return dE;
  }
  /// The power [W] that is not the dampers': loads doing external work and drivers. A
  /// driver's force -Phi_q^T lambda has the power -lambda^T Phi_q v = lambda^T Phi_t
  /// (Phi_q v + Phi_t = 0). NaN when the model has drivers and x carries no multipliers.
  double externalPower(const State& x) const {
    const double t0 = as_.time();
    as_.setTime(x.t);  // loads and drivers at the state's time; the integrator's time restored
    double P = as_.externalPower(x.q, x.v, p_);
    if (as_.rheonomic())
      P = x.lambda.size() == as_.m() ? P + x.lambda.dot(as_.phiT(x.q, p_)) : std::nan("");
    as_.setTime(t0);
    return P;
  }
  bool damped() const { return damped_; }
  /// The dampers' forces at x [N] (their power is v . dampingForce).
  VecX dampingForce(const State& x) const { return as_.dampingForce(x.q, x.v, p_); }
  /// dE/dt at x [W]: the dampers', the loads' doing external work and the drivers' power.
  double power(const State& x) const { return externalPower(x) + x.v.dot(dampingForce(x)); }

 private:
  const Assembler& as_;
  VecX p_;
  SpMat M_;
  double massTrace_ = 0.0;
  bool damped_ = as_.damped();
};

}  // namespace flexsens
