// A point torque on one ANCF node, applied through its position-gradient coordinates
// (`point_torque` with `node:`): the couple work-conjugate to the rotation of the node's
// cross-section, which an ANCF node carries in its slope r' (ancf_cable) or its gradients
// r_x, r_y, r_z (ancf_beam). The nodal torque formulas of PlanarTorque and SpatialTorque depend
// on their nodes only through the differences d = x_B - x_A (and x_C - x_A); here the inner
// torque sees the gradients as those differences (A at the origin, B at r' or r_x, C at r_y):
//   planar cable      Q_r' = tau f R90 r' / |r'|^2           (tau delta(atan2 r'_y, r'_x))
//   spatial cable     Q_r' = f T x r' / |r'|^2               (T perpendicular to r'_0)
//   ancf_beam         on the section vectors r_y, r_z (the cross-section's displacement field
//                     r + y r_y + z r_z; the slope r_x may differ from the section's normal by
//                     the shear): Q_ry = T1 x r_y / |r_y|^2, Q_rz = T2 x r_z / |r_z|^2, Q_rx = 0
//                     (the three-node split of SpatialTorque, d1 = r_y, d2 = r_z), so that
//                     Q . delta r = T . delta phi for any rotation of the section; the bending
//                     stress -M y / I of a moment M about z gives the same Q_ry = -M e_x;
//                     follower: T turns with the section.
// No force on the position (a pure couple); the inner torque's force on A, which would
// balance it, is dropped. Derivatives (analytic and AD) are the inner torque's, gathered on the
// gradient rows and columns. Units: tau, T [N m]; gradients [-]; Q_r [N m] per unit gradient.
#pragma once

#include <memory>

#include "core/Element.hpp"

namespace flexsens {

class GradientTorque : public Element {
 public:
  /// `inner`: a PlanarTorque (2 nodes) or SpatialTorque (2 nodes for a cable's slope, 3 for an
  /// ancf_beam's r_x, r_y) built on the node's gradients; `gradients`: 1 or 3.
  GradientTorque(std::string name, int node, int gradients, std::unique_ptr<Element> inner);
  std::string kind() const override { return "point_torque"; }
  int gradients() const override { return gradients_; }
  bool isLoad() const override { return true; }
  bool externalWork() const override { return true; }
  bool velocityDependent() const override { return false; }
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  void forceJacobianAD(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState&) const override { return 0.0; }
  std::vector<std::pair<std::string, Quantity*>> properties() override { return inner_->properties(); }

 private:
  /// The inner torque's local state: A at the origin, then the used gradients.
  LocalState innerState(const LocalState& s) const;
  /// Inner local vector -> this element's (position rows zero, unused gradients zero).
  VecX outerVector(const LocalState& s, const VecX& inner) const;
  MatX outerMatrix(const LocalState& s, const MatX& inner) const;
  int gradients_;
  int used_;       ///< gradients the inner torque acts on: 1 (a cable's r') or 2 (r_y, r_z)
  int first_ = 0;  ///< the first of them: 0 (r') or 1 (r_y)
  std::unique_ptr<Element> inner_;
};

}  // namespace flexsens
