// CRTP base of the elements whose force (and constant mass) are written once as value
// templates on the scalar type. It exists so that the glue around those kernels is written
// once instead of in every element: evaluating them with double for force() and mass(), and
// with the AD drivers (elements/AutoDiff.hpp) for forceJacobianAD() and parameterDerivativeAD().
//
// Derived (which befriends KernelElement<Derived>) provides
//   std::vector<const Quantity*> kernelProperties() const;  // the props the kernels read, in order
//   template <class T> VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v,
//                                     const VecT<T>& props) const;
// and, if it has a mass, `static constexpr bool hasMassKernel = true;` and
//   template <class T> MatT<T> massT(const LocalState& s, const VecT<T>& props) const;
// Without one, mass() is false and parameterDerivativeAD gives an empty 0x0 dM (massless).
//
// The members are defined in elements/KernelElementAD.hpp (it pulls in Eigen's AutoDiff): the
// element's .cpp includes it and ends with `template class KernelElement<Derived>;`.
#pragma once

#include "core/Element.hpp"

namespace flexsens {

template <class Derived>
class KernelElement : public Element {
 public:
  using Element::Element;
  bool mass(const LocalState& s, MatX& M) const override;
  void force(const LocalState& s, VecX& Q) const override;
  /// Q by the value template (force() unless Derived writes its own double path for speed;
  /// the tests compare the two).
  VecX kernelForce(const LocalState& s) const;
  void forceJacobianAD(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;

 protected:
  static constexpr bool hasMassKernel = false;  ///< hidden by Derived's when it has a massT

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
  /// forceT at state s as a generic callable (x, v, props) for the AD drivers.
  auto forceKernel(const LocalState& s) const {
    return [this, &s](const auto& x, const auto& v, const auto& pr) { return self().forceT(s, x, v, pr); };
  }
};

}  // namespace flexsens
