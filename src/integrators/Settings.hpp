// Integrator settings as read from the scene (and overridden on the command line).
#pragma once

#include <string>

namespace flexsens {

struct IntegratorSettings {
  std::string type = "idas";   ///< idas | trapezoidal | midpoint | bdf1 | generalized_alpha | maggi_rk4
  double tEnd = 1.0;           ///< [s]
  double dt = 1e-3;            ///< fixed step [s]; for IDAS the largest step allowed (0 = free)
  /// generalized_alpha: spectral radius at infinite frequency, in [0, 1]. 1 = no numerical
  /// dissipation (the trapezoidal rule's spectrum), 0 = asymptotic annihilation like BDF-1.
  double rhoInf = 0.9;
  double rtol = 1e-8;          ///< IDAS relative tolerance
  double atol = 1e-10;         ///< IDAS absolute tolerance
  double newtonTol = 1e-10;    ///< fixed-step Newton: tolerance on the scaled update
  int maxNewtonIterations = 25;
  /// Fixed-step Newton: "full" factorizes the Newton matrix at every iteration; "modified"
  /// keeps the factorization across iterations and steps and refreshes it when the iteration
  /// contracts slowly. Full is the default: modified leaves an error of up to the tolerance
  /// where full Newton's quadratic convergence leaves round-off (see README); a scene with a
  /// meshed body and no `newton` key gets modified (scene/SceneReader: hasMeshedBody).
  std::string newton = "full";
  /// Trapezoidal rule and generalized-alpha: project each step's velocities and accelerations
  /// onto the velocity and acceleration constraints (integrators/MotionProjection.hpp). Off by
  /// default: the index-3 schemes as published; on, the trapezoidal rule runs models whose
  /// nonlinear constraints make its undamped constraint-direction parts grow.
  bool projections = false;
  double frameInterval = 0.01; ///< time between output frames [s]
  bool sensitivityErrorControl = true;  ///< IDAS: sensitivities in the error test
  /// IDAS: how the sensitivities are corrected. "staggered": after the state's corrector has
  /// converged, with its iteration matrix; "simultaneous": state and sensitivities in one
  /// Newton iteration and one convergence test (see README, IDAS).
  std::string sensitivityCorrector = "staggered";
  /// IDAS: the sensitivities' error weights. "state": IDAS' own estimate
  /// (IDASensEEtolerances): each sensitivity held to the state's weights rtol |y_i| + atol_i,
  /// an absolute accuracy of the state's size however large the sensitivity grows;
  /// "normwise": rtol |s_i| + max(atol_i, rtol |s_k|_inf), each sensitivity vector held to
  /// rtol of its own size, the norm over dq/dp and dv/dp together (see README, IDAS).
  std::string sensitivityTolerance = "state";
  /// Energy audit (app/EnergyAudit.hpp): a gain of the energy balance E - E0 - W above this
  /// fraction of the run's energy scale marks the run suspect; 0 switches that side off ...
  double energyTolerance = 0.05;
  /// ... and a loss the dampers, loads and drivers do not account for (numerical
  /// dissipation) above this fraction; 0 switches that side off.
  double energyLossTolerance = 0.1;
  /// dd: analytic partial derivatives (direct differentiation); dq: IDAS' internal
  /// difference quotients of the residual (IDAS only). External finite differences (nd)
  /// run whole perturbed simulations and live in the app layer.
  std::string sensitivityMethod = "dd";
};

inline bool isSensitivityCorrector(const std::string& c) { return c == "staggered" || c == "simultaneous"; }
inline bool isSensitivityTolerance(const std::string& c) { return c == "state" || c == "normwise"; }

inline bool isNewtonMode(const std::string& m) { return m == "full" || m == "modified"; }
/// The schemes whose steps MotionProjection can project (they carry v and a from step to step).
inline bool takesProjections(const std::string& type) { return type == "trapezoidal" || type == "generalized_alpha"; }

/// The integrator names scenes and the command line accept.
inline constexpr const char* kIntegratorTypes = "idas, trapezoidal, midpoint, bdf1, generalized_alpha or maggi_rk4";
inline bool isIntegratorType(const std::string& t) {
  return t == "idas" || t == "trapezoidal" || t == "midpoint" || t == "bdf1" || t == "generalized_alpha" || t == "maggi_rk4";
}

}  // namespace flexsens
