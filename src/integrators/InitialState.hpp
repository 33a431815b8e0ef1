// Consistent initial state of the index-3 DAE and of its sensitivities:
// positions on Phi = 0, velocities on Phi_q v = 0, then accelerations and multipliers from
//   [M  Phi_q^T] [a     ]   [Q              ]
//   [Phi_q   0 ] [lambda] = [-(v^T H_i v)_i ]
// and the parameter derivative of that same system for a_p and lambda_p.
#pragma once

#include "core/Assembler.hpp"
#include "integrators/State.hpp"

namespace flexsens {

/// Moves q onto Phi(q, p) = 0 by least-norm Gauss-Newton; throws NumericalError if it fails.
VecX projectPositions(const Assembler& as, VecX q, const VecX& p, double tol = 1e-12);
/// Removes the component of v violating Phi_q v = 0 (least-norm correction).
VecX projectVelocities(const Assembler& as, const VecX& q, const VecX& v, const VecX& p);
/// Fills s.a and s.lambda from s.q, s.v (index-1 system at time s.t).
void solveAccelerations(const Assembler& as, State& s, const VecX& p);
/// Given x (q, v, a, lambda) and d.q, d.v for parameter k, fills d.a and d.lambda.
void solveAccelerationSensitivity(const Assembler& as, const State& x, const VecX& p, int k,
                                  State& d);

/// Augmented matrix [M + c H(lambda)..] helpers shared by the integrators.
SpMat augmentedMatrix(const Assembler& as, const VecX& q, const VecX& p);

}  // namespace flexsens
