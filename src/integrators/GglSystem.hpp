// The stabilized index-2 (GGL) form of the equations of motion that IDAS integrates,
//   q' - v + Phi_q^T mu = 0,  M v' + Phi_q^T lambda - Q = 0,  Phi = 0,  Phi_q v = 0,
// with y = (q, v, lambda, mu): its residual, iteration matrix dF/dy + cj dF/dy' and sensitivity
// residual, as plain functions of the assembler (integrators/IdasStepper drives IDAS with them).
#pragma once

#include <vector>

#include "core/Assembler.hpp"

namespace flexsens {

/// Constraint rows whose velocity-level GGL row is replaced by mu_r = 0: the rows touching
/// massless coordinates (ascending). Their multipliers lambda_r are fixed algebraically by the
/// massless coordinates' equilibrium (index 1), so they need no velocity stabilization; with it,
/// v_m = q_m' + (Phi_q^T mu)_m made v_m and mu index-2 variables through the derivative of an
/// algebraic q_m, and IDAS' corrector failed at random times on the massless satellite.
std::vector<int> gglPinnedRows(const Assembler& as, const std::vector<int>& massless);
/// GGL residual F(y, y') with y = (q, v, lambda, mu); M is the constant mass matrix; rows
/// `pinned` of the velocity constraints read mu_r = 0 instead.
VecX gglResidual(const Assembler& as, const VecX& p, const SpMat& M, const VecX& y, const VecX& yp,
                 const std::vector<int>& pinned = {});
/// dF/dy + cj dF/dy', assembled through acc (pattern cached there).
const SpMat& gglJacobian(const Assembler& as, const VecX& p, const VecX& y, double cj,
                         SparseAccumulator& acc, const std::vector<int>& pinned = {});
/// Sensitivity residual F_y s + F_y' s' + F_p for parameter k.
VecX gglSensitivityResidual(const Assembler& as, const VecX& p, const SpMat& M, const VecX& y,
                            const VecX& yp, int k, const VecX& s, const VecX& sd,
                            const std::vector<int>& pinned = {});
/// The same with Qq = dQ/dq and Qv = dQ/dv at y given (assembled once for all parameters: rebuilding
/// them per parameter and call was a quarter of an IDAS run's time, in pattern builds and heap).
VecX gglSensitivityResidual(const Assembler& as, const VecX& p, const SpMat& M, const VecX& y,
                            const VecX& yp, int k, const VecX& s, const VecX& sd, const SpMat& Qq,
                            const SpMat& Qv, const std::vector<int>& pinned = {});
/// dQ/dq and dQ/dv at the positions and velocities of y, into kq and kv (one element pass).
void gglForceJacobians(const Assembler& as, const VecX& p, const VecX& y, SparseAccumulator& kq,
                       SparseAccumulator& kv);

}  // namespace flexsens
