// General planar rigid body in natural coordinates: two basic points A, B are the coordinates;
// every material point is r = (1 - xi) r_A + xi r_B + eta R (r_B - r_A), R the +90 degree
// rotation, (xi, eta) fixed in the body. The mass matrix is then constant and needs only the
// mass, the centre of mass (xi_G, eta_G) and the polar moment of inertia, because
//   N^T N = [((1-xi)^2 + eta^2) I, ((1-xi) xi - eta^2) I + eta R; sym, (xi^2 + eta^2) I]:
//   M_AA = (m - 2 m xi_G + j) I, M_AB = (m xi_G - j) I + m eta_G R, M_BB = j I,
//   j = int (xi^2 + eta^2) dm = I_G / L^2 + m (xi_G^2 + eta_G^2), L = |r_B - r_A| at t = 0.
// A uniform bar (xi_G = 1/2, eta_G = 0, I_G = m L^2 / 12) gives the rigid bar's m/6 [[2, 1], [1, 2]].
// Gravity Q = M [g; g] (the body's weight at its centre of mass). The distance A-B and the
// attached points are constraints the scene reader adds.
//
// Units: mass [kg], inertia about the centre of mass [kg m^2], positions [m].
#pragma once

#include "elements/KernelElement.hpp"

namespace flexsens {

class PlanarRigidBody : public KernelElement<PlanarRigidBody> {
 public:
  /// xA, xB: basic points at t = 0 [m]; com: centre of mass at t = 0 [m].
  PlanarRigidBody(std::string name, int a, int b, const VecX& xA, const VecX& xB, const VecX& com,
                  Quantity mass, Quantity inertia);
  std::string kind() const override { return "planar_rigid_body"; }
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return false; }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override {
    return {{"mass", &mass_}, {"inertia", &inertia_}};
  }
  /// Body coordinates (xi, eta) of a point at position x at t = 0.
  static Eigen::Vector2d bodyCoordinates(const VecX& xA, const VecX& xB, const VecX& x);

 private:
  friend class KernelElement<PlanarRigidBody>;
  std::vector<const Quantity*> kernelProperties() const { return {&mass_, &inertia_}; }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  static constexpr bool hasMassKernel = true;
  template <class T>
  MatT<T> massT(const LocalState& s, const VecT<T>& props) const;
  Quantity mass_;     ///< [kg]
  Quantity inertia_;  ///< about the centre of mass [kg m^2]
  double xiG_, etaG_, L2_;  ///< centre of mass in body coordinates; |r_B - r_A|^2 at t = 0 [m^2]
};

}  // namespace flexsens
