// `optimize:` of a scene: what `flexsens optimize` minimizes (an objective of `objectives:`),
// over which parameters of `parameters:` (each within bounds), subject to which other
// objectives' bounds, with which NLopt algorithm (app/Optimize.hpp).
#pragma once

#include <string>
#include <vector>

namespace flexsens {

/// One design variable: a parameter, or a per-element family (all its members, each with the
/// same bounds). The bounds are in the parameter's unit.
struct OptimizeVariable {
  std::string name;             ///< as written under variables (a parameter or a family)
  std::vector<int> parameters;  ///< indices into Model::parameters
  double lower = 0.0, upper = 0.0;
};

/// An objective held within a bound: J <= max (upper) or J >= min.
struct OptimizeConstraint {
  int objective = -1;  ///< index into Scene::objectives
  double bound = 0.0;
  bool upper = true;
};

struct OptimizeSpec {
  bool given = false;  ///< the scene has `optimize:`
  int objective = -1;  ///< index into Scene::objectives
  std::string algorithm = "mma";  ///< mma | slsqp | lbfgs
  std::vector<OptimizeVariable> variables;
  std::vector<OptimizeConstraint> constraints;
  int maxEvaluations = 100;
  double tolerance = 1e-8;  ///< relative, on the objective and on the variables
  std::string gradient = "adjoint";  ///< adjoint | forward (dynamic scenes; static: exact static sensitivities)
  std::string where;  ///< "file:line:column: key 'optimize'", for errors found later
};

}  // namespace flexsens
