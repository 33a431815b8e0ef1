// Point force on one node: Q = F f(t), independent of q and v, so dQ/dq = 0 and dQ/dv = 0.
// Each component is a Quantity, so any of them may be a design parameter (for instance a tip
// load that a static solver steps through p); so are the constants of the optional time
// function f (core/TimeFunction.hpp; without one, f = 1: a dead load).
//
// Units: force components [N]; f [-]; positions [m]; potential energy U = -F . x [J] for a
// dead load; a load varying in time has none (it does external work: externalWork()).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include <memory>

#include "core/TimeFunction.hpp"
#include "elements/KernelElement.hpp"

namespace flexsens {

class PointForce : public KernelElement<PointForce> {
 public:
  /// components: dim entries [N] (2 planar, 3 spatial), in the order of the node's coordinates.
  PointForce(std::string name, int node, std::vector<Quantity> components,
             std::unique_ptr<TimeFunction> f = nullptr);
  std::string kind() const override { return "point_force"; }
  bool isLoad() const override { return true; }
  bool externalWork() const override { return f_ != nullptr; }
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return false; }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  bool parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  /// "x", "y", "z" by component index 0, 1, 2 (the node's coordinate order).
  std::vector<std::pair<std::string, Quantity*>> properties() override;
  int components() const { return static_cast<int>(F_.size()); }

 private:
  friend class KernelElement<PointForce>;
  void checkDim(const LocalState& s) const;
  /// Properties the kernel reads, in the order of its props vector: the components.
  std::vector<const Quantity*> kernelProperties() const;
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  double factor(const LocalState& s) const { return f_ ? f_->at(s.t, *s.p).f : 1.0; }
  std::vector<Quantity> F_;  ///< [N]
  std::unique_ptr<TimeFunction> f_;  ///< null: constant
};

}  // namespace flexsens
