// `flexsens static SCENE`: load-stepped static equilibrium of a scene with its exact static
// sensitivities dq/dp = -K_T^-1 dR/dp, written like a run (series.csv with one row per load
// step, VTK frames, summary.json).
#pragma once

#include <string>

#include "app/Run.hpp"
#include "integrators/Static.hpp"

namespace flexsens {

struct StaticResult {
  std::string directory;
  int loadSteps = 0;
  int newtonIterations = 0;
  double residualNorm = 0.0;    ///< |Q - Phi_q^T lambda|_inf at the end [N]
  double constraintNorm = 0.0;  ///< |Phi|_inf at the end
  double wallSeconds = 0.0;
  FactorizationCounters newtonFactor;       ///< the Newton matrices' (or the linear system's)
  FactorizationCounters sensitivityFactor;  ///< the sensitivity solves' (one per load step with parameters)
  bool linear = false;          ///< static.linear: one linear solve (residuals of that system)
};

/// Equilibrium of the scene's model under its loads (gravity, point forces) stepped in
/// `loadSteps` equal increments of the load factor, from the initial positions. Writes into
/// outDir (empty: writes nothing); on failure marks summary.json failed and rethrows. The
/// listener (when given) sees each load step's row, progress (load factor of 1) and the summary.
StaticResult runStaticScene(const Scene& scene, const std::string& outDir, int loadSteps,
                            RunListener* listener = nullptr);

}  // namespace flexsens
