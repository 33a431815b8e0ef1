// gradient.vtu of `flexsens gradient`: the model at its scene positions with, for each objective
// and each per-element parameter family (`per: element`), a cell array "d<objective>/d<family>"
// holding dJ/dp of the parameter of each cell (NaN on cells of no parameter of the family), so
// that ParaView shows where the design matters.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "core/Model.hpp"
#include "integrators/State.hpp"

namespace flexsens {

/// True when the model has per-element parameters (only then is there a field to write).
bool hasPerElementParameters(const Model& m);
/// Writes the grid to path (shown as `shown` in errors: OutputError); gradients are
/// (objective name, dJ/dp over all parameters).
void writeGradientVtu(const std::string& path, const std::string& shown, const Model& m,
                      const std::vector<std::pair<std::string, VecX>>& gradients);
/// The same grid with the per-element parameters' values p (all parameters), one cell array
/// per family named by it (`flexsens optimize`'s optimum.vtu: the optimized thicknesses).
void writeParameterVtu(const std::string& path, const std::string& shown, const Model& m, const VecX& p);

}  // namespace flexsens
