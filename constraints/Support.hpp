// A support of one node in chosen directions (`support` and `symmetry` of a meshed body):
// Phi = N (x - x0) = 0, N a k x dim matrix of unit rows (the fixed axes, or a symmetry plane's
// normal), x0 the node's initial position. Linear in q: constant Jacobian N, zero Hessian, no
// parameter. Through the constraint path like every joint, so its reactions are multipliers.
// Units: positions [m]; Phi [m].
#pragma once

#include "core/Element.hpp"

namespace flexsens {

class SupportConstraint : public Constraint {
 public:
  SupportConstraint(std::string name, int node, MatX directions, VecX x0)
      : Constraint(std::move(name), {node}), N_(std::move(directions)), x0_(std::move(x0)) {}
  std::string kind() const override { return "support"; }
  int rows() const override { return static_cast<int>(N_.rows()); }
  void phi(const LocalState& s, VecX& out) const override { out = N_ * (s.x - x0_); }
  void jacobian(const LocalState&, MatX& J) const override { J = N_; }
  void hessian(const LocalState&, int, MatX& H) const override { H.setZero(N_.cols(), N_.cols()); }
  bool constantHessian() const override { return true; }
  bool parameterDerivative(const LocalState&, int, VecX&, MatX&) const override { return false; }
  void jacobianAD(const LocalState& s, MatX& J) const override { jacobian(s, J); }
  void hessianAD(const LocalState& s, int r, MatX& H) const override { hessian(s, r, H); }
  bool parameterDerivativeAD(const LocalState&, int, VecX&, MatX&) const override { return false; }
  std::vector<std::pair<std::string, Quantity*>> properties() override { return {}; }

 private:
  MatX N_;   ///< k x dim, unit rows
  VecX x0_;  ///< [m]
};

}  // namespace flexsens
