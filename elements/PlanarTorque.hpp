// Point torque on a planar body given by two of its nodes A, B (a planar rigid body's basic
// points, a rigid bar's ends): tau(t) = tau f(t) [N m], counter-clockwise. Its virtual work
// tau delta theta with theta = atan2(d_y, d_x), d = x_B - x_A, gives the nodal forces
//   Q_B = tau f R d / |d|^2,  Q_A = -Q_B,  R = [[0, -1], [1, 0]]
// (a couple: no net force), which depend on q: dQ_B/dd = tau f (R - 2 R d d^T / |d|^2) / |d|^2.
// It has no potential (theta is multi-valued): the energy audit counts it as external work.
//
// Units: tau [N m]; f [-]; positions [m].
#pragma once

#include <memory>

#include "core/TimeFunction.hpp"
#include "core/Element.hpp"

namespace flexsens {

class PlanarTorque : public Element {
 public:
  PlanarTorque(std::string name, int a, int b, Quantity torque, std::unique_ptr<TimeFunction> f = nullptr)
      : Element(std::move(name), {a, b}), tau_(torque), f_(std::move(f)) {}
  std::string kind() const override { return "point_torque"; }
  bool isLoad() const override { return true; }
  bool externalWork() const override { return true; }
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  // Analytic in both derivative modes (a closed form of two lines has no value template).
  void forceJacobianAD(const LocalState& s, MatX& dQdq, MatX& dQdv) const override { forceJacobian(s, dQdq, dQdv); }
  bool parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const override {
    return parameterDerivative(s, k, dQ, dM);
  }
  double potential(const LocalState&) const override { return 0.0; }
  std::vector<std::pair<std::string, Quantity*>> properties() override;

 private:
  /// Q for a unit torque (tau f = 1).
  static VecX unitForce(const VecX& x);
  double factor(const LocalState& s) const { return f_ ? f_->at(s.t, *s.p).f : 1.0; }
  Quantity tau_;  ///< [N m]
  std::unique_ptr<TimeFunction> f_;
};

}  // namespace flexsens
