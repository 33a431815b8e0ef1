// Run health beyond energy (the energy audit is app/EnergyAudit): at every frame,
//  - the constraint rows left out as redundant (core/RedundantRows.hpp): the elimination is
//    exact only while the redundancy persists, so a left-out row beyond kLeftOutTolerance
//    makes the run `suspect`;
//  - the sensitivities: max_i |dq_i/dp_k| |p_k| / L (L the size of the model, the diagonal of
//    its initial bounding box) beyond kSensitivityBlowUp makes the run `suspect`: a 0.1%
//    change of p_k would move the mechanism by its own size, so the gradient is no guide (the
//    N-four-bar on maggi_rk4 reaches 1e6 after taking the wrong branch at a singular passage,
//    generalized-alpha's correct run stays below 1);
//  - the conditioning of Phi_q, sigma_min / sigma_max (from the eigenvalues of Phi_q Phi_q^T),
//    reported with its time: a near-singular passage, where a scheme may change branch;
//  - with massless parts, the stability of their equilibrium (integrators/InitialState.hpp,
//    masslessStability): a reduced stiffness eigenvalue below -kMasslessUnstable of the
//    largest makes the run `suspect` (a massless part buckled or snapped through, where the
//    massless idealization has no continuing solution and the result depends on the scheme).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Eigenvalues>

#include "core/Assembler.hpp"
#include "core/SparseAccumulator.hpp"
#include "integrators/State.hpp"

namespace flexsens {

inline constexpr double kLeftOutTolerance = 1e-6;    ///< |Phi| of a left-out row [m or its unit]
inline constexpr double kSensitivityBlowUp = 1e3;    ///< relative sensitivity |dq/dp| |p| / L [-]
inline constexpr double kConditioningWork = 1e8;     ///< m^2 n per frame above which it is skipped
/// sigma_min / sigma_max of Phi_q [-] below which a failure is said to follow a near rank loss.
/// The N-four-bar's collinear passage reaches 0.0093 at its frames; the massless satellite's
/// panels at the end of their swing 0.044, a well-posed configuration IDAS passes at rtol 1e-8
/// and 1e-10 (0.05 blamed it for the trapezoidal rule's failures, which have another cause).
inline constexpr double kNearSingular = 0.02;
inline constexpr double kMasslessUnstable = 1e-9;    ///< -lambda_min / lambda_max of the massless stiffness [-]
inline constexpr int kMasslessCheckMax = 3000;       ///< n above which it is skipped (dense n x n K per frame)

class RunHealth : public ForwardingObserver {
 public:
  RunHealth(const Assembler& as, const VecX& p, Observer& next);
  void frame(const StateWithSens& s) override;
  /// Plain words when a left-out row drifted or a sensitivity blew up; empty otherwise.
  std::string reason() const;
  /// For a failed run's message: when Phi_q came near rank loss at a frame (sigma ratio below
  /// kNearSingular), "; " and where, in plain words; empty otherwise.
  std::string failureHint() const;
  /// The massless parts' stability in plain words (for reason() and failureHint()).
  std::string masslessWords() const;
  /// summary.json's "health" object.
  std::string json() const;

 private:
  const Assembler& as_;
  const VecX& p_;
  double size_ = 1.0;  ///< L [m]
  double leftOut_ = 0.0, tLeftOut_ = 0.0;
  double sens_ = 0.0, tSens_ = 0.0, sensFirst_ = -1.0;  ///< largest, its time, first time past the limit
  int sensParam_ = -1;
  double cond_ = 1.0, tCond_ = 0.0;
  bool condChecked_ = false;
  SparseAccumulator phiQ_;  ///< Phi_q's pattern, and the Gram matrix and eigen-solver's storage
  MatX gram_;
  Eigen::SelfAdjointEigenSolver<MatX> eig_;
  std::vector<int> massless_;  ///< massless coordinates (checked when any and n <= kMasslessCheckMax)
  double masslessRatio_ = 1.0, tMassless_ = 0.0;  ///< smallest lambda_min / lambda_max, its time
  double masslessRatio0_ = 0.0;                   ///< the same at the first frame
  std::string masslessCoordinate_;
};

}  // namespace flexsens
