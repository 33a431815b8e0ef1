// `flexsens gradient SCENE`: the values of the scene's objectives (scene/Objective.hpp) and
// their exact gradients dJ/dp with respect to the design parameters, by the discrete adjoint
// (integrators/Adjoint.hpp: one backward sweep for all parameters) or by the forward
// sensitivities (one sensitivity solve per parameter and step); both differentiate the same
// discrete objective (app/Objectives.hpp), so they agree to round-off and solver tolerances.
// On integrator idas both take the objectives in continuous time and agree to the integration
// tolerance (app/IdasGradient.hpp, integrators/IdasAdjoint.hpp).
#pragma once

#include <string>
#include <vector>

#include "app/Run.hpp"
#include "integrators/Adjoint.hpp"

namespace flexsens {

struct GradientRequest {
  std::string scenePath;
  std::string caseName;    ///< a PIM case of the scene; "" the plain model with every parameter
  std::string objective;   ///< "" every objective of the scene
  std::string method = "adjoint";  ///< adjoint | forward
  std::string outDir;      ///< "" <output.directory>-gradient
  long checkpointEvery = 0;  ///< adjoint: k; 0 from the memory budget
  /// The static equilibrium (`flexsens static`'s last load step) instead of the motion; a scene
  /// without `integrator` is always static.
  bool statics = false;
  RunOptions options;      ///< --integrator, --t-end, --dt, ... (the run's overrides)
  std::string sceneText;   ///< non-empty: the scene itself (readRequestedScene)
};

struct ObjectiveGradient {
  std::string name;
  double value = 0.0;
  VecX gradient;  ///< dJ/dp, one entry per parameter
};

struct GradientResult {
  std::string method, directory, status = "complete", reason;  ///< status complete | suspect (the energy audit's reason)
  std::vector<std::string> parameters;
  std::vector<ObjectiveGradient> objectives;
  IntegratorStats stats;        ///< the forward pass
  AdjointStatistics adjoint;    ///< method adjoint
  long steps = 0;
  double wallSeconds = 0.0;
  bool field = false;  ///< gradient.vtu written (per-element parameters)
};

/// Computes the gradients of the scene's objectives (or the one named) without writing.
/// InputError for a scene without objectives, an unknown objective or method, an integrator
/// without the method (maggi_rk4), an objective other than terminal on a static scene. Integrator
/// idas: the objectives in continuous time and IDAS' continuous adjoint (app/IdasGradient.hpp).
/// Statics: J at the equilibrium, dJ/dp from the exact static sensitivities (one
/// factorization of the equilibrium's matrix, a solve per parameter), whatever the method.
GradientResult computeGradients(const Scene& scene, const GradientRequest& request);
/// gradient.json's text: one object {"objective", "value", "gradient", "statistics"}, or an
/// array of them when no objective was named.
std::string gradientJson(const GradientResult& result, bool single);
/// Reads the scene (and case), applies the options, computes and writes DIR/gradient.json.
GradientResult gradientCommand(const GradientRequest& request);

}  // namespace flexsens
