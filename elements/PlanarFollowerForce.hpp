// Follower point force on a planar body (`point_force` with `follower: true`): the force turns
// with the body through nodes A, B. Given F0 [N] in global components at t = 0 and d = x_B - x_A,
//   F(q, t) = f(t) (alpha d + beta R d),  alpha = F0 . d0 / |d0|^2,  beta = F0 . R d0 / |d0|^2,
// R the +90 degree rotation: F0 rotated by the body's rotation (|d| = |d0| on a rigid body), and
// linear in q, so dQ/dq is the constant f (alpha I + beta R) on d. Applied at node P (any node
// of the body, A or B included). No potential: the energy audit counts it as external work.
//
// Units: F0 [N]; f [-]; positions [m].
#pragma once

#include <memory>

#include "core/Element.hpp"
#include "core/TimeFunction.hpp"

namespace flexsens {

class PlanarFollowerForce : public Element {
 public:
  /// Nodes: P (where the force acts), A, B (the body's direction); d0 = x_B - x_A at t = 0.
  PlanarFollowerForce(std::string name, int p, int a, int b, const VecX& d0, std::vector<Quantity> F0,
                      std::unique_ptr<TimeFunction> f = nullptr);
  std::string kind() const override { return "point_force"; }
  bool isLoad() const override { return true; }
  bool externalWork() const override { return true; }
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  // Analytic in both derivative modes (linear in q: no value template needed).
  void forceJacobianAD(const LocalState& s, MatX& dQdq, MatX& dQdv) const override { forceJacobian(s, dQdq, dQdv); }
  bool parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const override {
    return parameterDerivative(s, k, dQ, dM);
  }
  double potential(const LocalState&) const override { return 0.0; }
  std::vector<std::pair<std::string, Quantity*>> properties() override;

 private:
  /// Q (6: P, A, B) for the force components F0 = c at time factor fac.
  VecX forceFor(const LocalState& s, const Eigen::Vector2d& c, double fac) const;
  double factor(const LocalState& s) const { return f_ ? f_->at(s.t, *s.p).f : 1.0; }
  Eigen::Vector2d d0_;
  std::vector<Quantity> F0_;  ///< [N]
  std::unique_ptr<TimeFunction> f_;
};

}  // namespace flexsens
