// Point torque on a 3D body (`point_torque` in a spatial scene), through two or three of its
// nodes: T(t) = f(t) T0 [N m], T0 in global components (each bindable), applied as nodal
// forces with no net force and moment T, so that its power on any rigid motion of the nodes
// is T . omega.
//
// Three nodes A, B, C (not collinear): d1 = x_B - x_A, d2 = x_C - x_A, n = d1 x d2,
// w = d1 |d2|^2 - d2 (d1 . d2) (w . d2 = 0, w . d1 = |n|^2). Split T = T1 + T2 with
//   T2 = (T . d1 / |n|^2) w  (perpendicular to d2),  T1 = T - T2  (T1 . d1 = 0),
// and apply each part as a couple on its own edge:
//   f_B = T1 x d1 / |d1|^2,  f_C = T2 x d2 / |d2|^2,  f_A = -(f_B + f_C).
// Then d1 x f_B = T1 and d2 x f_C = T2 (a x (b x a) = b |a|^2 for b perpendicular to a), so
// sum r_k x f_k = T and sum f_k = 0.
// Two nodes A, B (a rigid bar, a positions-only beam's end segment): only the part of T
// perpendicular to d = x_B - x_A can act on them, f_B = T x d / |d|^2 = -f_A (moment
// T - d (T . d)/|d|^2). The scene reader rejects a T0 with a component along the initial
// A-B; a space-fixed T0 on a turning bar still loses its axial part later (it does no work
// on the bar).
// follower (three nodes only): T turns with the body, T(q) = f (a1 d1 + a2 d2 + a3 n) with
// a = [d1_0, d2_0, n_0]^-1 T0 (elements/BodyTriad.hpp): the rotated T0 on a rigid body.
//
// Loads, scaled by the static load factor; no potential (the energy audit counts their work
// as external work, power = v . Q). dQ/dq analytic (forceJacobian) and by AD of the value
// template (forceJacobianAD); Q is linear in T0 and in f, so dQ/dp is Q of a unit component
// (or of df/dp_k) at the same state.
//
// Units: T0 [N m]; f [-]; positions [m]; nodal forces [N].
#pragma once

#include <memory>

#include "core/TimeFunction.hpp"
#include "elements/KernelElement.hpp"

namespace flexsens {

class SpatialTorque : public KernelElement<SpatialTorque> {
 public:
  /// nodes: [A, B] or [A, B, C]; torque: T0 (3 components) [N m]; X0: the nodes' initial
  /// positions (3 x nodes), read for the follower's coefficients. Throws
  /// std::invalid_argument on a follower with two nodes or collinear A, B, C at t = 0.
  SpatialTorque(std::string name, std::vector<int> nodes, std::vector<Quantity> torque,
                std::unique_ptr<TimeFunction> f, bool follower, const MatX& X0);
  std::string kind() const override { return "point_torque"; }
  bool isLoad() const override { return true; }
  bool externalWork() const override { return true; }
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  bool parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState&) const override { return 0.0; }
  /// "x", "y", "z" (the components of T0), then the function's constants.
  std::vector<std::pair<std::string, Quantity*>> properties() override;
  bool follower() const { return follower_; }

 private:
  friend class KernelElement<SpatialTorque>;
  void checkDim(const LocalState& s) const;
  std::vector<const Quantity*> kernelProperties() const;
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  /// Q for the components T0 = c at time factor fac.
  template <class T>
  VecT<T> load(const VecT<T>& x, const VecT<T>& c, double fac) const;
  VecX componentValues(const LocalState& s) const;
  double factor(const LocalState& s) const { return f_ ? f_->at(s.t, *s.p).f : 1.0; }
  std::vector<Quantity> T0_;  ///< [N m]
  std::unique_ptr<TimeFunction> f_;
  bool follower_;
  Eigen::Matrix3d Einv0_ = Eigen::Matrix3d::Zero();  ///< follower: [d1_0, d2_0, n_0]^-1
};

}  // namespace flexsens
