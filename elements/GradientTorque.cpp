#include "elements/GradientTorque.hpp"

#include <stdexcept>

namespace flexsens {

GradientTorque::GradientTorque(std::string name, int node, int gradients, std::unique_ptr<Element> inner)
    : Element(std::move(name), {node}), gradients_(gradients), inner_(std::move(inner)) {
  if (gradients_ != 1 && gradients_ != 3) throw std::invalid_argument("gradient torque: 1 or 3 gradients per node");
  used_ = static_cast<int>(inner_->nodes().size()) - 1;
  if (used_ < 1 || used_ > gradients_) throw std::invalid_argument("gradient torque: inner torque on 2 or 3 nodes");
  first_ = gradients_ == 3 ? 1 : 0;  // ancf_beam: the section vectors r_y, r_z
}

LocalState GradientTorque::innerState(const LocalState& s) const {
  LocalState in = s;
  in.gradients = 0;
  in.x = VecX::Zero(s.dim * (1 + used_));
  in.v = VecX::Zero(in.x.size());
  const int at = s.dim * (1 + first_);  // x = [r, r_1, r_2, ...]
  in.x.tail(s.dim * used_) = s.x.segment(at, s.dim * used_);
  if (s.v.size() == s.x.size()) in.v.tail(s.dim * used_) = s.v.segment(at, s.dim * used_);
  return in;
}

VecX GradientTorque::outerVector(const LocalState& s, const VecX& inner) const {
  VecX Q = VecX::Zero(s.x.size());
  Q.segment(s.dim * (1 + first_), s.dim * used_) = inner.tail(s.dim * used_);
  return Q;
}

MatX GradientTorque::outerMatrix(const LocalState& s, const MatX& inner) const {
  MatX K = MatX::Zero(s.x.size(), s.x.size());
  const int n = s.dim * used_;
  const int at = s.dim * (1 + first_);
  K.block(at, at, n, n) = inner.bottomRightCorner(n, n);
  return K;
}

void GradientTorque::force(const LocalState& s, VecX& Q) const {
  VecX in;
  inner_->force(innerState(s), in);
  Q = outerVector(s, in);
}

void GradientTorque::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  MatX K, C;
  inner_->forceJacobian(innerState(s), K, C);
  dQdq = outerMatrix(s, K);
  dQdv.setZero(s.x.size(), s.x.size());
}

void GradientTorque::forceJacobianAD(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  MatX K, C;
  inner_->forceJacobianAD(innerState(s), K, C);
  dQdq = outerMatrix(s, K);
  dQdv.setZero(s.x.size(), s.x.size());
}

bool GradientTorque::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  VecX in;
  if (!inner_->parameterDerivative(innerState(s), k, in, dM)) return false;
  dQ = outerVector(s, in);
  dM.setZero(s.x.size(), s.x.size());  // massless
  return true;
}

bool GradientTorque::parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  VecX in;
  if (!inner_->parameterDerivativeAD(innerState(s), k, in, dM)) return false;
  dQ = outerVector(s, in);
  dM.resize(0, 0);  // massless
  return true;
}

}  // namespace flexsens
