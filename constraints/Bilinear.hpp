// Constraints that are the dot product of two vectors linear in the local coordinates:
//   Phi = (N x + a0) . (W x + b0) - c0,   N, W, a0, b0 constant (N, W: 3 x local dofs)
// so that Phi_q = x^T (N^T W + W^T N) and the Hessian N^T W + W^T N is constant (remark 4.1
// of the PIM paper: flexsens constraints are at most quadratic). Two uses:
//  - perpendicular (universal joint): (x_b - x_a) . (x_d - x_c) = c0 (0 for a cross);
//  - point on a plane fixed to a rigid body: n(q) . (x_P - o(q)) = 0, where the plane's
//    normal n = sum_j cn_j e_j and origin o = x_A + sum_j co_j e_j are fixed combinations of
//    the body's basic vectors e_j = x_Bj - x_A (so they move with the body), or constants
//    for a plane fixed in space.
#pragma once

#include <memory>

#include "constraints/KernelConstraint.hpp"

namespace flexsens {

class BilinearConstraint : public KernelConstraint<BilinearConstraint> {
 public:
  /// N, W: 3 x (local dofs: 3 nodes.size(), or 12 nodes.size() with the ancf_beam's
  /// `gradients` = 3); a0, b0: constant parts (space-fixed vectors) [m].
  BilinearConstraint(std::string name, std::string kind, std::vector<int> nodes, MatX N, Eigen::Vector3d a0,
                     MatX W, Eigen::Vector3d b0, double c0, int gradients = 0);
  int gradients() const override { return gradients_; }
  std::string kind() const override { return kind_; }
  int rows() const override { return 1; }
  void phi(const LocalState& s, VecX& out) const override;
  void jacobian(const LocalState& s, MatX& J) const override;
  void hessian(const LocalState&, int, MatX& H) const override { H = H_; }
  bool constantHessian() const override { return true; }
  bool parameterDerivative(const LocalState&, int, VecX&, MatX&) const override { return false; }
  std::vector<std::pair<std::string, Quantity*>> properties() override { return {}; }

  /// (x_b - x_a) . (x_d - x_c) = c0 on nodes (a, b, c, d).
  static std::unique_ptr<BilinearConstraint> perpendicular(std::string name, std::vector<int> nodes, double c0);
  /// x_P on the plane through `origin` with `normal` (at t = 0), fixed to the body whose
  /// basic points are X0 (3 x 4, nodes basic[0..3]); nodes = (basic..., P).
  static std::unique_ptr<BilinearConstraint> pointOnBodyPlane(std::string name, const std::vector<int>& basic,
                                                             const Eigen::Matrix<double, 3, 4>& X0, int point,
                                                             const Eigen::Vector3d& origin,
                                                             const Eigen::Vector3d& normal);
  /// x_P on a plane fixed in space: n . (x_P - origin) = 0.
  static std::unique_ptr<BilinearConstraint> pointOnFixedPlane(std::string name, int point,
                                                              const Eigen::Vector3d& origin,
                                                              const Eigen::Vector3d& normal);

 private:
  friend class KernelConstraint<BilinearConstraint>;
  /// No properties: the geometry is fixed at build time.
  std::vector<const Quantity*> kernelProperties() const { return {}; }
  template <class T>
  VecT<T> phiT(const LocalState& s, const VecT<T>& x, const VecT<T>& props) const;
  std::string kind_;
  MatX N_, W_;
  Eigen::Vector3d a0_, b0_;
  double c0_;
  MatX H_;
  int gradients_;
  /// N = [nc_0 I, nc_1 I, ...] and W likewise (3 x 3 blocks; every construction here): N x
  /// is then a combination of the local 3-vectors, 3x fewer products than the 3 x 15 one
  /// (the satellite's residual evaluates ~100 of these per Newton iteration). Empty: general
  /// N, W.
  VecX nc_, wc_;
  void factors(const VecX& x, Eigen::Vector3d& a, Eigen::Vector3d& b) const;  ///< N x + a0, W x + b0
};

// Instantiated once, in the .cpp (its kernel templates are not visible elsewhere).
extern template class KernelConstraint<BilinearConstraint>;

}  // namespace flexsens
