// Follower point force on a 3D body (`point_force` with `follower: true` in a spatial scene):
// the force turns with the body through three of its nodes A, B, C. Given F0 [N] in global
// components at t = 0, d1 = x_B - x_A, d2 = x_C - x_A, n = d1 x d2,
//   F(q, t) = f(t) (a1 d1 + a2 d2 + a3 n),  a = [d1_0, d2_0, n_0]^-1 F0
// (elements/BodyTriad.hpp): F0 rotated by the body's rotation when A, B, C move rigidly.
// Applied at node P (any node of the body, A, B or C included). dQ/dq is nonzero:
//   dF/dd1 = f (a1 I - a3 [d2]x),  dF/dd2 = f (a2 I + a3 [d1]x),
// analytic (forceJacobian) and by AD of the value template (forceJacobianAD). Q is linear in
// F0 and f: dQ/dp is Q of a unit component (or of df/dp_k). A load (static load factor) with
// no potential: the energy audit counts its work as external work (power = v . Q).
//
// Units: F0 [N]; f [-]; positions [m].
#pragma once

#include <memory>

#include "core/TimeFunction.hpp"
#include "elements/KernelElement.hpp"

namespace flexsens {

class SpatialFollowerForce : public KernelElement<SpatialFollowerForce> {
 public:
  /// Nodes: P (where the force acts), then the body's A, B, C; X0: the initial positions of
  /// A, B, C (3 x 3 columns). Throws std::invalid_argument if they are collinear.
  SpatialFollowerForce(std::string name, int p, int a, int b, int c, const Eigen::Matrix3d& X0,
                       std::vector<Quantity> F0, std::unique_ptr<TimeFunction> f = nullptr);
  std::string kind() const override { return "point_force"; }
  bool isLoad() const override { return true; }
  bool externalWork() const override { return true; }
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  bool parameterDerivativeAD(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState&) const override { return 0.0; }
  /// "x", "y", "z" (the components of F0), then the function's constants.
  std::vector<std::pair<std::string, Quantity*>> properties() override;

 private:
  friend class KernelElement<SpatialFollowerForce>;
  void checkDim(const LocalState& s) const;
  std::vector<const Quantity*> kernelProperties() const;
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  /// Q (12: P, A, B, C) for the components F0 = c at time factor fac.
  template <class T>
  VecT<T> load(const VecT<T>& x, const VecT<T>& c, double fac) const;
  VecX componentValues(const LocalState& s) const;
  double factor(const LocalState& s) const { return f_ ? f_->at(s.t, *s.p).f : 1.0; }
  std::vector<Quantity> F0_;  ///< [N]
  std::unique_ptr<TimeFunction> f_;
  Eigen::Matrix3d Einv0_;  ///< [d1_0, d2_0, n_0]^-1
};

}  // namespace flexsens
