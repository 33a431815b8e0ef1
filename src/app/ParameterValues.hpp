// Runs at design parameter values other than the scene's nominal ones (Python's
// Scene.run(parameters=...), RunOptions::parameters). The perturbed mechanism starts where the
// scene says it does: a PIM case defines how the initial state depends on its parameters
// (pim/Pim.hpp), so the start is its nonlinear assembly at the new values, exactly as the
// perturbed runs of --method nd start (app/FiniteDifferences); without a case, the least-norm
// rule (the nominal start projected onto Phi(q, p) = 0). The velocities are the nominal ones
// plus v_p (p - p0), projected onto the velocity constraints. The central difference of two
// such runs therefore converges to the run's own sensitivities.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "scene/Scene.hpp"

namespace flexsens {

/// Parameter values by name in the order given (Python's Scene.run(parameters=...)).
using ParameterChanges = std::vector<std::pair<std::string, double>>;

/// Sets the nominal values of the named parameters, nothing else. InputError (the scene file,
/// key 'parameters') for a name the model does not have as a parameter (with a PIM case: a
/// parameter of the scene that is not the case's) or a value that is not finite.
void setParameterValues(Scene& scene, const ParameterChanges& values);

/// Makes `scene` the scene at the new values: the perturbed start described above becomes its
/// initial positions and velocities, the values its nominal ones. No-op for no change.
void applyParameterValues(Scene& scene, const ParameterChanges& values);

}  // namespace flexsens
