// Coordinate partitioning with Maggi's state (seed 000, section 2.2), integrated with the
// classic fourth-order Runge-Kutta rule at a fixed step, with forward sensitivities.
//
// Gaussian elimination with full pivoting of Phi_q (m x n) splits q into m dependent and
// f = n - m independent coordinates. The ODE state is y = (q, v_i): all positions (so no
// nonlinear position problem is ever solved; Phi = 0 drifts, reported as the largest |Phi|)
// and the independent velocities. Its right-hand side f(y):
//   v   from  Phi_q,d v_d = -Phi_q,i v_i                           (Phi_q v = 0)
//   a, lambda from [M Phi_q^T; Phi_q 0] [a; lambda] = [Q; -(v^T H_i v)_i]   (index 1)
//   y' = (v, a_i).
// Sensitivities y_p = (q_p, v_i,p) per parameter follow the exact linearization of f, and
// RK4 is applied to y and y_p jointly, so y_p is the exact derivative of the discrete RK4
// solution (up to the linear solves' round-off).
//
// The partition is chosen at the start and again at the start of any step whose dependent
// block Phi_q,d has become ill-conditioned or whose dependent coordinates have come to
// amplify the independent ones (MaggiOptions); the full
// velocities (and their sensitivities) are continuous across a change: the new v_i = v[indep].
#pragma once

#include <vector>

#include "core/Assembler.hpp"
#include "integrators/Settings.hpp"
#include "integrators/State.hpp"

namespace flexsens {

struct MaggiOptions {
  /// Re-partition (at the start of a step) when the 1-norm condition estimate of Phi_q,d
  /// exceeds maxCondition, or exceeds maxConditionGrowth times its value when the partition
  /// was chosen. The growth test is what matters in practice: the block is sampled once per
  /// step, and a mechanism moving at ~1 m/s crosses a singular dependent block (e.g. the rigid
  /// five-bar's bar 3-B passing the vertical with z3 independent, near t = 0.49 s) within a
  /// few steps; its condition estimate rises like 1/distance and RK4 stages straddling the
  /// singularity are meaningless long before any absolute threshold is met.
  double maxCondition = 1e8;
  double maxConditionGrowth = 10.0;
  /// ... or when max |B_ij| of B = Phi_q,d^-1 Phi_q,i (dq_d = -B dq_i: how strongly the
  /// dependent coordinates amplify the independent ones) exceeds maxCouplingGrowth times
  /// max(1, its value when the partition was chosen). The condition estimate of Phi_q,d cannot
  /// see a 1 x 1 block degrade (its rcond is 1 until it is exactly 0): a rigid pendulum
  /// released horizontal (Phi = x^2 + y^2 - L^2, x dependent) kept x through the bottom, where
  /// v_x = -(y / x) v_y is 0/0, and ended 0.12 m off at every dt from 2.5e-3 to 1e-3 s.
  double maxCouplingGrowth = 2.0;
  /// Stop when |Phi|_inf exceeds this; <= 0 picks 1e-2 max(1 m, |q0|_inf)^2 (distance
  /// constraints are d^2 - L^2 [m^2]: positions a few per cent of the model's size off
  /// the constraints mean the explicit scheme has gone unstable, the result is meaningless).
  double maxConstraintDrift = 0.0;
};

/// What the partitioning did (for tests and diagnostics).
struct MaggiReport {
  std::vector<double> partitionTimes;            ///< [s]: t0, then every re-partition
  std::vector<std::vector<int>> independent;     ///< independent coordinates of each partition
  /// Each step's embedded third-order estimate of its local position error,
  /// |h/6 (k4 - f(y_{n+1}))|_inf [m, or the coordinate's unit], summed over the steps so far
  /// (in the asymptotic range an upper estimate of the global error: the third-order
  /// solution's local errors, O(h^4) a step against RK4's O(h^5)) ...
  double errorEstimate = 0.0;
  double maxStepErrorEstimate = 0.0;  ///< ... its largest value in one step ...
  double maxStepErrorTime = 0.0;      ///< ... at the end of that step [s]
};

/// Integrates from start (q, v and q_p, v_p taken as given, assumed consistent) with RK4 at
/// the fixed step set.dt; frames every set.frameInterval and at the end. Throws
/// NumericalError (time, step, quantity, suggestion) on a non-finite state, a singular
/// dependent block or a runaway constraint drift; never emits a non-finite frame.
IntegratorStats integrateMaggi(const Assembler& as, const VecX& p, StateWithSens start,
                               const IntegratorSettings& set, Observer& obs);
IntegratorStats integrateMaggi(const Assembler& as, const VecX& p, StateWithSens start,
                               const IntegratorSettings& set, Observer& obs,
                               const MaggiOptions& opt, MaggiReport* report = nullptr);

}  // namespace flexsens
