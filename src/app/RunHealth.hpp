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
/// maggi_rk4: its local position error estimates summed over the steps (integrators/Maggi.hpp,
/// MaggiReport::errorEstimate) above this fraction of L make the run `suspect`. The sum bounds
/// the global error in the asymptotic range (an overestimate: it adds up the embedded
/// third-order solution's local errors). Rigid pendulum (L = 1 m, released horizontal, 5 s):
/// see tests/test_maggi_pendulum.cpp for the sums and the true errors per dt.
inline constexpr double kErrorEstimateTolerance = 1e-3;
/// maggi_rk4: the energy audit's largest gain or loss above this fraction of the energy scale
/// makes the run `suspect` (the audit's own tolerances, 5% and 10%, are for dissipative
/// schemes). RK4 has no numerical dissipation and a fourth-order error: a correct run keeps
/// the balance orders below (rigid pendulum 8e-7 at dt 1e-2 s; the audit's trapezoidal sum of
/// the dampers' and loads' work adds O(dt^2): 4e-6 on its damped, pushed pendulum at 1e-3 s).
/// The local error estimate cannot see a wrong partition kept through a singular block (the
/// pendulum lost 4% of its energy at the bottom while each step's estimate stayed ~1e-5 m).
inline constexpr double kRk4EnergyTolerance = 1e-3;
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
  /// The integrator's own error estimate (maggi_rk4): the sum over the steps of the local
  /// position error estimates [m], the largest in one step and when [s], and the energy audit's
  /// worst balance as a fraction of its scale (< 0: not judged); judged in reason().
  void errorEstimate(const std::string& integrator, double sum, double maxStep, double tMaxStep,
                     double energyFraction);

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
  std::string estimator_;  ///< the integrator that estimated its error; empty: none did
  double errorSum_ = 0.0, errorMaxStep_ = 0.0, tErrorMaxStep_ = 0.0, energyFraction_ = -1.0;
};

}  // namespace flexsens
