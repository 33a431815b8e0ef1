// The paper's fixed-step integrators on the index-3 form: trapezoidal rule (Newmark
// beta = 1/4, gamma = 1/2) and BDF-1 (backward Euler on q and v), and generalized-alpha
// (Arnold-Bruls; rho_inf sets the high-frequency damping, 1 = none). Each step solves
//   sigma (M a(q) + Phi_q^T lambda - Q(q, v(q))) = 0,  Phi(q) = 0
// for q_{n+1} and lambda~ = sigma lambda with Newton and KLU, where a(q) = ca (q - q_n) + abar,
// v(q) = cv (q - q_n) + vbar and sigma = 1/ca; integrator.newton: full (a factorization per
// iteration) or modified (the factorization kept while the iteration contracts fast).
// Sensitivities are the exact derivative of this discrete scheme: one more linear solve per
// parameter and step with the Newton matrix at the converged point, by GMRES preconditioned
// with the kept LU (core/PreconditionedSolve.hpp), or a factorization when that stalls.
#pragma once

#include "core/Assembler.hpp"
#include "integrators/Settings.hpp"
#include "integrators/State.hpp"

namespace flexsens {

IntegratorStats integrateFixedStep(const Assembler& as, const VecX& p, StateWithSens start,
                                   const IntegratorSettings& set, Observer& obs);

}  // namespace flexsens
