// CRTP base of the constraints whose Phi is written once as a value template on the scalar
// type. It exists so that the glue around that kernel is written once instead of in every
// constraint: evaluating it with double for phi(), and with the AD drivers
// (elements/AutoDiff.hpp) for jacobianAD(), hessianAD() and parameterDerivativeAD().
// The analytic derivatives (jacobian, hessian, parameterDerivative) stay in Derived.
//
// Derived (which befriends KernelConstraint<Derived>) provides
//   std::vector<const Quantity*> kernelProperties() const;  // the props the kernel reads, in order
//   template <class T> VecT<T> phiT(const LocalState& s, const VecT<T>& x, const VecT<T>& props) const;
// A constraint without properties returns an empty list: its kernel gets an empty props
// vector (s.p is not read) and parameterDerivativeAD is false for every parameter.
//
// The members are defined in constraints/KernelConstraintAD.hpp (it pulls in Eigen's AutoDiff):
// the constraint's .cpp includes it and ends with `template class KernelConstraint<Derived>;`.
#pragma once

#include "core/Element.hpp"

namespace flexsens {

template <class Derived>
class KernelConstraint : public Constraint {
 public:
  using Constraint::Constraint;
  void phi(const LocalState& s, VecX& out) const override;
  /// Phi by the value template (phi() unless Derived writes its own double path for speed;
  /// the tests compare the two).
  VecX kernelPhi(const LocalState& s) const;
  void jacobianAD(const LocalState& s, MatX& J) const override;
  void hessianAD(const LocalState& s, int r, MatX& H) const override;
  bool parameterDerivativeAD(const LocalState& s, int k, VecX& dphi, MatX& dJ) const override;

 private:
  const Derived& self() const { return static_cast<const Derived&>(*this); }
  /// Values of kernelProperties() at s.p; empty (s.p unread) when there are none.
  VecX kernelPropertyValues(const LocalState& s) const;
  /// phiT at state s as a generic callable (x, props) for the AD drivers.
  auto phiKernel(const LocalState& s) const {
    return [this, &s](const auto& x, const auto& pr) { return self().phiT(s, x, pr); };
  }
};

}  // namespace flexsens
