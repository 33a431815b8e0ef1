#include "app/RunHealth.hpp"

#include <cmath>
#include <sstream>

#include <Eigen/Eigenvalues>

#include "core/RedundantRows.hpp"
#include "integrators/InitialState.hpp"
#include "output/ResultWriter.hpp"

namespace flexsens {

RunHealth::RunHealth(const Assembler& as, const VecX& p, Observer& next) : ForwardingObserver(next), as_(as), p_(p) {
  const Model& m = as.model();
  if (!m.nodes.empty()) {
    VecX lo = m.nodes[0].position, hi = lo;
    for (const auto& nd : m.nodes) lo = lo.cwiseMin(nd.position), hi = hi.cwiseMax(nd.position);
    size_ = std::max((hi - lo).norm(), 1e-3);
  }
  condChecked_ = m.m > 0 && static_cast<double>(m.m) * m.m * m.n <= kConditioningWork;
  if (m.n <= kMasslessCheckMax) massless_ = masslessCoordinates(as, p);
}

void RunHealth::frame(const StateWithSens& s) {
  const Model& m = as_.model();
  if (!m.redundantRows.empty()) {
    const double v = leftOutViolation(m, as_, s.x.q, p_);
    if (v > leftOut_) leftOut_ = v, tLeftOut_ = s.x.t;
  }
  for (size_t k = 0; k < s.dp.size() && static_cast<int>(k) < p_.size(); ++k) {
    if (p_[k] == 0.0 || s.dp[k].q.size() == 0) continue;  // no scale to judge a zero nominal by
    const double r = s.dp[k].q.lpNorm<Eigen::Infinity>() * std::abs(p_[k]) / size_;
    if (!(r <= sens_)) sens_ = r, tSens_ = s.x.t, sensParam_ = static_cast<int>(k);
    if (!(r <= kSensitivityBlowUp) && sensFirst_ < 0) sensFirst_ = s.x.t;
  }
  if (condChecked_) {
    // The lower triangle of Phi_q Phi_q^T, column by column of Phi_q (the outer products of
    // each column's entries), in storage kept across frames: the dense product was ~1 ms a
    // frame on the satellite, Eigen's sparse one with its pattern built anew 5% of the run.
    const SpMat& J = as_.phiQSparse(s.x.q, p_, phiQ_);
    gram_.setZero(J.rows(), J.rows());
    for (Eigen::Index j = 0; j < J.outerSize(); ++j) {
      const Eigen::Index b = J.outerIndexPtr()[j], e = J.outerIndexPtr()[j + 1];
      const auto* row = J.innerIndexPtr();
      const double* val = J.valuePtr();
      for (Eigen::Index a = b; a < e; ++a)
        for (Eigen::Index c = a; c < e; ++c) gram_(row[c], row[a]) += val[a] * val[c];  // rows ascend: lower
    }
    eig_.compute(gram_, Eigen::EigenvaluesOnly);  // reads the lower triangle only
    const VecX& ev = eig_.eigenvalues();
    const double c = ev[ev.size() - 1] > 0 ? std::sqrt(std::max(ev[0], 0.0) / ev[ev.size() - 1]) : 0.0;
    if (c < cond_) cond_ = c, tCond_ = s.x.t;
  }
  if (!massless_.empty()) {
    const MasslessStability ms = masslessStability(as_, s.x, p_, massless_);
    if (ms.maxEigenvalue > 0.0 && masslessRatio0_ == 0.0) masslessRatio0_ = ms.minEigenvalue / ms.maxEigenvalue;
    if (ms.maxEigenvalue > 0.0 && ms.minEigenvalue / ms.maxEigenvalue < masslessRatio_) {
      masslessRatio_ = ms.minEigenvalue / ms.maxEigenvalue;
      tMassless_ = s.x.t;
      masslessCoordinate_ = ms.coordinate;
    }
  }
  next_.frame(s);
}

std::string RunHealth::reason() const {
  std::ostringstream os;
  if (leftOut_ > kLeftOutTolerance)
    os << "a constraint row left out as redundant at t = 0 reached |Phi| = " << leftOut_ << " at t = " << tLeftOut_
       << " s (tolerance " << kLeftOutTolerance << "): the redundancy did not persist along the motion, so the "
       << "model integrated is not the one described; remove the redundant joint from the scene or replace it "
       << "by one that constrains less";
  if (sensFirst_ >= 0) {
    if (os.tellp() > 0) os << "; ";
    os << "sensitivity blow-up: |dq/dp| |p| / L of parameter '" << as_.model().parameters[sensParam_].name
       << "' passed " << kSensitivityBlowUp << " at t = " << sensFirst_ << " s and reached " << sens_ << " at t = "
       << tSens_ << " s (L = " << size_ << " m); the motion is that sensitive only past a bifurcation "
       << "(a branch switch at a singular configuration, smallest sigma(Phi_q) ratio " << cond_ << " at t = " << tCond_
       << " s) or in chaotic motion: try generalized_alpha or a smaller dt, and compare";
  }
  if (masslessRatio_ < -kMasslessUnstable) {
    if (os.tellp() > 0) os << "; ";
    os << masslessWords();
  }
  if (!estimator_.empty() && !(errorSum_ <= kErrorEstimateTolerance * size_)) {
    if (os.tellp() > 0) os << "; ";
    os << estimator_ << "'s error estimate: the local position errors summed over the steps reached " << errorSum_
       << " m, above " << kErrorEstimateTolerance << " of the model's size L = " << size_
       << " m (largest in one step " << errorMaxStep_ << " m, at t = " << tErrorMaxStep_
       << " s); the fixed step is too large for this motion: use a smaller --dt (the estimate falls like dt^3) "
       << "or --integrator idas";
  }
  if (!estimator_.empty() && energyFraction_ > kRk4EnergyTolerance) {
    if (os.tellp() > 0) os << "; ";
    os << estimator_ << " changed the energy balance E - E0 - W by " << energyFraction_
       << " of the run's energy scale (summary.json energy), above " << kRk4EnergyTolerance
       << ": a fourth-order scheme without numerical dissipation keeps it orders below, so the motion took a "
       << "wrong turn (e.g. near a singular configuration); use a smaller --dt or --integrator idas, and compare";
  }
  return os.str();
}

void RunHealth::errorEstimate(const std::string& integrator, double sum, double maxStep, double tMaxStep,
                              double energyFraction) {
  energyFraction_ = energyFraction;
  estimator_ = integrator;
  errorSum_ = sum;
  errorMaxStep_ = maxStep;
  tErrorMaxStep_ = tMaxStep;
}

std::string RunHealth::masslessWords() const {
  std::ostringstream os;
  os << "a massless part lost its stiffness: the smallest eigenvalue of the massless coordinates' "
     << "reduced tangent stiffness reached " << masslessRatio_ << " of the largest at the frame t = " << tMassless_
     << " s (" << masslessRatio0_ << " at the start, softest in " << masslessCoordinate_
     << "), so its quasi-static equilibrium "
     << (masslessRatio_ < 0 ? "was unstable (buckling or snap-through)" : "came near a fold")
     << ", where a part without mass has no continuing motion and the result depends on the scheme; "
     << "give that part its mass (remove inertia: none)";
  return os.str();
}

std::string RunHealth::failureHint() const {
  std::ostringstream os;
  if (!massless_.empty() && masslessRatio_ < 1e-2 * masslessRatio0_) os << "; " << masslessWords();
  if (!condChecked_ || !(cond_ < kNearSingular)) return os.str();
  os << "; the constraint Jacobian was near rank loss before (smallest sigma_min/sigma_max of Phi_q "
     << cond_ << " at the frame t = " << tCond_ << " s): a singular configuration (e.g. bars passing a collinear "
     << "position), where the motion may switch branch; generalized_alpha (rho_inf < 1) passes such "
     << "configurations, or give the scene a driver or geometry that avoids them";
  return os.str();
}

std::string RunHealth::json() const {
  std::ostringstream os;
  os << "{\"redundant_rows_left_out\": [";
  const auto& rows = as_.model().redundantRows;
  for (size_t i = 0; i < rows.size(); ++i) os << (i ? ", " : "") << jsonString(rows[i]);
  os << "], \"max_left_out_violation\": " << jsonNumber(leftOut_) << ", \"left_out_at_t\": " << jsonNumber(tLeftOut_)
     << ", \"max_relative_sensitivity\": " << jsonNumber(sens_) << ", \"sensitivity_at_t\": " << jsonNumber(tSens_)
     << ", \"model_size_m\": " << jsonNumber(size_);
  if (condChecked_)
    os << ", \"min_constraint_conditioning\": " << jsonNumber(cond_) << ", \"conditioning_at_t\": " << jsonNumber(tCond_);
  if (!massless_.empty())
    os << ", \"min_massless_stiffness_ratio\": " << jsonNumber(masslessRatio_) << ", \"massless_stiffness_at_t\": "
       << jsonNumber(tMassless_) << ", \"massless_softest_coordinate\": " << jsonString(masslessCoordinate_)
       << ", \"initial_massless_stiffness_ratio\": " << jsonNumber(masslessRatio0_);
  if (!estimator_.empty())
    os << ", \"error_estimate_m\": " << jsonNumber(errorSum_) << ", \"error_estimate_tolerance_m\": "
       << jsonNumber(kErrorEstimateTolerance * size_) << ", \"max_step_error_estimate_m\": " << jsonNumber(errorMaxStep_)
       << ", \"max_step_error_estimate_at_t\": " << jsonNumber(tErrorMaxStep_)
       << ", \"energy_balance_fraction\": " << jsonNumber(energyFraction_)
       << ", \"energy_balance_tolerance\": " << jsonNumber(kRk4EnergyTolerance);
  os << "}";
  return os.str();
}

}  // namespace flexsens
