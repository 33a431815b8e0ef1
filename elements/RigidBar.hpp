// Uniform slender rigid bar between two nodes in natural coordinates: the endpoints are the
// coordinates, so the mass matrix is constant, M = m/6 [[2I, I], [I, 2I]], and gravity puts
// half the weight on each end. Rigidity comes from a distance constraint the builder adds.
#pragma once

#include "elements/KernelElement.hpp"

namespace flexsens {

class RigidBar : public KernelElement<RigidBar> {
 public:
  RigidBar(std::string name, int a, int b, Quantity mass)
      : KernelElement(std::move(name), {a, b}), mass_(mass) {}
  std::string kind() const override { return "rigid_bar"; }
  /// forceT for double, into Q's storage (no property or result vector per call).
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return false; }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override {
    return {{"mass", &mass_}};
  }

 private:
  friend class KernelElement<RigidBar>;
  /// Properties the kernels read, in the order of their props vector: (mass).
  std::vector<const Quantity*> kernelProperties() const { return {&mass_}; }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  static constexpr bool hasMassKernel = true;
  template <class T>
  MatT<T> massT(const LocalState& s, const VecT<T>& props) const;
  Quantity mass_;  ///< [kg]
};

/// Massless linear spring-damper: tension f = k (l - L0) + c l', acting along the line of nodes.
class SpringDamper : public KernelElement<SpringDamper> {
 public:
  SpringDamper(std::string name, int a, int b, Quantity k, Quantity c, Quantity L0)
      : KernelElement(std::move(name), {a, b}), k_(k), c_(c), L0_(L0) {}
  std::string kind() const override { return "spring_damper"; }
  /// forceT for double, into Q's storage (no property or result vector per call).
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  /// A spring with damping 0 that no parameter can change has dQ/dv = 0.
  bool velocityDependent() const override { return c_.param >= 0 || c_.constant != 0.0; }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override {
    return {{"stiffness", &k_}, {"damping", &c_}, {"natural_length", &L0_}};
  }

 private:
  friend class KernelElement<SpringDamper>;
  struct Geometry;
  Geometry geometry(const LocalState& s) const;
  [[noreturn]] void coincidentNodes(double l) const;
  /// Properties the kernels read, in the order of their props vector: (k, c, L0).
  std::vector<const Quantity*> kernelProperties() const { return {&k_, &c_, &L0_}; }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  Quantity k_;   ///< [N/m]
  Quantity c_;   ///< [N s/m]
  Quantity L0_;  ///< natural length [m]
};

}  // namespace flexsens
