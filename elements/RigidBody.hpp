// 3D rigid body in natural coordinates: four non-coplanar basic points A, B, C, D carry the
// coordinates; every material point is r = r_A + sum_j c_j (r_j - r_A) with constant body
// coordinates c, i.e. r = sum_k N_k(c) r_k with N = (1 - c1 - c2 - c3, c1, c2, c3). Hence
// the kinetic energy is 1/2 q'^T M q' with the CONSTANT mass matrix
//   M = (T J T^T) (x) I_3,  J = int [1; c][1; c]^T dm = [[m, m c_G^T], [m c_G, int c c^T dm]],
// built once from the mass, the centre of mass and the inertia tensor (about the centre of
// mass, global axes, at t = 0). Gravity is Q = (int N dm) (x) g. Rigidity (6 distances among
// the basic points, linear constraints for attached points) comes from pim/Rigidization, the
// generator the PIM uses; this element carries only inertia and weight.
//
// Units: mass [kg], inertia [kg m^2], positions [m], forces [N].
#pragma once

#include <array>

#include "elements/KernelElement.hpp"

namespace flexsens {

class RigidBody : public KernelElement<RigidBody> {
 public:
  /// basic: the four basic point node indices; X0: their initial positions (3 x 4 columns);
  /// com: centre of mass at t = 0 [m]; inertia: (Ixx, Iyy, Izz, Ixy, Ixz, Iyz), the tensor
  /// entries about the centre of mass in global axes at t = 0 (Ixy = -int x y dm).
  /// Throws std::invalid_argument if the basic points are (nearly) coplanar.
  RigidBody(std::string name, std::vector<int> basic, const Eigen::Matrix<double, 3, 4>& X0,
            Quantity mass, const Eigen::Vector3d& com, const std::array<Quantity, 6>& inertia);
  std::string kind() const override { return "rigid_body"; }
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return false; }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override;

  /// Second moments int rho rho^T dm about the centre of mass = 1/2 tr(I) Id - I [kg m^2];
  /// physical bodies have it positive semi-definite (the triangle inequalities of I).
  static Eigen::Matrix3d secondMoments(const Eigen::Matrix3d& I);

 private:
  friend class KernelElement<RigidBody>;
  /// Properties the kernels read, in the order of their props vector: (m, Ixx..Iyz).
  std::vector<const Quantity*> kernelProperties() const;
  static constexpr bool hasMassKernel = true;
  template <class T>
  MatT<T> massT(const LocalState& s, const VecT<T>& props) const;
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;
  Quantity mass_;
  std::array<Quantity, 6> inertia_;
  Eigen::Matrix3d Einv0_;  ///< inverse of the initial basis [r_B - r_A, r_C - r_A, r_D - r_A]
  Eigen::Vector3d cG_;     ///< body coordinates of the centre of mass
  Eigen::Vector3d dG_;     ///< r_G - r_A at t = 0 [m]
};

}  // namespace flexsens
