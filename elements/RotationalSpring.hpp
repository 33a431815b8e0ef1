// Rotational spring-damper of a revolute joint in natural coordinates: the joint angle theta
// (elements/JointAngle.hpp: from-vector to to-vector about the joint axis) carries the torque
//   tau = -k (theta - theta0) - c theta'   [N m],   theta' = grad(theta) . v,
// whose generalized force is Q = tau grad(theta) (virtual power tau dtheta). Massless.
// The angle is measured in (-pi, pi] around theta0: a joint turning more than ~0.95 pi from
// its rest angle stops the run with a diagnostic instead of a torque jump.
// Units: k [N m/rad], c [N m s/rad], angles [rad].
#pragma once

#include "elements/KernelElement.hpp"
#include "elements/JointAngle.hpp"

namespace flexsens {

class RotationalSpringDamper : public KernelElement<RotationalSpringDamper> {
 public:
  RotationalSpringDamper(std::string name, const AngleNodes& nodes, Quantity k, Quantity c, double restAngle)
      : KernelElement(std::move(name), nodes.list()), k_(k), c_(c), theta0_(restAngle) {}
  std::string kind() const override { return "rotational_spring_damper"; }
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override {
    return {{"stiffness", &k_}, {"damping", &c_}};
  }
  double restAngle() const { return theta0_; }

 private:
  friend class KernelElement<RotationalSpringDamper>;
  /// theta - theta0 wrapped to (-pi, pi]; throws NumericalError past ~0.95 pi.
  double deviation(double theta) const;
  std::vector<const Quantity*> kernelProperties() const { return {&k_, &c_}; }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  Quantity k_, c_;
  double theta0_;
};

}  // namespace flexsens
