#include "elements/PlanarTorque.hpp"

#include <stdexcept>

namespace flexsens {

VecX PlanarTorque::unitForce(const VecX& x) {
  const Eigen::Vector2d d = x.segment<2>(2) - x.segment<2>(0);
  const Eigen::Vector2d Rd(-d[1], d[0]);
  VecX Q(4);
  Q.segment<2>(2) = Rd / d.squaredNorm();
  Q.segment<2>(0) = -Q.segment<2>(2);
  return Q;
}

void PlanarTorque::force(const LocalState& s, VecX& Q) const {
  if (s.dim != 2) throw std::invalid_argument("point torque '" + name() + "' needs a planar model");
  Q = s.value(tau_) * factor(s) * unitForce(s.x);
}

void PlanarTorque::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  const Eigen::Vector2d d = s.x.segment<2>(2) - s.x.segment<2>(0);
  const double dd = d.squaredNorm();
  Eigen::Matrix2d R;
  R << 0, -1, 1, 0;
  const Eigen::Matrix2d K = s.value(tau_) * factor(s) * (R - 2.0 * R * d * d.transpose() / dd) / dd;
  dQdq.resize(4, 4);
  dQdq << K, -K, -K, K;  // Q_A = -Q_B(d), d = x_B - x_A
  dQdv.setZero(4, 4);
}

bool PlanarTorque::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  TimeValue d;
  const bool fn = f_ && f_->parameterDerivative(s.t, *s.p, k, d);
  if (!tau_.boundTo(k) && !fn) return false;
  const double c = (tau_.boundTo(k) ? factor(s) : 0.0) + (fn ? s.value(tau_) * d.f : 0.0);
  dQ = c * unitForce(s.x);
  dM.setZero(4, 4);  // massless
  return true;
}

std::vector<std::pair<std::string, Quantity*>> PlanarTorque::properties() {
  std::vector<std::pair<std::string, Quantity*>> r{{"torque", &tau_}};
  if (f_)
    for (auto& pr : f_->properties()) r.push_back(pr);
  return r;
}

}  // namespace flexsens
