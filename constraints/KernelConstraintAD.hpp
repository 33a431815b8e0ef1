// Member definitions of KernelConstraint (constraints/KernelConstraint.hpp). Include from a
// constraint's .cpp only (it pulls in Eigen's AutoDiff) and instantiate there, after the kernel:
//   template class KernelConstraint<MyConstraint>;
#pragma once

#include "constraints/KernelConstraint.hpp"
#include "elements/AutoDiff.hpp"

namespace flexsens {

template <class Derived>
VecX KernelConstraint<Derived>::kernelPropertyValues(const LocalState& s) const {
  const std::vector<const Quantity*> props = self().kernelProperties();
  return props.empty() ? VecX() : ad::propertyValues(props, *s.p);
}

template <class Derived>
void KernelConstraint<Derived>::phi(const LocalState& s, VecX& out) const {
  out = kernelPhi(s);
}

template <class Derived>
VecX KernelConstraint<Derived>::kernelPhi(const LocalState& s) const {
  return self().template phiT<double>(s, s.x, kernelPropertyValues(s));
}

template <class Derived>
void KernelConstraint<Derived>::jacobianAD(const LocalState& s, MatX& J) const {
  J = ad::constraintJacobian(phiKernel(s), s, kernelPropertyValues(s));
}

template <class Derived>
void KernelConstraint<Derived>::hessianAD(const LocalState& s, int r, MatX& H) const {
  H = ad::constraintHessian(phiKernel(s), s, kernelPropertyValues(s), r);
}

template <class Derived>
bool KernelConstraint<Derived>::parameterDerivativeAD(const LocalState& s, int k, VecX& dphi,
                                                      MatX& dJ) const {
  const VecX dir = ad::propertyDirection(self().kernelProperties(), k);
  if (dir.isZero()) return false;  // also when there are no properties (dir is empty)
  ad::constraintParameterDerivative(phiKernel(s), s, kernelPropertyValues(s), dir, dphi, dJ);
  return true;
}

}  // namespace flexsens
