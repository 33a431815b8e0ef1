// Consistent initial state of the index-3 DAE and of its sensitivities:
// positions on Phi = 0, velocities on Phi_q v = 0, then accelerations and multipliers from
//   [M  Phi_q^T] [a     ]   [Q              ]
//   [Phi_q   0 ] [lambda] = [-(v^T H_i v)_i ]
// and the parameter derivative of that same system for a_p and lambda_p.
#pragma once

#include <memory>
#include <vector>

#include "core/Assembler.hpp"
#include "core/SparseLU.hpp"
#include "integrators/State.hpp"

namespace flexsens {

/// Least-norm solutions x of Phi_q(q, p) x = r for several r: the saddle-point system
/// [I Phi_q^T; Phi_q 0] [x; mu] = [0; r] factorized sparse once, like the Newton matrices, so
/// the cost grows like n (a dense complete orthogonal decomposition costs n m^2: 80% of a
/// 50-step run of the satellite refined 10x). A Phi_q without full row rank makes that matrix
/// singular; then the dense decomposition gives the least-squares least-norm x.
class LeastNorm {
 public:
  LeastNorm(const Assembler& as, const VecX& q, const VecX& p);
  VecX solve(const VecX& r) const;

 private:
  int n_, m_;
  SpMat A_;
  std::unique_ptr<SparseLU> lu_;
  MatX denseJ_;  ///< the fallback's Phi_q (empty while the sparse factorization serves)
};

/// Moves q onto Phi(q, p) = 0 by least-norm Gauss-Newton; throws NumericalError if it fails.
VecX projectPositions(const Assembler& as, VecX q, const VecX& p, double tol = 1e-12);
/// Removes the component of v violating Phi_q v + Phi_t = 0 (least-norm correction; Phi_t at
/// the assembler's time: drivers).
VecX projectVelocities(const Assembler& as, const VecX& q, const VecX& v, const VecX& p);
/// Fills s.a and s.lambda from s.q, s.v (index-1 system at time s.t).
void solveAccelerations(const Assembler& as, State& s, const VecX& p);
/// Right-hand side of Phi_q v_p = -((Phi_q v + Phi_t)_q q_p + Phi_qp v + Phi_tp): the
/// derivative of the velocity constraint with respect to parameter k, given q_p = dq.
VecX velocitySensitivityRhs(const Assembler& as, const VecX& q, const VecX& v, const VecX& p, int k,
                            const VecX& dq);
/// Given x (q, v, a, lambda) and d.q, d.v for parameter k, fills d.a and d.lambda.
void solveAccelerationSensitivity(const Assembler& as, const State& x, const VecX& p, int k,
                                  State& d);
/// The same for parameters first, first + 1, ... (ds[j] for parameter first + j) with one
/// factorization: a per-element parameter family of hundreds costs one solve with that many
/// columns, not that many factorizations.
void solveAccelerationSensitivities(const Assembler& as, const State& x, const VecX& p, std::vector<State>& ds,
                                    int first = 0);

// --- massless coordinates (parts with `inertia: none`): rows of M that are zero. Their
// equations of motion are equilibrium equations F = (Phi_q^T lambda - Q)_m = 0, so at the start
// their positions, velocities and sensitivities follow from the other coordinates.
/// Coordinates whose row of M(p) is zero, ascending (empty for most models).
std::vector<int> masslessCoordinates(const Assembler& as, const VecX& p);
/// Moves the massless coordinates of s onto equilibrium with the others held: unknowns q_m and
/// the multipliers of the constraints C touching them, equations F = 0 and Phi_C = 0 (Newton);
/// then sets v_m to the quasi-static rate (dF/dt = 0 and d Phi_C / dt = 0 at the given v of the
/// other coordinates; damping forces on massless coordinates are not supported). Throws
/// NumericalError naming the coordinates of a massless direction without stiffness.
void equilibrateMassless(const Assembler& as, State& s, const VecX& p);
/// The same for a parameter sensitivity d of state x (d.q, d.v of the other coordinates
/// given): d.q_m exactly from the derivative of those equations with respect to p_k; d.v_m as
/// the rate at fixed K (exact when x.v = 0; otherwise the term with second derivatives of Q is
/// left out). No integrator reads d.v_m at the start: IDAS treats v_m as algebraic (solved in
/// its first step), the fixed-step schemes read velocities of massless coordinates only through
/// damping forces, which massless coordinates may not carry.
void masslessSensitivity(const Assembler& as, const State& x, const VecX& p, int k, State& d);

/// Stability of the massless parts' equilibrium at state s (the other coordinates held): the
/// extreme eigenvalues of their tangent stiffness K_mm = (-dQ/dq + H(lambda))_mm reduced to the
/// directions the constraints C touching them leave free, Z^T K_mm Z (Z spans the null space
/// of Phi_Cm). A smallest eigenvalue at or below zero means that equilibrium is unstable or at
/// a fold (a massless spring buckling or snapping through): there the quasi-static idealization
/// has no solution that continues, while the part with its mass would move fast.
struct MasslessStability {
  double minEigenvalue = 0.0, maxEigenvalue = 0.0;  ///< [N/m]
  std::string coordinate;  ///< the coordinate with the largest part in the softest direction
};
/// Empty optional-like: maxEigenvalue 0 when the model has no massless coordinates.
MasslessStability masslessStability(const Assembler& as, const State& s, const VecX& p,
                                    const std::vector<int>& massless);

/// Augmented matrix [M + c H(lambda)..] helpers shared by the integrators.
SpMat augmentedMatrix(const Assembler& as, const VecX& q, const VecX& p);

}  // namespace flexsens
