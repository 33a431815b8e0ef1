// `flexsens optimize SCENE`: minimizes an objective of the scene over design parameters within
// bounds, subject to bounds on other objectives (the scene's `optimize:`, scene/OptimizeSpec.hpp),
// with NLopt's gradient-based algorithms (MMA, SLSQP, L-BFGS). Every evaluation is one run of
// `flexsens gradient` in this process at the optimizer's parameter values: one forward pass, the
// objective and the constraints from it, their gradients by one backward sweep (adjoint; or the
// forward sensitivities; a static scene: its exact static sensitivities). An evaluation the model
// cannot complete (a rejected step, a Newton failure) stops the optimizer; the best point so
// far is kept and written with the model's message.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "core/Types.hpp"
#include "scene/Scene.hpp"

namespace flexsens {

struct OptimizeRequest {
  std::string scenePath;
  std::string outDir;  ///< "" <output.directory>-optimize
  bool plots = true;   ///< draw history.png (scripts/plot_optimize.py)
};

/// One run of the model at the optimizer's point x.
struct OptimizeEvaluation {
  int index = 0;  ///< 1, 2, ...
  VecX x;         ///< the variables' values (OptimizeResult::variables)
  bool ok = false;
  std::string status;  ///< complete | suspect (energy audit) | failed
  double objective = 0.0;
  std::vector<double> constraints;  ///< the constraint objectives' values
  VecX gradient;                    ///< dJ/dx
  std::vector<VecX> constraintGradients;
  double seconds = 0.0;
  std::string message;  ///< failed: the model's message; suspect: the audit's reason
};

struct OptimizeResult {
  /// converged | stalled (NLopt stopped at a point whose KKT residual exceeds 0.1) | suspect
  /// (converged, the best run doubted by the energy audit) | max_evaluations |
  /// roundoff_limited | infeasible | failed | interrupted | nlopt_failure
  std::string status;
  std::string nloptResult = "NOT_RUN";  ///< NLopt's return code by its name (FTOL_REACHED, ...)
  int nloptCode = 0;
  std::string algorithm, gradient, objective;
  std::vector<std::string> variables;  ///< one per parameter (a family's members each)
  VecX lower, upper;
  std::vector<std::string> constraints;  ///< "<objective> <= bound" / ">="
  std::vector<double> bounds;
  std::vector<bool> upperBounds;
  std::vector<OptimizeEvaluation> history;
  int best = -1;  ///< index into history: the lowest objective among the feasible evaluations
  int failed = -1;  ///< index into history of the evaluation that failed
  int interruptedBy = 0;
  double wallSeconds = 0.0;
  /// The best point's stationarity: |g + A^T mu|_inf / max(|g|_inf, |g_start|_inf) over the variables not held by
  /// an active bound (A: the active constraints' gradients, mu their least-squares multipliers);
  /// near 0 at a KKT point, NaN when not computed. A check on NLopt's stop, not a status.
  double kktResidual = std::numeric_limits<double>::quiet_NaN();
  std::string directory, plotNote, sceneNote;

  /// Exit code: 0 converged, 5 stalled, suspect, stopped without convergence or infeasible, 2 an evaluation
  /// failed, 3 NLopt failed, 128 + signal interrupted.
  int exitCode() const;
};

/// The evaluations `flexsens optimize` makes, at the given points (the variables' values in
/// the order of OptimizeResult::variables), each from the scene as read; for tests. A failed
/// evaluation has ok false and the model's message.
std::vector<OptimizeEvaluation> evaluatePoints(Scene& scene, const std::vector<VecX>& points);

/// Reads the scene, runs the optimizer and writes DIR: history.csv (history_variables.csv
/// for more than 20 variables), optimize.json, optimized.yaml, optimum.csv, history.png.
/// InputError before anything is written (a scene without `optimize:`, an integrator without a
/// gradient path).
OptimizeResult optimizeCommand(const OptimizeRequest& request);

}  // namespace flexsens
