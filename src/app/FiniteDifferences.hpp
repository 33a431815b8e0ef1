// External numerical differentiation (method "nd"): sensitivities as finite differences of
// whole perturbed simulations. Each perturbed run starts from a consistent perturbed
// initial state: the PIM's nonlinear assembly at p +/- h when the scene has a case (the
// least-norm projection otherwise), with velocities v0 +/- h v_p0 projected on Phi_q v = 0.
#pragma once

#include <string>

#include "app/Run.hpp"

namespace flexsens {

struct NdSettings {
  std::string scheme = "central";  ///< forward | central
  double step = 1e-6;              ///< relative step: h_k = step * max(|p_k|, 1)
};

/// Integrates the nominal and the perturbed models and sends frames whose sensitivities are
/// the finite differences to `obs`. `start` is the nominal initial state with the PIM (or
/// least-norm) initial sensitivities, used for the perturbed initial velocities.
IntegratorStats integrateFiniteDifferences(const Assembler& as, const VecX& p0,
                                           const StateWithSens& start, const PimCase* pim,
                                           const IntegratorSettings& set, const NdSettings& nd,
                                           Observer& obs);

}  // namespace flexsens
