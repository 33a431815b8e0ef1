// Member definitions of KernelElement (elements/KernelElement.hpp). Include from an element's
// .cpp only (it pulls in Eigen's AutoDiff) and instantiate there, after the kernels:
//   template class KernelElement<MyElement>;
#pragma once

#include "elements/AutoDiff.hpp"
#include "elements/KernelElement.hpp"

namespace flexsens {

template <class Derived>
bool KernelElement<Derived>::mass(const LocalState& s, MatX& M) const {
  if constexpr (Derived::hasMassKernel) {
    M = self().template massT<double>(s, ad::propertyValues(self().kernelProperties(), *s.p));
    return true;
  } else {
    return Element::mass(s, M);
  }
}

template <class Derived>
void KernelElement<Derived>::force(const LocalState& s, VecX& Q) const {
  Q = kernelForce(s);
}

template <class Derived>
VecX KernelElement<Derived>::kernelForce(const LocalState& s) const {
  return self().template forceT<double>(s, s.x, s.v, ad::propertyValues(self().kernelProperties(), *s.p));
}

template <class Derived>
void KernelElement<Derived>::forceJacobianAD(const LocalState& s, MatX& dQdq, MatX& dQdv) const {
  ad::forceJacobian(forceKernel(s), s, ad::propertyValues(self().kernelProperties(), *s.p), dQdq, dQdv);
}

template <class Derived>
bool KernelElement<Derived>::parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const {
  const VecX dir = ad::propertyDirection(self().kernelProperties(), k);
  if (dir.isZero()) return false;
  const VecX props = ad::propertyValues(self().kernelProperties(), *s.p);
  dQ = ad::forceParameterDerivative(forceKernel(s), s, props, dir);
  if constexpr (Derived::hasMassKernel)
    dM = ad::massParameterDerivative([&](const auto& pr) { return self().massT(s, pr); }, props, dir);
  else
    dM.resize(0, 0);  // massless
  return true;
}

}  // namespace flexsens
