#include "elements/RotationalSpring.hpp"

#include <sstream>

#include "elements/KernelElementAD.hpp"

namespace flexsens {

double RotationalSpringDamper::deviation(double theta) const {
  const double d = std::remainder(theta - theta0_, 2.0 * M_PI);
  if (std::abs(d) > 0.95 * M_PI) {
    std::ostringstream os;
    os << "rotational spring-damper '" << name() << "': the joint turned " << d
       << " rad from its rest angle " << theta0_
       << " rad; angles are measured within half a revolution of the rest angle, so the torque "
          "would jump: try a stiffer spring, more damping or a shorter run";
    throw NumericalError(os.str());
  }
  return d;
}

// Value template: props = (k, c).
template <class T>
VecT<T> RotationalSpringDamper::forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v,
                                       const VecT<T>& props) const {
  if (s.dim != 3) throw std::invalid_argument("rotational spring-damper " + name() + ": spatial scenes only");
  VecT<T> g;
  const T theta = jointAngleT<T>(x, &g);
  const T dev = ad::wrapAngle(T(theta - theta0_));
  deviation(ad::valueOf(theta));
  const T rate = g.dot(v);                               // theta' [rad/s]
  const T tau = -props[0] * dev - props[1] * rate;       // [N m]
  return VecT<T>(tau * g);
}

void RotationalSpringDamper::forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  VecX g;
  const double theta = jointAngleT<double>(s.x, &g);
  const MatX H = jointAngleHessian(s.x);
  const double k = s.value(k_), c = s.value(c_);
  const double tau = -k * deviation(theta) - c * g.dot(s.v);
  dQdq = -k * g * g.transpose() + tau * H - c * g * (H * s.v).transpose();
  dQdv = -c * g * g.transpose();
}

bool RotationalSpringDamper::parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  if (!k_.boundTo(k) && !c_.boundTo(k)) return false;
  VecX g;
  const double theta = jointAngleT<double>(s.x, &g);
  double dtau = 0.0;
  if (k_.boundTo(k)) dtau -= deviation(theta);
  if (c_.boundTo(k)) dtau -= g.dot(s.v);
  dQ = dtau * g;
  dM.resize(0, 0);
  return true;
}

double RotationalSpringDamper::potential(const LocalState& s) const {
  const double d = deviation(jointAngleT<double>(s.x, nullptr));
  return 0.5 * s.value(k_) * d * d;  // [J]
}

template class KernelElement<RotationalSpringDamper>;

}  // namespace flexsens
