// The fixed-step schemes' coefficients: the trapezoidal rule, BDF-1, generalized-alpha and the
// implicit midpoint rule, each as a(q) = ca (q - q_n) + abar, v(q) = cv (q - q_n) + vbar in the
// step's unknown q = q_{n+1}, with the history terms (abar, vbar) from the step before.
#pragma once

#include "core/Types.hpp"
#include "integrators/Settings.hpp"
#include "integrators/State.hpp"

namespace flexsens {

/// Scheme coefficients: a = ca (q - qn) + abar, v = cv (q - qn) + vbar.
/// Newmark family with generalized-alpha averaging of the accelerations (Chung-Hulbert,
/// in Arnold-Bruls' index-3 form: equilibrium and constraints exactly at t_{n+1}):
///   q_{n+1} = q_n + h v_n + h^2 (1/2 - beta) w_n + h^2 beta w_{n+1}
///   v_{n+1} = v_n + h (1 - gamma) w_n + h gamma w_{n+1}
///   (1 - am) w_{n+1} + am w_n = (1 - af) a_{n+1} + af a_n,  w = pseudo-acceleration.
/// Trapezoidal = (am, af, beta, gamma) = (0, 0, 1/4, 1/2), so w = a. BDF-1 is separate.
/// Implicit midpoint rule: q_{n+1} = q_n + h (v_n + v_{n+1}) / 2, M (v_{n+1} - v_n) / h =
/// Q(q_{n+1/2}, v_{n+1/2}, t_{n+1/2}) - Phi_q(q_{n+1/2}, t_{n+1/2})^T lambda with
/// q_{n+1/2} = (q_n + q_{n+1}) / 2: a symplectic Runge-Kutta method, so with no constraint it
/// conserves linear and angular momentum exactly (internal forces of a frame-indifferent
/// energy have no net force or moment at any configuration) and every quadratic invariant;
/// energy is bounded, not drifting. Constraints hold at t_{n+1} (index 3), Phi(q_{n+1}) = 0, as
/// in the other schemes; the reaction acts where the forces do. With the reaction at q_{n+1}
/// instead, the step's force is off by (h/2) (sum lambda_i Hess Phi_i) v = O(h), one sign
/// every step: first order (seed-000 double pendulum, joint angle over 2 s against IDAS:
/// 1.6e-3, 8.2e-4, 4.1e-4 rad at dt 2, 1, 0.5 ms). At the midpoint the step is symmetric
/// (swap n and n+1, h -> -h: the same equations, given Phi(q_n) = 0), hence of even order: 2.
/// lambda is then the mid-step multiplier; the loads read t_{n+1/2} for the same reason.
struct Scheme {
  double ca = 0, cv = 0;
  bool bdf1 = false, trapezoidal = false, midpoint = false;
  double am = 0, af = 0, beta = 0.25, gamma = 0.5, h = 0;
  /// Forces are evaluated at (fw q_{n+1} + (1 - fw) q_n, fw v_{n+1} + (1 - fw) v_n).
  double fw = 1.0;
  explicit Scheme(const IntegratorSettings& set) : h(set.dt) {
    bdf1 = set.type == "bdf1";
    trapezoidal = set.type == "trapezoidal";
    midpoint = set.type == "midpoint";
    if (bdf1) {
      ca = 1.0 / (h * h);
      cv = 1.0 / h;
      return;
    }
    if (midpoint) {  // a = (v_{n+1} - v_n) / h with v_{n+1} = 2 (q_{n+1} - q_n) / h - v_n
      ca = 2.0 / (h * h);
      cv = 2.0 / h;
      fw = 0.5;
      return;
    }
    if (set.type == "generalized_alpha") {
      const double r = set.rhoInf;  // second order for every r in [0, 1]
      am = (2.0 * r - 1.0) / (r + 1.0);
      af = r / (r + 1.0);
      gamma = 0.5 + af - am;
      beta = 0.25 * (gamma + 0.5) * (gamma + 0.5);
    }
    ca = (1.0 - am) / ((1.0 - af) * beta * h * h);
    cv = gamma / (beta * h);
  }
  /// w_0 = a_0, the consistent initial accelerations (Chung-Hulbert's and Arnold-Bruls' start).
  /// A mode with omega h >> 1 released out of equilibrium then overshoots in the first step:
  /// v_1 -> (1 - rho_inf)^2 / 4 h a_0 instead of at most omega x_0, then decays (its energy by
  /// rho_inf^2 per step asymptotically; test GeneralizedAlpha.FirstStepOvershootOfAStiffModeFollowsTheRecurrence).
  static const VecX& pseudo(const State& n) { return n.pseudoAcc.size() ? n.pseudoAcc : n.a; }
  /// History terms (abar, vbar) from the previous step's q, v, a, w (or their
  /// sensitivities: the map is linear, and q_n enters through -ca q_n, -cv q_n).
  void history(const State& n, VecX& abar, VecX& vbar) const {
    if (midpoint) {
      abar = -2.0 / h * n.v;
      vbar = -n.v;
      return;
    }
    if (bdf1) {
      abar = -n.v / h;
      vbar = VecX::Zero(n.v.size());
      return;
    }
    if (trapezoidal) {  // the general formulas below with w = a, in the original arithmetic
      abar = -4.0 / h * n.v - n.a;
      vbar = -n.v;
      return;
    }
    const VecX& w = pseudo(n);
    const VecX jump = n.v / (beta * h) + (0.5 - beta) / beta * w;  // -(w_{n+1} at q = q_n)
    abar = (-(1.0 - am) * jump + am * w - af * n.a) / (1.0 - af);
    vbar = n.v + h * (1.0 - gamma) * w - gamma * h * jump;
  }
  /// w_{n+1} from a_{n+1} (also for sensitivities); empty for BDF-1.
  VecX nextPseudo(const State& n, const VecX& aNext) const {
    if (bdf1 || trapezoidal || midpoint) return VecX();  // trapezoidal: w = a
    return ((1.0 - af) * aNext + af * n.a - am * pseudo(n)) / (1.0 - am);
  }
  /// Where the forces are evaluated: fw x_{n+1} + (1 - fw) x_n (x = q or v); `next` itself
  /// unless fw < 1 (then written into buf), so the other schemes copy nothing per residual.
  const VecX& forcePoint(const VecX& next, const VecX& old, VecX& buf) const {
    if (fw == 1.0) return next;
    buf = fw * next + (1.0 - fw) * old;
    return buf;
  }
  /// The time [s] of the force point of the step ending at t.
  double forceTime(double t) const { return t - (1.0 - fw) * h; }
};

}  // namespace flexsens
