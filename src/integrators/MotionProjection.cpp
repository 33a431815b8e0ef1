#include "integrators/MotionProjection.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace flexsens {

MotionProjection::MotionProjection(const Assembler& as, const VecX& p, const std::vector<int>& massless)
    : as_(as), p_(p) {
  weight_ = as.mass(p);
  if (!massless.empty()) {
    double largest = 0.0;
    for (int c = 0; c < weight_.outerSize(); ++c)
      for (SpMat::InnerIterator it(weight_, c); it; ++it) largest = std::max(largest, std::abs(it.value()));
    SpMat e(weight_.rows(), weight_.cols());
    std::vector<Eigen::Triplet<double, SpMat::StorageIndex>> t;
    for (int i : massless) t.emplace_back(i, i, 1e-8 * largest);  // [kg]
    e.setFromTriplets(t.begin(), t.end());
    weight_ += e;
  }
}

void MotionProjection::project(State& x, long step) {
  const int n = as_.n(), m = as_.m();
  if (m == 0) return;
  acc_.begin(n + m, n + m);
  for (int c = 0; c < weight_.outerSize(); ++c)
    for (SpMat::InnerIterator it(weight_, c); it; ++it) acc_.add(it.row(), it.col(), it.value());
  as_.addPhiQ(acc_, x.q, p_, 1.0, 0, n, true);
  as_.addPhiQ(acc_, x.q, p_, 1.0, n, 0, false);
  lu_.factor(acc_.finish(), [&] {
    std::ostringstream what;
    what << "projection matrix [M Phi_q^T; Phi_q 0] at t = " << x.t << " s (step " << step
         << "; redundant constraints, or a massed coordinate the constraints fix without mass)";
    return what.str();
  });
  VecX b = VecX::Zero(n + m);
  b.tail(m) = -(as_.phiQTimes(x.q, p_, x.v) + as_.phiT(x.q, p_));
  VecX s = lu_.solve(b);
  dv_ = s.head(n);
  mu_ = s.tail(m);
  x.v += dv_;
  b.tail(m) = -(as_.phiQTimes(x.q, p_, x.a) + as_.hessianQuadratic(x.q, p_, x.v) +
                as_.accelerationTimeTerms(x.q, x.v, p_));
  s = lu_.solve(b);
  da_ = s.head(n);
  kappa_ = s.tail(m);
  x.a += da_;
  if (!x.v.allFinite() || !x.a.allFinite()) {
    std::ostringstream os;
    os << "projection at t = " << x.t << " s (step " << step << "): the projected velocities or accelerations "
       << "are not finite; try a smaller --dt";
    throw NumericalError(os.str());
  }
}

void MotionProjection::sensitivity(const State& x, int k, State& d) const {
  const int n = as_.n(), m = as_.m();
  if (m == 0) return;
  // Velocity: W (v - v~) + Phi_q^T mu = 0, Phi_q v + Phi_t = 0, differentiated at fixed W
  // but for M_p (eps is a constant).
  VecX b(n + m);
  b.head(n) = -(as_.massParamDerivativeTimes(p_, k, dv_) + as_.hessianTimes(x.q, p_, mu_, d.q) +
                as_.phiQParamDerivativeTransposeTimes(x.q, p_, k, mu_));
  b.tail(m) = -(as_.hessianRowsTimes(x.q, p_, x.v, d.q) + as_.phiQParamDerivativeTimes(x.q, p_, k, x.v) +
                as_.phiQTTimes(x.q, p_, d.q) + as_.phiTParamDerivative(x.q, p_, k)) -
              as_.phiQTimes(x.q, p_, d.v);
  VecX s = lu_.solve(b);
  d.v += s.head(n);
  // Acceleration: Phi_q a + (v^T H_i v)_i + g(q, v) = 0 differentiated likewise.
  b.head(n) = -(as_.massParamDerivativeTimes(p_, k, da_) + as_.hessianTimes(x.q, p_, kappa_, d.q) +
                as_.phiQParamDerivativeTransposeTimes(x.q, p_, k, kappa_));
  b.tail(m) = -(as_.hessianRowsTimes(x.q, p_, x.a, d.q) + as_.phiQParamDerivativeTimes(x.q, p_, k, x.a) +
                2.0 * as_.hessianRowsTimes(x.q, p_, x.v, d.v) + as_.accelerationTimeTermsQTimes(x.q, x.v, p_, d.q) +
                2.0 * as_.phiQTTimes(x.q, p_, d.v) + as_.accelerationTimeTermsParamDerivative(x.q, x.v, p_, k)) -
              as_.phiQTimes(x.q, p_, d.a);
  s = lu_.solve(b);
  d.a += s.head(n);
}

}  // namespace flexsens
