// The mass of a body as an objective (`objectives: - {name, mass: {of: BODY}}`): a function of
// the design parameters alone (density, thickness, cross-section, ...), not of the motion,
// with its exact gradient from the elements' parameter derivatives of their mass matrices.
#pragma once

#include <vector>

#include "core/Model.hpp"
#include "scene/Objective.hpp"

namespace flexsens {

struct ExplicitObjective {
  double value = 0.0;  ///< [kg] for a mass
  VecX gradient;       ///< d value / dp, one entry per parameter
};

/// m = sum over the elements of U^T M_e U, U a unit rigid translation along the first axis
/// (the kinetic energy of a translation at unit speed is m/2, for every element whose mass
/// matrix is constant, whatever its coordinates: positions, ANCF gradients, natural coordinates).
/// dm/dp_k = U^T dM_e/dp_k U from Element::parameterDerivative, for the parameters bound to
/// the element's properties. p: all parameters' values.
ExplicitObjective bodyMass(const Model& m, const std::vector<int>& elements, const VecX& p);

/// The part of objective i that depends on the parameters directly (mass, and the masses in
/// a sum, times their weights); zero for the objectives of the outputs' time series.
ExplicitObjective explicitObjective(const Model& m, const std::vector<ObjectiveSpec>& objectives, size_t i,
                                    const VecX& p);

}  // namespace flexsens
