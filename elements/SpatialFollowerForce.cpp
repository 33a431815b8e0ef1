#include "elements/SpatialFollowerForce.hpp"

#include <stdexcept>

#include "elements/BodyTriad.hpp"
#include "elements/KernelElementAD.hpp"

namespace flexsens {

using triad::V3;

SpatialFollowerForce::SpatialFollowerForce(std::string name, int p, int a, int b, int c, const Eigen::Matrix3d& X0,
                                           std::vector<Quantity> F0, std::unique_ptr<TimeFunction> f)
    : KernelElement(std::move(name), {p, a, b, c}), F0_(std::move(F0)), f_(std::move(f)) {
  const Eigen::Vector3d d1 = X0.col(1) - X0.col(0), d2 = X0.col(2) - X0.col(0);
  if (F0_.size() != 3 || !(d1.cross(d2).norm() > 1e-6 * d1.norm() * d2.norm()))
    throw std::invalid_argument("follower force '" + this->name() + "': 3 components, body nodes not collinear");
  Einv0_ = triad::inverseTriad(d1, d2);
}

void SpatialFollowerForce::checkDim(const LocalState& s) const {
  if (s.dim != 3) throw std::invalid_argument("follower force '" + name() + "' (3 components) needs a spatial model");
}

std::vector<const Quantity*> SpatialFollowerForce::kernelProperties() const { return {&F0_[0], &F0_[1], &F0_[2]}; }

VecX SpatialFollowerForce::componentValues(const LocalState& s) const {
  return Eigen::Vector3d(s.value(F0_[0]), s.value(F0_[1]), s.value(F0_[2]));
}

template <class T>
VecT<T> SpatialFollowerForce::load(const VecT<T>& x, const VecT<T>& c, double fac) const {
  // Local nodes: 0 = P, 1 = A, 2 = B, 3 = C.
  const V3<T> d1 = triad::at(x, 2) - triad::at(x, 1), d2 = triad::at(x, 3) - triad::at(x, 1);
  VecT<T> Q(12);
  const V3<T> F = triad::follower(d1, d2, Einv0_, c, fac);
  Q.template segment<3>(0) = F;
  // No force on A, B, C: zeros as scalar-double products so that AD outputs stay well formed.
  for (int i = 3; i < 12; ++i) Q[i] = c[0] * 0.0;
  return Q;
}

template <class T>
VecT<T> SpatialFollowerForce::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>&,
                                     const VecT<T>& props) const {
  checkDim(s);
  return load<T>(x, props, factor(s));
}

void SpatialFollowerForce::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  checkDim(s);
  const Eigen::Vector3d d1 = s.x.segment<3>(6) - s.x.segment<3>(3), d2 = s.x.segment<3>(9) - s.x.segment<3>(3);
  const Eigen::Vector3d a = factor(s) * Einv0_ * componentValues(s);
  Eigen::Matrix3d D1, D2;
  triad::followerJacobian(d1, d2, a, D1, D2);
  dQdq.setZero(12, 12);
  dQdq.block<3, 3>(0, 3) = -(D1 + D2);  // d1 = x_B - x_A, d2 = x_C - x_A
  dQdq.block<3, 3>(0, 6) = D1;
  dQdq.block<3, 3>(0, 9) = D2;
  dQdv.setZero(12, 12);
}

bool SpatialFollowerForce::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  checkDim(s);
  TimeValue d;
  const bool fn = f_ && f_->parameterDerivative(s.t, *s.p, k, d);
  Eigen::Vector3d unit;
  for (int i = 0; i < 3; ++i) unit[i] = F0_[i].boundTo(k) ? 1.0 : 0.0;
  const bool comp = !unit.isZero();
  if (!fn && !comp) return false;
  dQ = VecX::Zero(12);
  if (comp) dQ += load<double>(s.x, unit, factor(s));
  if (fn) dQ += load<double>(s.x, componentValues(s), d.f);
  dM.setZero(12, 12);  // massless
  return true;
}

bool SpatialFollowerForce::parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  checkDim(s);
  // AD through the components; the time function's constants (Q of df/dp_k) analytic.
  const bool comp = KernelElement::parameterDerivativeAD(s, k, dQ, dM);
  TimeValue d;
  if (!f_ || !f_->parameterDerivative(s.t, *s.p, k, d)) return comp;
  if (!comp) dQ.setZero(12);
  dQ += load<double>(s.x, componentValues(s), d.f);
  dM.resize(0, 0);  // massless
  return true;
}

std::vector<std::pair<std::string, Quantity*>> SpatialFollowerForce::properties() {
  std::vector<std::pair<std::string, Quantity*>> r{{"x", &F0_[0]}, {"y", &F0_[1]}, {"z", &F0_[2]}};
  if (f_)
    for (auto& pr : f_->properties()) r.push_back(pr);
  return r;
}

template class KernelElement<SpatialFollowerForce>;

}  // namespace flexsens
