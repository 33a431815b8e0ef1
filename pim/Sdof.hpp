// Sensitivity degrees of freedom z(q) of a PIM case (paper eq. 7): scalar functions of the
// coordinates whose parameter derivatives z_p0, z'_p0 the user prescribes.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/Model.hpp"

namespace flexsens {

class Sdof {
 public:
  virtual ~Sdof() = default;
  std::string name;
  double dp = 0.0;  ///< prescribed dz/dp at t = 0
  double dv = 0.0;  ///< prescribed dz'/dp at t = 0
  virtual double value(const Model& m, const VecX& q) const = 0;
  virtual VecX gradient(const Model& m, const VecX& q) const = 0;   ///< z_q (n)
  virtual MatX hessian(const Model& m, const VecX& q) const = 0;    ///< z_qq (n x n)
};

/// A linear combination sum_j coef_j q[dof_j] (a single node coordinate is the simplest).
class LinearSdof : public Sdof {
 public:
  struct Term { int node, component; double coef; };
  std::vector<Term> terms;
  double value(const Model& m, const VecX& q) const override;
  VecX gradient(const Model& m, const VecX& q) const override;
  MatX hessian(const Model& m, const VecX& q) const override;
};

/// Planar angle of the segment a -> b to the first axis: atan2(r_b2 - r_a2, r_b1 - r_a1) [rad].
class AngleSdof : public Sdof {
 public:
  int a = -1, b = -1;
  double value(const Model& m, const VecX& q) const override;
  VecX gradient(const Model& m, const VecX& q) const override;
  MatX hessian(const Model& m, const VecX& q) const override;
};

// SDOFs of a 3D rigid body in natural coordinates (elements/RigidBody.hpp), in pim/BodySdof.cpp:
// its centre of mass (a fixed linear combination of the four basic points) and its orientation.

/// r_G[component] = r_A + sum_j c_j (r_j - r_A) with c = E0^{-1} (com - X0_A),
/// E0 = [X0_B - X0_A, X0_C - X0_A, X0_D - X0_A]: a LinearSdof on the basic points.
std::unique_ptr<LinearSdof> centerOfMassSdof(const std::array<int, 4>& basic,
                                             const Eigen::Matrix<double, 3, 4>& X0,
                                             const Eigen::Vector3d& com, int component);

/// Tait-Bryan angle (z-y'-x'': yaw about z, pitch about y, roll about x) [rad] of
/// R = E E0^{-1}, E = [r_B - r_A, r_C - r_A, r_D - r_A] now and E0 at t = 0:
///   roll = atan2(R32, R33), pitch = -asin(R31), yaw = atan2(R21, R11)
/// (R is a rotation when the body's rigidity constraints hold; R = I and every angle is 0
/// at t = 0). Gradient and Hessian by nested forward AD over the 12 basic-point
/// coordinates, mapped to the global dofs (ground basic points contribute none).
class BodyRotationSdof : public Sdof {
 public:
  /// axis: 0 = x (roll), 1 = y (pitch), 2 = z (yaw).
  BodyRotationSdof(const std::array<int, 4>& basic, const Eigen::Matrix<double, 3, 4>& X0, int axis);
  double value(const Model& m, const VecX& q) const override;
  VecX gradient(const Model& m, const VecX& q) const override;
  MatX hessian(const Model& m, const VecX& q) const override;
  /// The angle from the basic points' coordinates x = (r_A, r_B, r_C, r_D).
  double angle(const VecX& x) const;

 private:
  template <class T>
  T angleT(const VecT<T>& x) const;
  VecX local(const Model& m, const VecX& q) const;
  std::array<int, 4> basic_;
  Eigen::Matrix3d Einv0_;
  int axis_;
};

}  // namespace flexsens
