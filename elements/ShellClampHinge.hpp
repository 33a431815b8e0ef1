// Bending term of a clamped boundary edge of a discrete shell (elements/ShellMesh.hpp): 3
// nodes in 3D, positions only, massless. Nodes: x0, x1 the boundary edge (both fixed by the
// clamp), x2 the third node of its one triangle.
//
// Derivation (a ghost triangle): a clamp makes the slope across the edge zero, so w extends
// evenly beyond it, w(-n) = w(n) (n the distance from the edge). The ghost triangle is then the
// mirror image of the real one across the wall plane (through the edge, normal to the rest
// triangle) and moves as that image: when the triangle turns about the edge by phi from its rest
// orientation, the interior hinge between it and its ghost (ShellHinge.hpp) folds by 2 phi, with
// the weight |e|^2 / (A + A). That hinge stands for a strip straddling the edge, half of it in
// the plate, so the clamp carries half its energy:
//   U = 1/2 D/2 |e|^2 / (2 A) (2 phi)^2 = D/2 |e|^2 / A phi^2  [J],
// D = E t^3 / (12 (1 - nu^2)), |e| and A the rest edge and triangle area. Calibration: under
// the clamped cylinder w = kappa n^2 / 2 the triangle tilts by phi = atan(kappa d / 2), d = 2 A /
// |e| its height, so U = D/2 kappa^2 A (1 + O(kappa^2 d^2)): Kirchhoff's D/2 kappa^2 on the
// strip from the edge to half the height, the half strip of an interior hinge parallel to it
// (on rows of equilateral triangles exactly half a row's hinge energy;
// tests/test_shell_clamp.cpp checks it on a mesh).
// phi is computed without moving a ghost: as the dihedral angle (ShellHinge::dihedralAngle)
// between the triangle and a fixed rest ghost X3, the rest X2 reflected across the rest edge
// line, which is the rotation about the edge from the rest orientation whenever the edge nodes
// stay where they were (as a clamp's do). phi is wrapped to (-pi, pi]. The rest orientation
// is the mesh triangle's (also under rest_shape: flat). Units: positions [m], D [N m], forces
// [N], energy [J].
//
// Symmetry plane (a shell's `symmetry` key; the plane through `point` with unit normal n):
// the ghost is the mirror image of x2 across that plane, moving with it,
//   x3 = x2 - 2 n (n . (x2 - point)),
// the edge nodes held on the plane (their normal displacement: SupportConstraint). The hinge
// between the triangle and its mirror image is the interior hinge the full (mirrored) shell
// has there, shared by the two halves: this half carries half its energy,
//   U = 1/2 (D/2 |e|^2 / (2 A)) (theta - theta0)^2 = 1/2 D (|e|^2 / (4 A)) (theta - theta0)^2,
// theta the dihedral angle between the triangle and its mirror (theta0 at rest). Its
// derivatives are the 4-node angle's through the map x -> (x, x3(x2)). A plane of symmetry
// through a smooth shell thus holds the slope across it at its rest value, as the mirrored
// model would.
#pragma once

#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "elements/KernelElement.hpp"
#include "elements/ShellProperties.hpp"

namespace flexsens {

class ShellClampHinge : public KernelElement<ShellClampHinge> {
 public:
  /// restX: rest positions of x0, x1 (the clamped edge) and x2 (9 entries [m]). Throws
  /// std::invalid_argument for a zero rest edge or triangle.
  ShellClampHinge(std::string name, std::vector<int> nodes, std::shared_ptr<ShellProperties> props, const VecX& restX);
  /// The hinge of a symmetry plane through `point` with unit `normal` (above); x0, x1 on it.
  ShellClampHinge(std::string name, std::vector<int> nodes, std::shared_ptr<ShellProperties> props, const VecX& restX,
                  const Eigen::Vector3d& normal, const Eigen::Vector3d& point);
  std::string kind() const override { return mirror_ ? "shell_symmetry" : "shell_clamp"; }
  /// Q and its Jacobians in fixed size (no heap); kernelForce() and the AD Jacobians evaluate
  /// the value template forceT instead.
  void force(const LocalState& s, VecX& Q) const override;
  void forceJacobian(const LocalState& s, MatX& dQdq, MatX& dQdv) const override;
  bool velocityDependent() const override { return props_->bendingDamped(); }
  bool parameterDerivative(const LocalState& s, int k, VecX& dQ, MatX& dM) const override;
  double potential(const LocalState& s) const override;
  std::vector<std::pair<std::string, Quantity*>> properties() override { return props_->properties(); }

  double weight() const { return w_; }  ///< |e|^2 / A (clamp) or |e|^2 / (4 A) (symmetry) [-]
  /// phi at positions x (9 entries), relative to the rest orientation, wrapped to (-pi, pi] [rad].
  double rotation(const VecX& x) const;

 private:
  friend class KernelElement<ShellClampHinge>;
  void checkDim(const LocalState& s) const;
  /// x (9) and the ghost: the 12 positions of ShellHinge::dihedralAngle.
  Eigen::Matrix<double, 12, 1> withGhost(const VecX& x) const;
  /// D w [N m], phi wrapped [rad], grad phi (9) and, when H is given, its Hessian at s.x.
  void bendingState(const LocalState& s, double& Dw, double& dev, Eigen::Matrix<double, 9, 1>& g,
                    Eigen::Matrix<double, 9, 9>* H) const;
  std::vector<const Quantity*> kernelProperties() const {
    return {&props_->E, &props_->nu, &props_->thickness, &props_->beta};
  }
  template <class T>
  VecT<T> forceT(const LocalState& s, const VecT<T>& x, const VecT<T>& v, const VecT<T>& props) const;

  std::shared_ptr<ShellProperties> props_;
  /// The ghost of x2: fixed (clamp) or its mirror image across the plane (symmetry).
  template <class T>
  Eigen::Matrix<T, 3, 1> ghostOf(const Eigen::Matrix<T, 3, 1>& x2) const {
    if (!mirror_) return ghost_.cast<T>() + x2 * 0.0;
    return x2 - (2.0 * normal_.cast<T>().dot(x2 - point_.cast<T>())) * normal_.cast<T>();
  }
  Eigen::Vector3d ghost_;  ///< X3, fixed [m] (clamp)
  bool mirror_ = false;
  Eigen::Vector3d normal_ = Eigen::Vector3d::Zero(), point_ = Eigen::Vector3d::Zero();  ///< symmetry plane
  double phi0_, w_;        ///< the rest angle (round-off: the ghost lies in the rest plane) [rad], |e|^2 / A
};

}  // namespace flexsens
