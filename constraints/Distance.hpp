// Constraints between node coordinates. All are at most quadratic in q (constant Hessians).
#pragma once

#include "constraints/KernelConstraint.hpp"

namespace flexsens {

/// Constant distance: Phi = |x_b - x_a|^2 - L^2 (quadratic form, as in the paper).
class DistanceConstraint : public KernelConstraint<DistanceConstraint> {
 public:
  DistanceConstraint(std::string name, int a, int b, Quantity length)
      : KernelConstraint(std::move(name), {a, b}), length_(length) {}
  std::string kind() const override { return "distance"; }
  int rows() const override { return 1; }
  /// phiT for double, into out's storage (no property or result vector per call).
  void phi(const LocalState& s, VecX& out) const override;
  void jacobian(const LocalState& s, MatX& J) const override;
  void hessian(const LocalState& s, int r, MatX& H) const override;
  bool constantHessian() const override { return true; }
  bool parameterDerivative(const LocalState& s, int k, VecX& dphi, MatX& dJ) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override {
    return {{"length", &length_}};
  }

 private:
  friend class KernelConstraint<DistanceConstraint>;
  /// Properties the kernel reads, in the order of its props vector: (L).
  std::vector<const Quantity*> kernelProperties() const { return {&length_}; }
  template <class T>
  VecT<T> phiT(const LocalState& s, const VecT<T>& x, const VecT<T>& props) const;
  Quantity length_;  ///< [m]
};

/// Fixed node: Phi = x - x_fix (dim rows), for free nodes held in place.
class FixedNodeConstraint : public KernelConstraint<FixedNodeConstraint> {
 public:
  FixedNodeConstraint(std::string name, int node, VecX position)
      : KernelConstraint(std::move(name), {node}), position_(std::move(position)) {}
  std::string kind() const override { return "fixed"; }
  int rows() const override { return static_cast<int>(position_.size()); }
  void jacobian(const LocalState& s, MatX& J) const override {
    J = MatX::Identity(s.x.size(), s.x.size());
  }
  void hessian(const LocalState& s, int, MatX& H) const override {
    H.setZero(s.x.size(), s.x.size());
  }
  bool constantHessian() const override { return true; }
  bool parameterDerivative(const LocalState&, int, VecX&, MatX&) const override { return false; }
  std::vector<std::pair<std::string, Quantity*>> properties() override { return {}; }

 private:
  friend class KernelConstraint<FixedNodeConstraint>;
  /// No properties: never depends on a parameter (the fixed position is a constant).
  std::vector<const Quantity*> kernelProperties() const { return {}; }
  /// Value template (no properties: props is empty).
  template <class T>
  VecT<T> phiT(const LocalState& s, const VecT<T>& x, const VecT<T>& props) const;
  VecX position_;  ///< [m]
};

// Instantiated once, in the .cpp (its kernel templates are not visible elsewhere).
extern template class KernelConstraint<DistanceConstraint>;
extern template class KernelConstraint<FixedNodeConstraint>;

}  // namespace flexsens
