// Mass-orthogonal projections of a fixed-step step's velocities and accelerations onto the
// velocity and acceleration constraints at t_{n+1} (Bayo and Ledesma's index-3 augmented
// Lagrangian with projections, ALI3-P, here on the trapezoidal rule and generalized-alpha):
//   [W  Phi_q^T] [dv ]   [0                   ]      [W  Phi_q^T] [da   ]   [0                          ]
//   [Phi_q   0 ] [mu ] = [-(Phi_q v~ + Phi_t) ],     [Phi_q   0 ] [kappa] = [-(Phi_q a~ + v^T H v + g) ]
// with v = v~ + dv, a = a~ + da. An index-3 scheme enforces Phi = 0 only: the trapezoidal rule
// then carries the velocities' and accelerations' parts along the constraint directions
// undamped (a_n+1 = 4 (q_n+1 - q_n) / h^2 - 4 v_n / h - a_n), and with nonlinear constraints
// they grow (the massless satellite: |a| 5e3 -> 1e6 m/s^2 in 0.8 s). The projections remove
// them every step and change nothing else: W = M is the kinetic-energy metric, so the
// smallest change of kinetic energy. Massless coordinates get a weight eps = 1e-8 of the
// largest mass: their velocities and accelerations carry no inertia and take up the
// correction of the constraints they share (in the limit eps -> 0, free).
// The sensitivities differentiate the projections exactly (constraints with zero third
// derivatives in q, as every constraint here; the drivers' time terms included).
#pragma once

#include <vector>

#include "core/Assembler.hpp"
#include "core/SparseLU.hpp"
#include "integrators/State.hpp"

namespace flexsens {

class MotionProjection {
 public:
  MotionProjection(const Assembler& as, const VecX& p, const std::vector<int>& massless);
  /// Projects x.v and x.a at x.q, x.t (the assembler's time set to x.t); `step` names the
  /// step in error messages. Keeps the corrections and multipliers for sensitivity().
  void project(State& x, long step);
  /// For parameter k: d.q given, d.v and d.a the scheme's (before projection) -> projected.
  /// Call after project() with the same x.
  void sensitivity(const State& x, int k, State& d) const;
  long factorizations() const { return lu_.factorizations(); }

 private:
  const Assembler& as_;
  VecX p_;
  SpMat weight_;  ///< W = M + eps on the massless coordinates' diagonal
  SparseAccumulator acc_;
  SparseLU lu_;
  VecX dv_, da_, mu_, kappa_;  ///< the last projection's corrections and multipliers
};

}  // namespace flexsens
