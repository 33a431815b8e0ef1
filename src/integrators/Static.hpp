// Static equilibrium with load stepping:
//   Q(q, 0, p) - Phi_q^T lambda = 0,   Phi(q, p) = 0
// solved by Newton on the sparse matrix
//   [ -dQ/dq + sum_i lambda_i Hess(Phi_i)   Phi_q^T ]
//   [  Phi_q                                0       ]
// assembled through the Assembler (SparseAccumulator) and factorized by KLU. The load path is
// a function p(s) of the load factor s in (0, 1] supplied by the caller (e.g. a force component
// bound to a design parameter, scaled by s); the solver takes `steps` equal increments of s
// and converges Newton at each, starting from the previous equilibrium. Works with m = 0.
//
// Units: q [m], lambda in the units of the constraints' conjugate forces ([N] for position
// constraints), residuals [N]. Converged when the Newton update is small: |dq|_inf <= tol
// (1 + |q|_inf) (the dynamic Newton's test) and |dlambda|_inf <= tol (1 + F), F the force scale
// max(|Q|_inf, |Phi_q^T lambda|_inf, |lambda|_inf, k (1 + |q|_inf)) with k the largest diagonal
// stiffness (the force the positions' tolerance stands for). A load step that plain Newton does
// not solve is solved again from the last equilibrium with a backtracking line search on |R|_2.
#pragma once

#include <functional>
#include <vector>

#include "core/Assembler.hpp"

namespace flexsens {

struct StaticSettings {
  int steps = 10;           ///< equal load increments of the load factor s
  double time = 0.0;        ///< time [s] at which loads and drivers are evaluated
  int maxIterations = 25;   ///< Newton iterations per load step
  double tol = 1e-10;       ///< Newton tolerance (above); `flexsens static`: integrator.newton_tol
  /// Parameters at load factor s in (0, 1]; must give the solver's p at s = 1. Empty: p at every
  /// step (no stepping, a single Newton solve).
  std::function<VecX(double)> paramsAt;
  /// Step the applied loads instead: Assembler::setLoadFactor(s) at each step (gravity and
  /// load elements scaled by s), back to 1 on return. Used by `flexsens static`.
  bool stepLoadFactor = false;
  /// Called after each converged load step with the load factor, q and lambda (the
  /// assembler's load factor is still s then, so derivatives taken there belong to step s).
  std::function<void(int step, double loadFactor, const VecX& q, const VecX& lambda)> onStep;
};

/// The direct solver's work in a static solve (summary.json's statistics).
struct FactorizationCounters {
  long factorizations = 0;
  double seconds = 0.0;  ///< wall time in numeric factorizations [s]
  double maxFill = 0.0;  ///< largest nnz(L + U) / nnz(A) (a Cholesky or LDL^T factor: 2 nnz(L) - n)
  void add(const FactorizationCounters& o);
};

struct StaticReport {
  int steps = 0;                       ///< load steps taken
  int iterations = 0;                  ///< Newton iterations, all steps
  std::vector<int> iterationsPerStep;
  double residualNorm = 0.0;           ///< |Q - Phi_q^T lambda|_inf at the returned q [N]
  double constraintNorm = 0.0;         ///< |Phi|_inf at the returned q
  VecX lambda;                         ///< multipliers at the returned q
  FactorizationCounters factor;        ///< the Newton matrices' factorizations
};

/// Equilibrium at parameters p (the load factor 1 of s.paramsAt), starting from q0.
/// Throws NumericalError naming the load step, the failing update with its bound, the
/// residual and what to change on failure.
VecX solveStatic(const Assembler& as, const VecX& p, VecX q0, const StaticSettings& s,
                 StaticReport* report = nullptr);

/// Exact static sensitivities at an equilibrium (q, lambda) of R = [Phi_q^T lambda - Q; Phi]:
/// R_x [q_p; lambda_p] = -R_p with R_p = [Phi_qp^T lambda - Q_p; Phi_p], one column per
/// parameter, with the Newton matrix R_x factorized once (plus one refinement step).
struct StaticSensitivity {
  MatX qp;       ///< n x np [m per parameter unit]
  MatX lambdap;  ///< m x np
  FactorizationCounters factor;  ///< the factorization the sensitivities took
};
StaticSensitivity staticSensitivities(const Assembler& as, const VecX& q, const VecX& lambda, const VecX& p);

/// Small-displacement (linear) statics at the rest state q0: with K = -dQ/dq and the
/// constraints linearized at (q0, lambda = 0),
///   [K, Phi_q^T; Phi_q, 0] [u; lambda] = [Q(q0); -Phi(q0)],   q = q0 + u,
/// one solve (plus a refinement step). Loads are taken at load factor 1 and time s.time.
/// report (optional) gets 1 step, 1 iteration, the system's residual and lambda.
VecX solveLinearStatic(const Assembler& as, const VecX& p, const VecX& q0, double time,
                       StaticReport* report = nullptr);

/// Sensitivities of the linear solution: [K, Phi_q^T; Phi_q, 0] [u_p; lambda_p] = -[-Q_p -
/// Q_qp u + Phi_qp^T lambda; Phi_p + Phi_qp u], all at (q0, p). Q_qp u, the stiffness's
/// parameter derivative along u, is a fourth-order central difference of the analytic Q_p
/// along u (relative error ~1e-10 on smooth elements; exactly 0 for loads).
StaticSensitivity linearStaticSensitivities(const Assembler& as, const VecX& q0, const VecX& q, const VecX& lambda,
                                            const VecX& p);

/// Linear load path p(s) = pUnloaded + s (pLoaded - pUnloaded), for StaticSettings::paramsAt
/// (only sensible when the loaded parameters enter the forces linearly, e.g. point forces).
std::function<VecX(double)> linearLoadPath(const VecX& pUnloaded, const VecX& pLoaded);

}  // namespace flexsens
