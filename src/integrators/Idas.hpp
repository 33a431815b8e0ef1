// SUNDIALS IDAS (variable-order BDF) on the stabilized index-2 (GGL) form
//   q' - v + Phi_q^T mu = 0,  M v' + Phi_q^T lambda - Q = 0,  Phi = 0,  Phi_q v = 0
// with y = (q, v, lambda, mu); lambda and mu are algebraic (IDASetId) and kept out of the
// error test (IDASetSuppressAlg). Jacobian dF/dy + cj dF/dy' assembled sparse for KLU; the
// sensitivity residual is analytic (resS), staggered corrector.
#pragma once

#include "core/Assembler.hpp"
#include "integrators/Settings.hpp"
#include "integrators/State.hpp"

namespace flexsens {

/// GGL residual F(y, y') with y = (q, v, lambda, mu); M is the constant mass matrix.
VecX gglResidual(const Assembler& as, const VecX& p, const SpMat& M, const VecX& y, const VecX& yp);
/// dF/dy + cj dF/dy', assembled through acc (pattern cached there).
const SpMat& gglJacobian(const Assembler& as, const VecX& p, const VecX& y, double cj,
                         SparseAccumulator& acc);
/// Sensitivity residual F_y s + F_y' s' + F_p for parameter k.
VecX gglSensitivityResidual(const Assembler& as, const VecX& p, const SpMat& M, const VecX& y,
                            const VecX& yp, int k, const VecX& s, const VecX& sd);
/// The same with -dQ/dq and -dQ/dv at y given (assembled once for all parameters: rebuilding
/// them per parameter and call was a quarter of an IDAS run's time, in pattern builds and heap).
VecX gglSensitivityResidual(const Assembler& as, const VecX& p, const SpMat& M, const VecX& y,
                            const VecX& yp, int k, const VecX& s, const VecX& sd, const SpMat& negQq,
                            const SpMat& negQv);
/// -dQ/dq and -dQ/dv at the positions and velocities of y, into kq and kv (patterns cached).
void gglForceJacobians(const Assembler& as, const VecX& p, const VecX& y, SparseAccumulator& kq,
                       SparseAccumulator& kv);

IntegratorStats integrateIdas(const Assembler& as, const VecX& p, const StateWithSens& start,
                              const IntegratorSettings& set, Observer& obs);

}  // namespace flexsens
