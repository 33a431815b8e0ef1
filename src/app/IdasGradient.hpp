// `flexsens gradient` on integrator idas: the objectives in continuous time, on the solution
// IDAS interpolates between its own (adaptive) steps, and their gradients by IDAS' forward
// sensitivities or by the continuous adjoint (integrators/IdasAdjoint.hpp):
//   integral  J = integral over [from, to] of o(t)^power dt
//   tracking  J = integral over [from, to] of (o(t) - r(t))^2 dt
//   max       J = m + ln(integral over [from, to] of exp(rho (o - m)) dt / (to - from)) / rho,
//             the KS mean of the continuous output (m its largest sample): J <= max o, -> max o
//             as rho grows
//   terminal  J = o(at); the adjoint takes at = t_end only (its terminal condition; a jump
//             condition inside the run is not set up)
//   sum       J = sum_j weight_j J_j
// The integrals are 3-point Gauss-Legendre rules on every IDAS step (the step's interpolating
// polynomial), so J and its gradient carry the integration tolerance, not round-off.
#pragma once

#include <vector>

#include "app/Gradient.hpp"

namespace flexsens {

/// InputError when objective sel[i] (or a term of it) is terminal before t_end (method adjoint).
void requireIdasAdjointObjectives(const Scene& sc, const std::vector<size_t>& sel);

/// The values (one per selected objective) and gradients (parameters x objectives) on an IDAS
/// run of the scene; fills res' statistics. `audit` sees the run as in flexsens run.
MatX idasGradients(const Scene& sc, const Assembler& as, const VecX& p, const StateWithSens& start,
                   const std::vector<size_t>& sel, const GradientRequest& req, Observer& audit, GradientResult& res,
                   std::vector<double>& values);

}  // namespace flexsens
